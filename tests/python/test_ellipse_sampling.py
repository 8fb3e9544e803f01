"""Ellipse (disk) lights through the bindings: the `spherical_ellipse` map and `area` sampling
against their own pdfs (chi2.py's ellipse_chi2_test: the project's one chi-square harness), the
map's Jacobian, its inverse, irradiance from a disk against the closed form, the solid angle
against an mpmath reference, hard configurations, the area-fallback switch, and the API's
contract."""
import math

import mpmath
import numpy as np
import pytest

import sphrect
from chi2 import EllipseConfig, ellipse_chi2_test

DTYPES = ("float32", "float64")
TECHNIQUES = ("area", "spherical_ellipse")

# The light lies in z = 0 centred at the world origin (float32 points on it stay precise); its
# normal cross(axis_u, axis_v) is +z.
DISK = dict(center=(0.0, 0.0, 0.0), axis_u=(1.0, 0.0, 0.0), axis_v=(0.0, 1.0, 0.0))
ELLIPSE = dict(center=(0.0, 0.0, 0.0), axis_u=(1.0, 0.0, 0.0), axis_v=(0.0, 0.4, 0.0))
_S2 = math.sqrt(0.5)
ROTATED = dict(center=(0.3, -0.2, 0.1), axis_u=(0.6 * _S2, 0.6 * _S2, 0.0), axis_v=(0.0, 0.0, 0.9))
THIN = dict(center=(0.0, 0.0, 0.0), axis_u=(1.0, 0.0, 0.0), axis_v=(0.0, 1e-3, 0.0))
ORDINARY = [
    EllipseConfig("disk-above", origin=(0.2, 0.1, 1.0), **DISK),
    EllipseConfig("ellipse-beside", origin=(1.8, 0.3, 0.4), **ELLIPSE),
    EllipseConfig("rotated", origin=(-1.0, 0.5, 0.7), **ROTATED),
    EllipseConfig("below-two-sided", origin=(0.3, -0.2, -0.6), **ELLIPSE),
]
HARD = [
    EllipseConfig("interior-h1e-3", origin=(0.3, 0.1, 1e-3), **ELLIPSE),
    EllipseConfig("rim-h1e-3", origin=(1.0, 0.0, 1e-3), **ELLIPSE),
    EllipseConfig("grazing-beside-h1e-4", origin=(2.0, 0.3, 1e-4), **ELLIPSE),
    EllipseConfig("far-d1e4", origin=(0.3, 0.1, 1e4), **ELLIPSE),
    EllipseConfig("thin-aspect1e3", origin=(0.3, 0.1, 0.3), **THIN),
]
CONFIGS = ORDINARY + HARD


def _args(c):
    return (c.origin, c.center, c.axis_u, c.axis_v)


def _uv_grid(n):
    g = np.linspace(0.0, 1.0, n)
    g[-1] = np.nextafter(np.float32(1.0), np.float32(0.0))   # 1-: the largest float32 below 1
    u, v = np.meshgrid(np.concatenate([g, [1.0]]), np.concatenate([g, [1.0]]), indexing="ij")
    return np.stack([u.ravel(), v.ravel()], axis=1)


def _disk_coordinates(c, points):
    """(p, q): offsets from the centre in semi-axes, and the distance from the light's plane."""
    _, center, au, av = (np.asarray(x, float) for x in _args(c))
    rel = points.astype(float) - center
    n = np.cross(au, av)
    return rel @ au / au.dot(au), rel @ av / av.dot(av), np.abs(rel @ (n / np.linalg.norm(n)))


# ---------------------------------------------------------------------------------------------
# Each technique against its own pdf.  False failures: the seeds are fixed (reproducible); every
# test runs at a Sidak-corrected level such that a correct implementation fails one of the
# CHI2_TESTS with probability 1e-3.
CHI2_CASES = [(t, c, d) for c in CONFIGS for t, d in
              [("spherical_ellipse", "float32"), ("spherical_ellipse", "float64")]] + \
             [("area", c, "float32") for c in (ORDINARY[1], HARD[0])]
CHI2_TESTS = len(CHI2_CASES) + 1


@pytest.mark.slow
@pytest.mark.parametrize("technique, config, dtype", CHI2_CASES, ids=lambda x: str(x))
def test_chi2_technique_matches_its_pdf(technique, config, dtype):
    r = ellipse_chi2_test(technique, config, dtype=dtype, sample_count=200_000, significance=1e-3,
                          test_count=CHI2_TESTS)
    assert r.passed, str(r)
    assert abs(r.total_probability - 1) < 1e-3, str(r)


def test_chi2_detects_the_wrong_technique():
    """The map is not area sampling: the same test, the map's samples against the area pdf."""
    r = ellipse_chi2_test("spherical_ellipse", ORDINARY[0], against="area", sample_count=200_000)
    assert not r.passed and r.p_value < 1e-12, str(r)


def test_uniform_in_solid_angle():
    for c in CONFIGS:
        omega = sphrect.ellipse_solid_angle(*_args(c), dtype="float64")
        for dtype in DTYPES:
            _, pdf = sphrect.sample_ellipse("spherical_ellipse", *_args(c), _uv_grid(9), dtype=dtype)
            np.testing.assert_allclose(pdf, 1 / omega, rtol=1e-6, err_msg=c.name)


# ---------------------------------------------------------------------------------------------
# The map: Jacobian and inverse.

def test_jacobian_is_the_solid_angle():
    """|dw/du x dw/dv| = Omega (central differences of the directions, double)."""
    rng = np.random.default_rng(4)
    uv = rng.uniform(0.02, 0.98, size=(200, 2))
    step = 1e-6
    for c in CONFIGS[:-2] + [CONFIGS[-1]]:   # (at 1e4 sizes the differences resolve 3 digits only)
        o = np.asarray(c.origin, float)

        def directions(q):
            p, _ = sphrect.sample_ellipse("spherical_ellipse", *_args(c), q, dtype="float64")
            d = p - o
            return d / np.linalg.norm(d, axis=1)[:, None]

        du = (directions(uv + [step, 0]) - directions(uv - [step, 0])) / (2 * step)
        dv = (directions(uv + [0, step]) - directions(uv - [0, step])) / (2 * step)
        jac = np.linalg.norm(np.cross(du, dv), axis=1)
        omega = sphrect.ellipse_solid_angle(*_args(c), dtype="float64")
        np.testing.assert_allclose(jac, omega, rtol=1e-4, err_msg=c.name)


@pytest.mark.parametrize("dtype", DTYPES)
def test_invert_round_trip(dtype):
    """invert(sample(uv)) = uv, small solid angles included.  (u = 0 and u = 1 are left out: the map
    sends each of those edges of the square to one point, an end of the minor axis; near them v
    is ill-conditioned (chords ~ u^(1/3) long), so u = 1e-6 and 1 - 1e-6 are checked in double only.)"""
    g = np.linspace(0, 1, 33)[1:-1]
    if dtype == "float64":
        g = np.concatenate([[1e-6], g, [1 - 1e-6]])
    u, v = np.meshgrid(g, np.linspace(0, 1, 33), indexing="ij")
    uv = np.stack([u.ravel(), v.ravel()], axis=1)
    for c in CONFIGS:
        points, pdf = sphrect.sample_ellipse("spherical_ellipse", *_args(c), uv, dtype=dtype)
        back = sphrect.invert_ellipse(*_args(c), points, dtype=dtype)
        assert back.shape == uv.shape and back.dtype == np.dtype(dtype)
        err = np.abs(back.astype(float) - uv).max(axis=1)
        assert err.max() <= 1e-4, f"{c.name}: max |uv - invert(sample(uv))| = {err.max():.3g} at {uv[err.argmax()]}"


# ---------------------------------------------------------------------------------------------
# Irradiance from a disk parallel to the receiver: E = pi L F with the classical form factor of a
# differential area to a coaxial-parallel disk of radius R at height H, offset rho from its axis,
#   F = (1 - (H^2 + rho^2 - R^2) / sqrt((H^2 + rho^2 + R^2)^2 - 4 rho^2 R^2)) / 2.
# Bound 4 standard errors: false-failure rate 6e-5 per check (normal approximation), 6 checks.

@pytest.mark.parametrize("technique", TECHNIQUES)
@pytest.mark.parametrize("rho", [0.0, 0.7, 2.5])
def test_disk_irradiance_closed_form(technique, rho):
    R, H = 1.0, 0.8
    F = 0.5 * (1 - (H * H + rho * rho - R * R) / math.sqrt((H * H + rho * rho + R * R) ** 2 - 4 * rho * rho * R * R))
    origin = np.array([rho, 0.0, -H])   # below the disk, facing it (two-sided light)
    uv = sphrect.pattern("independent", 200_000, seed=21)
    points, pdf = sphrect.sample_ellipse(technique, origin, *DISK.values(), uv, dtype="float64")
    d = points - origin
    cos = d[:, 2] / np.linalg.norm(d, axis=1)
    x = cos / pdf
    se = x.std(ddof=1) / math.sqrt(len(x))
    assert abs(x.mean() - math.pi * F) <= 4 * se + 1e-12, (x.mean(), math.pi * F, se)


# ---------------------------------------------------------------------------------------------
# Solid angle against a high-precision reference: mpmath (40 digits) integrating, about the foot
# of o, the solid angle of the ray segments through the ellipse, int (h / r_near - h / r_far) dphi.

def _reference_solid_angle(origin, center, axis_u, axis_v):
    mpmath.mp.dps = 40
    o, c, au, av = (mpmath.matrix([mpmath.mpf(float(x)) for x in v]) for v in (origin, center, axis_u, axis_v))
    a, b = mpmath.norm(au), mpmath.norm(av)
    uh, vh = au / a, av / b
    n = mpmath.matrix([uh[1] * vh[2] - uh[2] * vh[1], uh[2] * vh[0] - uh[0] * vh[2], uh[0] * vh[1] - uh[1] * vh[0]])
    d = o - c
    fx, fy = (d.T * uh)[0] / a, (d.T * vh)[0] / b   # the foot of o in semi-axes
    h = abs((d.T * n)[0])
    c0 = fx * fx + fy * fy - 1

    def radii(phi):   # the ray from the foot at angle phi (in the plane): entry and exit distances
        cs, sn = mpmath.cos(phi), mpmath.sin(phi)
        A2 = (cs / a) ** 2 + (sn / b) ** 2
        B1 = fx * cs / a + fy * sn / b
        disc = B1 * B1 - A2 * c0
        if disc < 0:
            return None
        s = mpmath.sqrt(disc)
        return (-B1 - s) / A2, (-B1 + s) / A2

    def through(phi):
        r = radii(phi)
        if r is None or r[1] <= 0:
            return mpmath.mpf(0)
        near = h / mpmath.sqrt(r[0] ** 2 + h * h) if c0 > 0 else mpmath.mpf(1)
        return near - h / mpmath.sqrt(r[1] ** 2 + h * h)

    if c0 < 0:
        return mpmath.quad(through, [0, mpmath.pi / 2, mpmath.pi, 3 * mpmath.pi / 2, 2 * mpmath.pi])
    # Beside: the rays between the two tangents, phi0 +- delta (in the frame scaled by the semi-axes).
    dist = mpmath.sqrt(fx * fx + fy * fy)
    mid = mpmath.atan2(-fy, -fx)
    delta = mpmath.asin(1 / dist)

    def scaled(t):   # the tangent directions in the scaled frame, back in the plane
        return mpmath.atan2(b * mpmath.sin(t), a * mpmath.cos(t))

    lo, hi = scaled(mid - delta), scaled(mid + delta)
    if hi < lo:
        hi += 2 * mpmath.pi
    return mpmath.quad(through, mpmath.linspace(lo, hi, 5))


def _solid_angle_configs():
    out = []
    for ratio in (1e-6, 1e-3, 1.0, 1e3, 1e6):            # distance / size
        out.append((f"distance {ratio:g}", (0.3 * ratio, 0.1 * ratio, ratio), ELLIPSE))
    for h in (1e-9, 1e-6, 1e-3, 1e-1):                    # heights above the interior, the rim, beside
        out.append((f"interior h={h:g}", (0.4, 0.1, h), ELLIPSE))
        out.append((f"rim h={h:g}", (1.0, 0.0, h), ELLIPSE))
        out.append((f"beside h={h:g}", (1.5, 0.2, h), ELLIPSE))
    for aspect in (1e2, 1e4):
        out.append((f"aspect {aspect:g}", (0.3, 0.0, 0.5), dict(center=(0.0, 0.0, 0.0), axis_u=(1.0, 0.0, 0.0),
                                                                axis_v=(0.0, 1.0 / aspect, 0.0))))
    out.append(("rotated", (-1.0, 0.5, 0.7), ROTATED))
    return out


@pytest.mark.slow
@pytest.mark.parametrize("dtype", DTYPES)
def test_solid_angle_matches_mpmath(dtype):
    """Within 1e-6 relative, for the inputs as the dtype holds them (the float32 path computes in
    double from the float32 inputs)."""
    np_dtype = np.dtype(dtype)
    for name, origin, light in _solid_angle_configs():
        args = [np.asarray(v, np_dtype) for v in (origin, light["center"], light["axis_u"], light["axis_v"])]
        got = sphrect.ellipse_solid_angle(*args, dtype=dtype)
        ref = float(_reference_solid_angle(*args))
        assert abs(got - ref) <= 1e-6 * ref, f"{name}: {got!r} vs {ref!r} (rel {abs(got - ref) / ref:.2g})"


def test_solid_angle_closed_form_of_a_disk_on_its_axis():
    # A disk of radius R seen from height H on its axis: 2 pi (1 - H / sqrt(H^2 + R^2)).
    for R, H in [(1.0, 1.0), (1.0, 1e-6), (1.0, 1e4), (3.0, 0.5)]:
        exact = 2 * math.pi * R * R / (H * H + R * R + H * math.sqrt(H * H + R * R))
        got = sphrect.ellipse_solid_angle((0, 0, H), (0, 0, 0), (R, 0, 0), (0, R, 0), dtype="float64")
        assert abs(got - exact) <= 1e-12 * exact


# ---------------------------------------------------------------------------------------------
# Hard cases: finite, on the light, pdf that of the returned point (float32).

def _hard_configs():
    out = []
    for ratio in (1e-6, 1e-3, 1.0, 1e3, 1e6):
        out.append(EllipseConfig(f"distance {ratio:g}", origin=(0.3 * ratio, 0.1 * ratio, ratio), **ELLIPSE))
    for h in (1e-9, 1e-6, 1e-3, 1e-1):
        out.append(EllipseConfig(f"interior h={h:g}", origin=(0.4, 0.1, h), **ELLIPSE))
        out.append(EllipseConfig(f"rim h={h:g}", origin=(1.0, 0.0, h), **ELLIPSE))
        out.append(EllipseConfig(f"beside h={h:g}", origin=(1.5, 0.2, h), **ELLIPSE))
    for aspect in (1e2, 1e4):
        out.append(EllipseConfig(f"aspect {aspect:g}", origin=(0.3, 0.0, 0.5), center=(0, 0, 0),
                                 axis_u=(1.0, 0, 0), axis_v=(0, 1.0 / aspect, 0)))
        out.append(EllipseConfig(f"aspect {aspect:g} beside", origin=(0.0, 2.0, 0.01), center=(0, 0, 0),
                                 axis_u=(1.0, 0, 0), axis_v=(0, 1.0 / aspect, 0)))
    out.append(EllipseConfig("rotated offset", origin=(-1.0, 0.5, 0.7), **ROTATED))
    out.append(EllipseConfig("rotated offset far", origin=(-1e3, 5e2, 7e2), **ROTATED))
    return out


@pytest.mark.parametrize("technique", TECHNIQUES)
def test_hard_cases_finite_on_the_light_with_their_pdf(technique):
    uv = _uv_grid(17)
    for c in _hard_configs():
        points, pdf = sphrect.sample_ellipse(technique, *_args(c), uv, dtype="float32")
        assert np.all(np.isfinite(points)) and np.all(np.isfinite(pdf)) and np.all(pdf > 0), c.name
        p, q, off = _disk_coordinates(c, points)
        assert np.all(p * p + q * q <= 1 + 1e-5), c.name
        assert np.all(off <= 1e-6 * np.linalg.norm(c.axis_u)), c.name
        again = sphrect.ellipse_pdf(technique, *_args(c), points, dtype="float32")
        np.testing.assert_array_equal(again, pdf, err_msg=c.name)
        back = sphrect.invert_ellipse(*_args(c), points, dtype="float32")
        assert np.all(np.isfinite(back)) and np.all((back >= 0) & (back <= 1)), c.name


# ---------------------------------------------------------------------------------------------
# The area fallback: beside a disk, nearly in its plane, the spherical ellipse gets too thin for the
# map ((15) of docs/ellipse_map.md) and sampling switches to area.  On both sides of the switch:
# unbiased (E[1/pdf] = Omega, within 4.5 standard errors: false-failure rate 7e-6 per check) and
# chi-square against its own pdf.

def _fallback_heights():
    """Heights just above and below the switch (found by bisection on whether pdf is uniform)."""
    def uniform(h):
        _, pdf = sphrect.sample_ellipse("spherical_ellipse", (2.0, 0.3, h), *DISK.values(), _uv_grid(5),
                                        dtype="float64")
        return np.ptp(pdf) == 0
    lo, hi = -12.0, -3.0   # log10 h: area fallback at 1e-12, the map at 1e-3
    assert not uniform(10 ** lo) and uniform(10 ** hi)
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if uniform(10 ** mid) else (mid, hi)
    return 10 ** lo / 2, 10 ** hi * 2


@pytest.mark.parametrize("side", [0, 1], ids=["area-fallback", "map"])
def test_fallback_switch_is_unbiased_on_both_sides(side):
    h = _fallback_heights()[side]
    c = EllipseConfig(f"beside h={h:.3g}", origin=(2.0, 0.3, h), **DISK)
    omega = sphrect.ellipse_solid_angle(*_args(c), dtype="float64")
    uv = sphrect.pattern("independent", 200_000, seed=17)
    points, pdf = sphrect.sample_ellipse("spherical_ellipse", *_args(c), uv, dtype="float64")
    assert (np.ptp(pdf) == 0) == (side == 1)
    x = 1 / pdf
    se = x.std(ddof=1) / math.sqrt(len(x))
    assert abs(x.mean() - omega) <= 4.5 * se + 1e-9 * omega, (x.mean(), omega, se)
    r = ellipse_chi2_test("spherical_ellipse", c, dtype="float64", sample_count=200_000, significance=1e-3,
                          test_count=2)
    assert r.passed, str(r)


# ---------------------------------------------------------------------------------------------
# The API's contract

ARGS = ((0.2, 0.3, 1.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.5, 0.0))
UV = np.array([[0.25, 0.5], [0.75, 0.125]])


def test_technique_names():
    assert sphrect.ellipse_techniques == ("area", "spherical_ellipse")


@pytest.mark.parametrize("call, message", [
    (lambda: sphrect.sample_ellipse("rectangle", *ARGS, UV),
     "unknown ellipse technique 'rectangle'; valid ellipse techniques: 'area', 'spherical_ellipse'"),
    (lambda: sphrect.ellipse_pdf("foo", *ARGS, np.zeros((1, 3))), "valid ellipse techniques"),
    (lambda: sphrect.sample_ellipse("area", ARGS[0], ARGS[1], (1, 0, 0), (1, 1, 0), UV), "must be orthogonal"),
    (lambda: sphrect.ellipse_solid_angle(ARGS[0], ARGS[1], (1, 0, 0), (0.1, 1, 0)), "must be orthogonal"),
    (lambda: sphrect.invert_ellipse(ARGS[0], ARGS[1], (1, 0, 0), (1, 1, 0), np.zeros((1, 3))), "must be orthogonal"),
    (lambda: sphrect.sample_ellipse("area", ARGS[0], ARGS[1], (0, 0, 0), ARGS[3], UV), "must be non-zero"),
    (lambda: sphrect.ellipse_solid_angle(ARGS[0], ARGS[1], ARGS[2], (0, 0, 0)), "must be non-zero"),
    (lambda: sphrect.sample_ellipse("area", (np.nan, 0, 1), *ARGS[1:], UV), "origin contains NaN or Inf"),
    (lambda: sphrect.sample_ellipse("area", *ARGS[:3], (0, np.inf, 0), UV), "axis_v contains NaN or Inf"),
    (lambda: sphrect.sample_ellipse("area", *ARGS, UV * 2), "uv must lie in [0, 1]"),
    (lambda: sphrect.sample_ellipse("area", np.zeros((3, 3)), *ARGS[1:], UV), "uv has 2 rows but origin has 3"),
    (lambda: sphrect.sample_ellipse("area", ARGS[0], np.zeros((2, 3)), *ARGS[2:], UV), "center must have shape (3,)"),
    (lambda: sphrect.ellipse_pdf("area", *ARGS, np.zeros((2, 2))), "points must have shape (N, 3)"),
    (lambda: sphrect.invert_ellipse(*ARGS, np.zeros(3)), "points must have shape (N, 3)"),
    (lambda: sphrect.sample_ellipse("area", *ARGS, UV, normal=(0, 0, 0)), "normal must be a non-zero"),
    (lambda: sphrect.ellipse_solid_angle((1e300, 0, 0), *ARGS[1:]), "overflows the requested dtype"),
    (lambda: sphrect.sample_ellipse("area", *ARGS, UV, dtype="int32"), "dtype must be 'float32' or 'float64'"),
])
def test_bad_input_raises_value_error(call, message):
    with pytest.raises(ValueError) as info:
        call()
    assert message in str(info.value)


def test_per_row_origins_dtypes_and_sidedness():
    rng = np.random.default_rng(1)
    origins = rng.uniform(-1, 2, size=(16, 3)) + [0, 0, 0.5]
    uv = sphrect.pattern("independent", 16, seed=1)
    for technique in TECHNIQUES:
        for dtype in DTYPES:
            points, pdf = sphrect.sample_ellipse(technique, origins, *ARGS[1:], uv, dtype=dtype)
            assert points.dtype == np.dtype(dtype) and pdf.shape == (16,)
            for i in range(0, 16, 5):
                p1, q1 = sphrect.sample_ellipse(technique, origins[i], *ARGS[1:], uv[i:i + 1], dtype=dtype)
                np.testing.assert_array_equal(points[i], p1[0])
                np.testing.assert_array_equal(pdf[i], q1[0])
            np.testing.assert_array_equal(sphrect.ellipse_pdf(technique, origins, *ARGS[1:], points, dtype=dtype), pdf)
    w = sphrect.ellipse_solid_angle(origins, *ARGS[1:])
    assert w.shape == (16,) and w.dtype == np.float32
    assert isinstance(sphrect.ellipse_solid_angle(ARGS[0], *ARGS[1:]), float)
    # One-sided: the emitting side is cross(axis_u, axis_v) = +z; below, nothing (and NaN from invert).
    below = (0.2, 0.3, -1.0)
    for technique in TECHNIQUES:
        _, pdf = sphrect.sample_ellipse(technique, below, *ARGS[1:], UV, two_sided=False)
        assert np.all(pdf == 0)
        _, pdf = sphrect.sample_ellipse(technique, below, *ARGS[1:], UV)
        assert np.all(pdf > 0)
    assert sphrect.ellipse_solid_angle(below, *ARGS[1:], two_sided=False) == 0
    assert np.all(np.isnan(sphrect.invert_ellipse(below, *ARGS[1:], np.zeros((1, 3)), two_sided=False)))
    # In the light's plane: pdf 0.
    _, pdf = sphrect.sample_ellipse("spherical_ellipse", (2.0, 0.0, 0.0), *ARGS[1:], UV)
    assert np.all(pdf == 0)
