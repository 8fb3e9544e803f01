"""Single scattering in a homogeneous medium against numerical integration.

Orthographic rays (straight down from z = 5, escaping to infinity) cross a medium lit by a
one-sided rectangle beside them and a point light.  Expected radiance per pixel:

  L = int_0^inf sigma_s T(t) [ int_A p(wi . d) L_e T(r) cos_l / r^2 dA  +  p(wi . d) I T(r) / r^2 ] dt,

T(s) = exp(-sigma_t s), p the Henyey-Greenstein phase function, by Gauss-Legendre quadrature over
the pixel, the light and t (composite, to t = 80, where T < 1e-13).  Every technique and each
distance-sampling strategy must pass the per-pixel t-test of test_render_analytic (family-wise
false-failure rate 1e-4 per image, 4 x 3 + 3 images: < 0.15 % for the file)."""
import functools

import numpy as np
import pytest

import sphrect
from render_testing import ALL_TECHNIQUES, pixel_t_test, replicate_images, top_camera

SIGMA_S, SIGMA_A, G = 0.3, 0.1, 0.4
RECT = dict(corner=(2.0, -0.5, -1.0), edge_x=(0, 0, 2.0), edge_y=(0, 1.0, 0), radiance=(3.0, 3.0, 3.0))  # faces -x
POINT = dict(position=(-1.5, 0.8, 0.5), intensity=(0.4, 0.4, 0.4))


def medium_scene():
    return sphrect.Scene(camera=top_camera(width=6, height=6), lights=[
        sphrect.RectLight(**RECT), sphrect.PointLight(**POINT)],
        world=sphrect.World(medium=sphrect.Medium(sigma_s=(SIGMA_S,) * 3, sigma_a=(SIGMA_A,) * 3, g=G)))


def henyey_greenstein(cos_theta, g):
    d = 1 + g * g - 2 * g * cos_theta
    return (1 - g * g) / (4 * np.pi * d * np.sqrt(d))


def gauss(a, b, n):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (a + b), 0.5 * (b - a) * w


def expected_image():
    cam = top_camera(width=6, height=6)
    sigma_t = SIGMA_S + SIGMA_A
    # t: composite Gauss on [0, 80] in 40 pieces of 8 points (the integrand is smooth).
    ts, wts = zip(*(gauss(2.0 * k, 2.0 * k + 2.0, 8) for k in range(40)))
    t, wt = np.concatenate(ts), np.concatenate(wts)
    # Light: 16 x 16 Gauss points.
    (u, wu), (v, wv) = gauss(0, 1, 16), gauss(0, 1, 16)
    c, ex, ey = (np.asarray(RECT[k], np.float64) for k in ("corner", "edge_x", "edge_y"))
    area = np.linalg.norm(np.cross(ex, ey))
    n_l = np.cross(ex, ey) / area
    Y = (c + u[:, None, None] * ex + v[None, :, None] * ey).reshape(-1, 3)
    wY = (wu[:, None] * wv[None, :]).ravel() * area
    # Pixel footprint: 3 x 3 Gauss points.
    hw, hh, _, _ = cam.image_plane()
    (pu, wpu) = gauss(0, 1, 3)
    img = np.zeros((cam.height, cam.width))
    d = np.array([0.0, 0.0, -1.0])
    for row in range(cam.height):
        for col in range(cam.width):
            total = 0.0
            for a, wa in zip(pu, wpu):
                for b, wb in zip(pu, wpu):
                    x0 = np.array([(2 * (col + a) / cam.width - 1) * hw, (1 - 2 * (row + b) / cam.height) * hh, 5.0])
                    X = x0 + t[:, None] * d                                   # [Nt, 3]
                    w = Y[None, :, :] - X[:, None, :]                          # [Nt, NY, 3]
                    r = np.linalg.norm(w, axis=-1)
                    wi = w / r[..., None]
                    cos_l = np.clip(-(wi @ n_l), 0, None)
                    f = henyey_greenstein(wi @ d, G) * RECT["radiance"][0] * np.exp(-sigma_t * r) * cos_l / r ** 2
                    rect = f @ wY                                             # [Nt]
                    wp = np.asarray(POINT["position"]) - X
                    rp = np.linalg.norm(wp, axis=-1)
                    point = (henyey_greenstein((wp @ d) / rp, G) * POINT["intensity"][0] * np.exp(-sigma_t * rp)
                             / rp ** 2)
                    total += wa * wb * np.sum(wt * SIGMA_S * np.exp(-sigma_t * t) * (rect + point))
            img[row, col] = total
    return img


@pytest.fixture(scope="module")
def expected():
    return expected_image()


@functools.lru_cache(maxsize=None)
def replicates_with_mis(medium_sampling):
    """Every technique's 16 replicates of 1024 spp with MIS, rendered once: the power check reuses rectangle's (a
    technique's images do not depend on the others rendered with it)."""
    return replicate_images(medium_scene(), ALL_TECHNIQUES, 16, 1024, medium_sampling=medium_sampling, mis="balance")


@pytest.mark.slow
@pytest.mark.parametrize("medium_sampling", ["distance", "equiangular", "mis"])
def test_single_scattering_matches_quadrature(expected, medium_sampling):
    assert expected.min() > 1e-3
    reps = replicates_with_mis(medium_sampling)
    for t in ALL_TECHNIQUES:
        ok, p_min, alpha = pixel_t_test(reps[t], expected, 1e-4, rel_tol=1e-3)
        rel = np.abs(reps[t].mean(0) - expected).max() / expected.max()
        assert ok, f"{medium_sampling}/{t}: worst p = {p_min:.3g} < {alpha:.3g} (max rel. error {rel:.3g})"


def test_single_scattering_without_mis(expected):
    reps = replicate_images(medium_scene(), ["rectangle"], 16, 1024, mis="none")
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, 1e-4, rel_tol=1e-3)
    assert ok, f"mis=none: worst p = {p_min:.3g} < {alpha:.3g}"


def test_single_scattering_with_several_light_samples(expected):
    """Three light (and phase) samples per camera sample, each along its own distance samples."""
    reps = replicate_images(medium_scene(), ["rectangle"], 16, 342, light_samples=3, mis="balance")
    ok, p_min, alpha = pixel_t_test(reps["rectangle"], expected, 1e-4, rel_tol=1e-3)
    assert ok, f"light_samples=3: worst p = {p_min:.3g} < {alpha:.3g}"


def test_medium_test_has_power(expected):
    """The same test rejects an expected image 5 % off (the estimate's relative standard error is
    ~0.5 %: strong extinction makes both distance strategies noisy here)."""
    reps = replicates_with_mis("mis")
    assert pixel_t_test(reps["rectangle"], expected, 1e-4, rel_tol=1e-3)[0]
    assert not pixel_t_test(reps["rectangle"], expected * 1.05, 1e-4, rel_tol=1e-3)[0]
