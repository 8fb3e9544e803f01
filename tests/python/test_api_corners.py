"""Numerical corners through the Python API (issue 15): float32 inputs beyond float32's range are refused instead
of answered wrongly, and pdf() / invert() of points off the light give 0 / NaN (tolerance in their docstrings)."""
import math

import numpy as np
import pytest

import sphrect

HUGE = dict(origin=(0, 0, 0), corner=(-1e20, -1e20, 1), edge_x=(2e20, 0, 0), edge_y=(0, 2e20, 0))
TINY = dict(origin=(0, 0, 0), corner=(0, 0, 1), edge_x=(1e-30, 0, 0), edge_y=(0, 1e-30, 0))


def test_float64_computes_what_float32_cannot():
    # A 2e20 light a unit above the origin covers the hemisphere; a 1e-30 square at distance 1 subtends 1e-60.
    assert sphrect.solid_angle(**HUGE, dtype="float64") == pytest.approx(2 * math.pi, rel=1e-12)
    assert sphrect.solid_angle(**TINY, dtype="float64") == pytest.approx(1e-60, rel=1e-6)


@pytest.mark.parametrize("case", [HUGE, TINY], ids=["huge", "tiny"])
def test_float32_refuses_inputs_beyond_its_range(case):
    with pytest.raises(ValueError, match="beyond what float32 computes"):
        sphrect.solid_angle(**case)
    with pytest.raises(ValueError, match="beyond what float32 computes"):
        sphrect.sample("rectangle", uv=[[0.5, 0.5]], **case)


def test_float32_refuses_far_origins_and_ellipse_axes():
    with pytest.raises(ValueError, match="origin is beyond"):
        sphrect.solid_angle((0, 0, 1e20), (0, 0, 0), (1, 0, 0), (0, 1, 0))
    with pytest.raises(ValueError, match="axis_u is beyond"):
        sphrect.ellipse_solid_angle((0, 0, 0), (0, 0, 1), (1e-25, 0, 0), (0, 1, 0))
    # The edge of the range still computes: 1e18 light at a unit: nearly the hemisphere.
    assert sphrect.solid_angle((0, 0, 0), (-1e18, -1e18, 1), (2e18, 0, 0), (0, 2e18, 0)) == pytest.approx(
        2 * math.pi, rel=1e-5)


LIGHT = dict(origin=(0.1, -0.2, 0.0), corner=(-0.5, -0.5, 1.0), edge_x=(1.0, 0, 0), edge_y=(0, 1.0, 0))
OFF = np.array([[0.1, -0.2, 0.0],      # the origin itself
                [0.0, 0.0, 1.01],      # 1% of the edge off the plane
                [1.6, 0.0, 1.0],       # in the plane, beyond an edge
                [0.0, -0.6, 1.0]])


@pytest.mark.parametrize("dtype", ["float32", "float64"])
@pytest.mark.parametrize("technique", sphrect.techniques)
def test_points_off_the_light_have_pdf_zero_and_no_inverse(technique, dtype):
    uv = np.random.default_rng(4).random((64, 2))
    points, pdf = sphrect.sample(technique, uv=uv, normal=(0, 0, 1), dtype=dtype, **LIGHT)
    assert np.all(pdf > 0)
    np.testing.assert_allclose(sphrect.pdf(technique, points=points, normal=(0, 0, 1), dtype=dtype, **LIGHT), pdf,
                               rtol=1e-4)
    assert np.all(sphrect.pdf(technique, points=OFF, normal=(0, 0, 1), dtype=dtype, **LIGHT) == 0)
    if technique == "rectangle":
        assert np.isfinite(sphrect.invert(points=points, dtype=dtype, **LIGHT)).all()
        assert np.isnan(sphrect.invert(points=OFF, dtype=dtype, **LIGHT)).all()


def test_far_lights_keep_their_own_points():
    """A light 1e4 away, sampled in float32: its points' rounding is within the tolerance, so they are on it."""
    far = dict(origin=(0, 0, 0), corner=(-0.5 + 1e4, -0.5, 1e4), edge_x=(1, 0, 0), edge_y=(0, 1, 0))
    points, pdf = sphrect.sample("rectangle", uv=np.random.default_rng(1).random((256, 2)), **far)
    assert np.all(sphrect.pdf("rectangle", points=points, **far) > 0)
    assert np.isfinite(sphrect.invert(points=points, **far)).all()


def test_ellipse_points_off_the_light():
    disk = dict(origin=(0, 0, 0), center=(0, 0, 1), axis_u=(0.5, 0, 0), axis_v=(0, 0.3, 0))
    points, pdf = sphrect.sample_ellipse("spherical_ellipse", uv=np.random.default_rng(2).random((64, 2)), **disk)
    assert np.all(sphrect.ellipse_pdf("spherical_ellipse", points=points, **disk) > 0)
    off = np.array([[0.45, 0.25, 1.0], [0.0, 0.0, 1.05], [0, 0, 0]])  # outside the rim; off the plane; origin
    assert np.all(sphrect.ellipse_pdf("spherical_ellipse", points=off, **disk) == 0)
    assert np.isnan(sphrect.invert_ellipse(points=off, **disk)).all()
