"""Shared helpers of the renderer tests: small analytic scenes, closed-form irradiance, and a
per-pixel t-test over independent replicate renders with a Sidak multiple-comparison correction."""
import json

import numpy as np
from scipy import stats

import sphrect
from chi2 import sidak_alpha

ALL_TECHNIQUES = list(sphrect.techniques)


def plane_mesh(size=50.0, z=0.0):
    v = np.array([[-size, -size, z], [size, -size, z], [size, size, z], [-size, size, z]], np.float32)
    return sphrect.Mesh(vertices=v, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), name="ground")


def top_camera(width=12, height=12, half=1.0, height_above=5.0):
    """Orthographic camera looking straight down (-Z) at the square [-half, half]^2 of the z = 0 plane."""
    return sphrect.Camera(width=width, height=height, type="orthographic", ortho_scale=2 * half,
                          to_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, height_above], [0, 0, 0, 1]])


def gauss_pixel_points(cam, order=16):
    """Plane points (x, y, 0) and weights of a Gauss-Legendre rule over every pixel of the top camera
    (the renderer's box filter averages radiance over the pixel's footprint)."""
    hw, hh, ox, oy = cam.image_plane()
    nodes, weights = np.polynomial.legendre.leggauss(order)
    nodes = 0.5 * (nodes + 1)
    weights = 0.5 * weights
    px = (np.arange(cam.width)[:, None] + nodes[None, :])          # [W, order] film x
    py = (np.arange(cam.height)[:, None] + nodes[None, :])         # [H, order] film y
    x = (2 * px / cam.width - 1) * hw + ox
    y = (1 - 2 * py / cam.height) * hh + oy
    X = np.broadcast_to(x[None, :, None, :], (cam.height, cam.width, order, order))
    Y = np.broadcast_to(y[:, None, :, None], (cam.height, cam.width, order, order))
    W = weights[:, None] * weights[None, :]
    return X, Y, W


def polygon_irradiance(points, normal, verts, two_sided=True):
    """Irradiance per unit radiance at `points` [..., 3] (normal `normal`) from a polygon above
    their horizon: E / L = 1/2 |sum_i theta_i n . unit(v_i x v_{i+1})| (Lambert's formula).
    One-sided: zero for points behind the polygon (normal = cross(v1 - v0, v3 - v0) direction)."""
    verts = np.asarray(verts, np.float64)
    r = verts - points[..., None, :]
    r /= np.linalg.norm(r, axis=-1, keepdims=True)
    e = np.zeros(points.shape[:-1])
    for i in range(len(verts)):
        a, b = r[..., i, :], r[..., (i + 1) % len(verts), :]
        c = np.cross(a, b)
        s = np.linalg.norm(c, axis=-1)
        theta = np.arctan2(s, np.sum(a * b, axis=-1))
        e += theta * np.where(s > 0, (c @ np.asarray(normal, np.float64)) / np.where(s > 0, s, 1), 0)
    e = 0.5 * np.abs(e)
    if not two_sided:
        n_light = np.cross(verts[1] - verts[0], verts[-1] - verts[0])
        e = np.where((points - verts[0]) @ n_light > 0, e, 0.0)
    return e


def expected_plane_image(cam, albedo, irradiance_fn, order=16):
    """Pixel-averaged Lambertian radiance albedo / pi * E(x) on the z = 0 plane.  Order 16: E has a kink
    where a pixel straddles the plane of a light, and order 6 leaves a detectable quadrature error there."""
    X, Y, W = gauss_pixel_points(cam, order)
    P = np.stack([X, Y, np.zeros_like(X)], axis=-1)
    E = irradiance_fn(P)
    return albedo / np.pi * np.einsum("hwij,ij->hw", E, W)


def replicate_images(scene, techniques, replicates, samples, first_seed=1000, **kw):
    """{technique: [replicates, H, W] red channel}, each replicate an independent seed (first_seed, first_seed + 1,
    ...: stacks to compare with each other take seeds apart)."""
    out = {t: [] for t in techniques}
    for rep in range(replicates):
        r = sphrect.Renderer(scene, techniques=techniques, seed=first_seed + rep, **kw)
        assert r.render(samples)
        for t in techniques:
            assert r.stats(t)["dropped_samples"] == 0, f"{t}: non-finite samples"
            out[t].append(r.image(t)[:, :, 0].astype(np.float64))
    return {t: np.array(v) for t, v in out.items()}


def pixel_t_test(reps, expected, family_alpha, rel_tol=2e-5):
    """Per-pixel two-sided t-test of the replicate means against `expected`; the family-wise false
    failure rate over all pixels is `family_alpha` (Sidak).  rel_tol absorbs float32 rounding where
    the estimator has (near) zero variance.  Returns (passed, worst p-value, per-pixel threshold)."""
    k = reps.shape[0]
    mean = reps.mean(axis=0)
    var = reps.var(axis=0, ddof=1)
    se = np.sqrt(var / k + (rel_tol * np.abs(expected) + 1e-7) ** 2)
    t = (mean - expected) / se
    p = 2 * stats.t.sf(np.abs(t), df=k - 1)
    n = expected.size
    alpha_pixel = sidak_alpha(family_alpha, n)
    return bool(p.min() >= alpha_pixel), float(p.min()), alpha_pixel


def save_as_older_version(path, old_path, version, edit):
    """Write the scene file `path` again at `old_path` as format `version`, its scene.json changed by edit(meta)
    (which drops what that version lacks): a file an older sphrect wrote."""
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(bytes(arrays["scene.json"]).decode("utf-8"))
    meta["version"] = version
    edit(meta)
    arrays["scene.json"] = np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8)
    np.savez_compressed(old_path, **arrays)
