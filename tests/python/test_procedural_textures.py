"""Cycles' procedural textures (sphrect._native.procedural_texture) at their edges: closed forms they reduce to,
huge coordinates, determinism, and the binding's checks.  Their values against Cycles 3.4 are
tests/blender/test_procedural_textures.py's."""
import numpy as np
import pytest

from sphrect import _native

NODES = _native.procedural_textures
RNG = np.random.default_rng(7)
POINTS = RNG.uniform(-3, 3, (500, 3)).astype(np.float32)
W = RNG.uniform(-3, 3, 500).astype(np.float32)


def tex(node, points=POINTS, w=W, **params):
    return _native.procedural_texture(node, points, w, **params)


def test_every_node_is_exported():
    assert set(NODES) == {"noise", "musgrave", "voronoi", "white_noise", "gradient", "checker", "wave", "magic",
                          "brick"}


@pytest.mark.parametrize("dimensions", [1, 2, 3, 4])
def test_noise_detail_0_is_one_octave_of_musgrave_fbm(dimensions):
    """Detail 0 is one octave of unsigned noise, 0.5 snoise + 0.5; Musgrave fBM of detail 1 is that snoise."""
    noise = tex("noise", dimensions=dimensions, scale=2.5, detail=0.0)["fac"]
    fbm = tex("musgrave", dimensions=dimensions, type="fbm", scale=2.5, detail=1.0)["fac"]
    assert np.array_equal(noise, np.float32(0.5) * fbm + np.float32(0.5))
    assert noise.std() > 0.05


def test_noise_fraction_of_detail_blends_octaves():
    """A fractional detail lies between the integer details' results (the extra octave's weight is the fraction)."""
    lo, mid, hi = (tex("noise", detail=d)["fac"] for d in (2.0, 2.5, 3.0))
    assert np.all(np.minimum(lo, hi) - 1e-6 <= mid) and np.all(mid <= np.maximum(lo, hi) + 1e-6)
    assert not np.array_equal(lo, hi)


def test_noise_color_red_is_fac_and_distortion_moves_it():
    out = tex("noise", distortion=0.0)
    assert np.array_equal(out["color"][:, 0], out["fac"])
    assert np.abs(tex("noise", distortion=2.0)["fac"] - out["fac"]).max() > 0.05


@pytest.mark.parametrize("dimensions", [2, 3, 4])
def test_voronoi_without_randomness_is_the_integer_lattice(dimensions):
    """Randomness 0 puts each cell's point at its corner: F1 is the distance to the nearest lattice point, Position
    that point."""
    scale = 3.0
    out = tex("voronoi", dimensions=dimensions, randomness=0.0, scale=scale)
    q = np.concatenate([POINTS, W[:, None]], axis=1)[:, :dimensions].astype(np.float64) * scale
    nearest = np.round(q)
    assert np.allclose(out["distance"], np.linalg.norm(q - nearest, axis=1), atol=1e-5)
    position = np.concatenate([out["position"], out["w"][:, None]], axis=1)
    expected = nearest / scale
    assert np.allclose(position[:, :min(dimensions, 3)], expected[:, :3], atol=1e-5)
    if dimensions == 4:
        assert np.allclose(out["w"], expected[:, 3], atol=1e-5)


def test_voronoi_features_order_and_ranges():
    f1, f2 = (tex("voronoi", feature=f)["distance"] for f in ("f1", "f2"))
    smooth = tex("voronoi", feature="smooth_f1", smoothness=1.0)["distance"]
    assert np.all(f1 <= f2) and np.all(smooth <= f1 + 1e-6)
    edge = tex("voronoi", feature="distance_to_edge")["distance"]
    radius = tex("voronoi", feature="n_sphere_radius")["radius"]
    assert np.all(edge >= 0) and np.all(edge <= f2) and np.all(radius > 0) and np.all(radius < 1.5)


@pytest.mark.parametrize("metric", ["euclidean", "manhattan", "chebychev", "minkowski"])
def test_voronoi_metrics_order(metric):
    """Chebychev <= Euclidean <= Manhattan for the same cell point; Minkowski 1 is Manhattan, 2 Euclidean."""
    d = {m: tex("voronoi", metric=m, exponent=e)["distance"] for m, e in
         (("chebychev", 1.0), ("euclidean", 1.0), ("manhattan", 1.0), ("minkowski", 1.0))}
    assert np.all(d["chebychev"] <= d["euclidean"] + 1e-6) and np.all(d["euclidean"] <= d["manhattan"] + 1e-6)
    assert np.allclose(d["minkowski"], d["manhattan"], atol=1e-5)
    assert np.allclose(tex("voronoi", metric="minkowski", exponent=2.0)["distance"], d["euclidean"], atol=1e-5)


def test_checker_parity_and_gradient_closed_forms():
    """Checker (positive coordinates): colour 1 where the cells' integer coordinates sum to an odd number."""
    points = RNG.uniform(0.01, 4, (500, 3)).astype(np.float32)
    out = tex("checker", points, None, scale=1.7, color1=(1, 0, 0), color2=(0, 0, 1))
    cells = np.floor(points.astype(np.float64) * np.float32(1.7)).astype(int)
    odd = cells.sum(axis=1) % 2 == 1
    assert np.array_equal(out["fac"] == 1.0, odd)
    assert np.array_equal(out["color"][odd], np.tile([1, 0, 0], (odd.sum(), 1)))
    assert np.array_equal(tex("gradient", type="linear")["fac"], np.clip(POINTS[:, 0], 0, 1))
    spherical = tex("gradient", type="spherical")["fac"]
    assert np.allclose(spherical, np.maximum(0.999999 - np.linalg.norm(POINTS, axis=1), 0), atol=1e-6)


def test_white_noise_hashes_the_bits():
    """White noise of a point is its hash: the same point the same value, -0 and +0 different, in [0, 1]."""
    zero = np.zeros((1, 3), np.float32)
    plus, minus = (tex("white_noise", zero, np.array([s], np.float32), dimensions=1)["value"][0] for s in (0.0, -0.0))
    assert plus != minus
    v = tex("white_noise")
    assert v["value"].min() >= 0 and v["value"].max() <= 1 and 0.4 < v["value"].mean() < 0.6
    assert np.array_equal(v["color"][:, 0], v["value"])


def test_magic_depth_0_closed_form():
    out = tex("magic", depth=0, scale=1.0, distortion=0.0)
    p = np.fmod(POINTS, np.float32(2 * np.pi))
    s = 5.0
    expected = np.stack([0.5 - np.sin((p[:, 0] + p[:, 1] + p[:, 2]) * s),
                         0.5 - np.cos((-p[:, 0] + p[:, 1] - p[:, 2]) * s),
                         0.5 + np.cos((-p[:, 0] - p[:, 1] + p[:, 2]) * s)], axis=1)
    assert np.allclose(out["color"], expected, atol=1e-5)
    assert np.allclose(out["fac"], expected.mean(axis=1), atol=1e-5)


def test_brick_mortar_and_tints():
    out = tex("brick", mortar_smooth=0.0, mortar=(0, 0, 0), color1=(1, 1, 1), color2=(1, 1, 1))
    mortar = out["fac"] == 1.0
    assert 0.02 < mortar.mean() < 0.5
    assert np.all(out["color"][mortar] == 0) and np.allclose(out["color"][~mortar], 1, atol=1e-6)


SETTINGS = {"noise": {}, "musgrave": {"type": "hybrid_multifractal", "offset": 0.5, "gain": 2.0},
            "voronoi": {"feature": "smooth_f1"}, "white_noise": {}, "gradient": {"type": "radial"}, "checker": {},
            "wave": {"distortion": 3.0, "bands_direction": "diagonal"}, "magic": {"depth": 10}, "brick": {}}
# (Wave's rings are NaN beyond ~1e18 as in Cycles: the squared radius overflows a float, and sin(inf) is NaN.)


@pytest.mark.parametrize("node", NODES)
@pytest.mark.parametrize("magnitude", [1e6, 1e12, 1e30])
def test_huge_coordinates_stay_finite(node, magnitude):
    points = (RNG.uniform(-1, 1, (64, 3)) * magnitude).astype(np.float32)
    w = (RNG.uniform(-1, 1, 64) * magnitude).astype(np.float32)
    for dimensions in ([1, 2, 3, 4] if node in ("noise", "musgrave", "voronoi", "white_noise") else [None]):
        extra = {} if dimensions is None else {"dimensions": dimensions}
        for name, value in tex(node, points, w, **SETTINGS[node], **extra).items():
            assert np.isfinite(value).all(), (node, dimensions, name)


@pytest.mark.parametrize("node", NODES)
def test_deterministic_and_pointwise(node):
    """The same point gives the same bits, whether alone or in a batch."""
    a = tex(node, **SETTINGS[node])
    b = tex(node, **SETTINGS[node])
    single = _native.procedural_texture(node, POINTS[7:8], W[7:8], **SETTINGS[node])
    for name in a:
        assert np.array_equal(a[name], b[name])
        assert np.array_equal(a[name][7:8], single[name])


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="unknown procedural texture 'nois'"):
        tex("nois")
    with pytest.raises(ValueError, match="unknown voronoi setting 'roughness'.*'randomness'"):
        tex("voronoi", roughness=1.0)
    with pytest.raises(ValueError, match="unknown voronoi feature 'f3'.*'n_sphere_radius'"):
        tex("voronoi", feature="f3")
    with pytest.raises(ValueError, match=r"noise dimensions must be in \[1, 4\], got 5"):
        tex("noise", dimensions=5)
    with pytest.raises(ValueError, match="noise scale must be a number"):
        tex("noise", scale="big")
    with pytest.raises(ValueError, match="magic depth must be in"):
        tex("magic", depth=11)
    with pytest.raises(ValueError, match="checker color1 must be three numbers"):
        tex("checker", color1=(1, 0))
    with pytest.raises(ValueError, match=r"points must have shape \(N, 3\)"):
        tex("noise", POINTS[:, :2])
    with pytest.raises(ValueError, match=r"w must have shape \(500,\)"):
        tex("noise", POINTS, W[:10])
