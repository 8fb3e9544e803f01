"""Edge behaviour of the colour and shading-input node functions (native/render/svm/color_nodes.h, shading_nodes.h,
through sphrect._native.svm_color): Cycles 3.4's clamps, safe divisions and special cases, and the binding's
input checks.  Their values over ordinary inputs are held against Cycles in tests/blender/test_color_nodes.py."""
import numpy as np
import pytest

from sphrect._native import svm_color as svm

UP = (0.0, 0.0, 1.0)


def test_names_are_blenders_identifiers():
    assert svm.VECTOR_MATH_OPERATIONS[:2] == ("ADD", "SUBTRACT") and len(svm.VECTOR_MATH_OPERATIONS) == 27
    assert svm.VECTOR_ROTATE_TYPES == ("AXIS_ANGLE", "X_AXIS", "Y_AXIS", "Z_AXIS", "EULER_XYZ")
    assert svm.LIGHT_FALLOFF_KINDS == ("Quadratic", "Linear", "Constant")
    assert svm.CURVE_TABLE_SIZE == 256


# ---- Shading inputs -----------------------------------------------------------------------------------------

def test_layer_weight_blend_half_is_the_plain_facing_and_ior_two():
    n = np.array([[0.0, 0.6, 0.8], [0.0, 0.0, 1.0], [0.0, -0.8, -0.6]], dtype=np.float32)
    fresnel, facing = svm.layer_weight(0.5, UP, n)
    np.testing.assert_allclose(facing, 1 - np.abs(n[:, 2]), atol=1e-7)
    np.testing.assert_allclose(fresnel, svm.fresnel(2.0, UP, n), atol=1e-7)
    # On a back face the relative IOR inverts: Layer Weight's eta becomes 1 - blend, the Fresnel node's 1 / ior.
    back, _ = svm.layer_weight(0.5, UP, n, 1)
    np.testing.assert_allclose(back, svm.fresnel(2.0, UP, n, 1), atol=1e-7)
    assert (back >= fresnel).all()  # from the dense side: total internal reflection at grazing angles


def test_layer_weight_facing_clamps_blend():
    _, at_one = svm.layer_weight(1.0, UP, (0.0, 0.6, 0.8))  # p = 0.5 / 1e-5: 0.8^50000 underflows to 0
    _, beyond = svm.layer_weight(7.0, UP, (0.0, 0.6, 0.8))
    assert at_one[0] == pytest.approx(1.0) and beyond[0] == at_one[0]
    _, at_zero = svm.layer_weight(-1.0, UP, (0.0, 0.6, 0.8))  # p = 0: 1 - 0.8^0
    assert at_zero[0] == 0.0


def test_fresnel_ior_floor_and_total_internal_reflection():
    assert svm.fresnel(0.0, UP, UP)[0] == svm.fresnel(1e-5, UP, UP)[0]  # IOR clamped at 1e-5
    assert svm.fresnel(1.0, UP, UP)[0] == 0.0
    assert svm.fresnel(1.5, UP, (0.0, 0.99, 0.1), 1)[0] == 1.0  # back face, grazing: TIR


def test_light_falloff_powers_and_smoothing():
    r = np.array([0.5, 2.0, 10.0], dtype=np.float32)
    np.testing.assert_allclose(svm.light_falloff("Quadratic", 3.0, 0.0, r), 3.0)
    np.testing.assert_allclose(svm.light_falloff("Linear", 3.0, 0.0, r), 3.0 * r, rtol=1e-6)
    np.testing.assert_allclose(svm.light_falloff("Constant", 3.0, 0.0, r), 3.0 * r * r, rtol=1e-6)
    np.testing.assert_allclose(svm.light_falloff("Quadratic", 3.0, 4.0, r), 3.0 * r * r / (4.0 + r * r), rtol=1e-6)
    # A sun's FLT_MAX length: r^2 overflows and the smoothing is skipped.
    sun = svm.light_falloff("Quadratic", 3.0, 4.0, np.finfo(np.float32).max)
    assert sun[0] == 3.0
    with pytest.raises(ValueError, match="unknown light falloff output 'Cubic'; valid outputs: 'Quadratic'"):
        svm.light_falloff("Cubic", 1.0, 0.0, 1.0)


def test_bump_differentials_are_cycles_orthonormals():
    dx, dy = svm.bump_differentials(np.array([UP, (0.0, 0.6, 0.8)], dtype=np.float32), 0.25)
    for ng, a, b in zip((UP, (0.0, 0.6, 0.8)), dx, dy):
        assert np.linalg.norm(a) == pytest.approx(0.25) and np.linalg.norm(b) == pytest.approx(0.25)
        assert abs(a @ ng) < 1e-6 and abs(b @ ng) < 1e-6 and abs(a @ b) < 1e-6
        np.testing.assert_allclose(np.cross(ng, a / 0.25), b / 0.25, atol=1e-6)
    # (n.z - n.y, n.x - n.z, n.y - n.x), normalised: for n = +Z that is (1, -1, 0) / sqrt 2.
    np.testing.assert_allclose(dx[0], 0.25 * np.array([1, -1, 0]) / np.sqrt(2), atol=1e-7)


def test_bump_without_slope_or_strength_keeps_the_normal():
    dx, dy = svm.bump_differentials(UP, 0.1)
    flat = svm.bump(UP, UP, UP, dx, dy, 0.3, 0.3, 0.3, strength=1.0, distance=2.0)
    sloped = svm.bump(UP, UP, UP, dx, dy, 0.0, 0.05, 0.0, strength=1.0, distance=1.0)
    weak = svm.bump(UP, UP, UP, dx, dy, 0.0, 0.05, 0.0, strength=-1.0, distance=1.0)  # clamped to 0
    inverted = svm.bump(UP, UP, UP, dx, dy, 0.0, 0.05, 0.0, strength=1.0, distance=1.0, invert=True)
    np.testing.assert_allclose(flat[0], UP)
    np.testing.assert_allclose(weak[0], UP, atol=1e-7)
    assert np.linalg.norm(sloped[0]) == pytest.approx(1.0)
    # The height rises along dx: the normal leans against it; inverted, with it.
    assert sloped[0] @ dx[0] < 0 < inverted[0] @ dx[0]


def test_ensure_valid_reflection():
    ng, incoming = np.array(UP), np.array([0.8, 0.0, 0.6])
    kept = svm.ensure_valid_reflection(ng, incoming, (0.0, 0.0, 1.0))
    np.testing.assert_allclose(kept[0], UP)
    # A normal leaning so far that the reflection of I would go below the surface is turned towards Ng until it
    # reflects I just above it.
    n = np.array([-0.8, 0.0, 0.6])
    fixed = svm.ensure_valid_reflection(ng, incoming, n)[0]
    reflected = 2 * (fixed @ incoming) * fixed - incoming
    assert np.linalg.norm(fixed) == pytest.approx(1.0) and reflected @ ng == pytest.approx(0.01, abs=1e-4)


# ---- Colour -----------------------------------------------------------------------------------------------------

def test_blackbody_ends_and_clamp():
    low, cold, hot, hotter = svm.blackbody([100.0, 799.0, 12000.0, 1e6])
    np.testing.assert_array_equal(low, cold)  # constant below 800 K
    np.testing.assert_array_equal(hot, hotter)  # and from 12000 K
    assert cold[1] == 0.0 and cold[2] == 0.0 and cold[0] > 5  # the fit's negative green and blue clamped
    np.testing.assert_array_equal(svm.blackbody(np.nan)[0], cold)  # NaN: the low end


def test_wavelength_range():
    # Cycles truncates (nm - 380) / 5 towards zero: (375, 380) still reads the first rows (extrapolated).
    c = svm.wavelength([374.9, 377.0, 380.0, 550.0, 779.9, 780.0, np.nan])
    assert (c[[0, 5, 6]] == 0).all()
    assert (c[[1, 2, 3, 4]].sum(axis=1) > 0).all() and (c >= 0).all()
    assert c[3, 1] > c[3, 0] and c[3, 1] > c[3, 2]  # 550 nm is green


def test_hsv_neutral_settings_and_fac():
    rng = np.random.default_rng(1)
    color = rng.uniform(0, 1, (64, 3)).astype(np.float32)
    np.testing.assert_allclose(svm.hue_saturation_value(color), color, atol=2e-6)
    np.testing.assert_allclose(svm.hue_saturation_value(color - 0.5, hue=0.2, fac=0.0), np.maximum(color - 0.5, 0))
    # Saturation is clamped to [0, 1] after scaling: 0 gives grey (the value), 10 a fully saturated colour.
    grey = svm.hue_saturation_value(color, saturation=0.0)
    np.testing.assert_allclose(grey, np.repeat(color.max(axis=1, keepdims=True), 3, axis=1), atol=1e-6)
    assert (svm.hue_saturation_value(color, saturation=10.0).min(axis=1) <= 1e-6).all()


def test_bright_contrast_gamma_invert_rgb_to_bw():
    c = np.array([[-0.5, 0.25, 2.0]], dtype=np.float32)
    np.testing.assert_allclose(svm.bright_contrast(c, 0.1, 1.0), [[0.0, 0.1, 3.6]], atol=1e-6)
    np.testing.assert_allclose(svm.gamma(c, 2.0), [[-0.5, 0.0625, 4.0]])  # non-positive components kept
    np.testing.assert_array_equal(svm.gamma(c, 0.0), [[1, 1, 1]])  # gamma 0: white
    np.testing.assert_allclose(svm.invert(c, 0.25), [[0.0, 0.375, 1.25]])
    assert svm.rgb_to_bw((1.0, 1.0, 1.0))[0] == pytest.approx(1.0, abs=1e-6)
    assert svm.rgb_to_bw((0.0, 1.0, 0.0))[0] == pytest.approx(svm.RGB_TO_Y[1])


# ---- Curves ----------------------------------------------------------------------------------------------------

def _ramp(size=256):
    return np.linspace(0.0, 1.0, size, dtype=np.float32)


def test_curve_identity_extrapolation_and_clamp():
    x = np.array([-0.5, 0.0, 0.3, 1.0, 1.5], dtype=np.float32)
    identity = np.stack([_ramp()] * 3, axis=1)
    extended = svm.curves_rgb(identity, 0.0, 1.0, True, 1.0, np.stack([x] * 3, axis=1))
    np.testing.assert_allclose(extended[:, 0], x, atol=1e-6)  # the end slopes extended
    held = svm.curve_float(_ramp(), 0.0, 1.0, False, 1.0, x)
    np.testing.assert_allclose(held, np.clip(x, 0, 1), atol=1e-6)
    # The range [min_x, max_x] maps onto the table; fac mixes with the input (not clamped).
    np.testing.assert_allclose(svm.curve_float(1 - _ramp(), -1.0, 3.0, False, 1.0, [-1.0, 1.0, 3.0]), [1, 0.5, 0],
                               atol=1e-6)
    np.testing.assert_allclose(svm.curve_float(1 - _ramp(), 0.0, 1.0, False, 2.0, [0.25]), [2 * 0.75 - 0.25],
                               atol=1e-6)


def test_curve_table_checks():
    with pytest.raises(ValueError, match=r"table must have shape \(size, 3\) with size >= 2, got \(256,\)"):
        svm.curves_rgb(_ramp(), 0.0, 1.0, True, 1.0, (0.5, 0.5, 0.5))
    with pytest.raises(ValueError, match="max_x must be greater than min_x"):
        svm.curve_float(_ramp(), 1.0, 1.0, True, 1.0, 0.5)


# ---- Vector Math, Vector Rotate, Normal -----------------------------------------------------------------------

def test_vector_math_safe_cases():
    zero = (0.0, 0.0, 0.0)
    a = (1.0, -2.0, 3.0)

    def vec(op, *args, **kw):
        return svm.vector_math(op, *args, **kw)[1][0]

    np.testing.assert_array_equal(vec("DIVIDE", a, (2.0, 0.0, -1.0)), [0.5, 0.0, -3.0])
    np.testing.assert_array_equal(vec("NORMALIZE", zero), zero)
    np.testing.assert_array_equal(vec("PROJECT", a, zero), zero)
    np.testing.assert_array_equal(vec("MODULO", (5.5, -5.5, 1.0), (2.0, 2.0, 0.0)), [1.5, -1.5, 0.0])  # fmod
    np.testing.assert_array_equal(vec("WRAP", a, (1.0, 1.0, 1.0), (1.0, 1.0, 1.0)), [1, 1, 1])  # empty range: min
    np.testing.assert_array_equal(vec("SNAP", (1.7, -1.7, 1.0), (0.5, 0.5, 0.0)), [1.5, -2.0, 0.0])
    # Refract beyond the critical angle: zero; the normal is normalised first.
    np.testing.assert_array_equal(vec("REFRACT", (0.9, 0.0, -0.43589), (0, 0, 5), scale=1.5), zero)
    np.testing.assert_allclose(vec("REFLECT", (1.0, 0.0, -1.0), (0.0, 0.0, 3.0)), [1.0, 0.0, 1.0])
    np.testing.assert_array_equal(vec("FACEFORWARD", a, UP, (0, 0, 1)), [-1, 2, -3])
    value, vector = svm.vector_math("DOT_PRODUCT", a, a)
    assert value[0] == 14.0 and (vector == 0).all()  # the unused output is zero
    with pytest.raises(ValueError, match="unknown vector math operation 'CROSS'; valid operations: 'ADD'"):
        svm.vector_math("CROSS", a, a)


@pytest.mark.parametrize("rotation_type", svm.VECTOR_ROTATE_TYPES)
def test_vector_rotate_inverse_undoes_it(rotation_type):
    rng = np.random.default_rng(7)
    v = rng.normal(size=(32, 3)).astype(np.float32)
    kw = dict(center=(0.3, -0.1, 0.2), axis=(0.2, -0.5, 0.8), angle=1.1, rotation=(0.4, -1.2, 2.0))
    forward = svm.vector_rotate(rotation_type, False, v, **kw)
    back = svm.vector_rotate(rotation_type, True, forward, **kw)
    np.testing.assert_allclose(back, v, atol=2e-6)
    assert np.abs(forward - v).max() > 0.1
    # distances to the centre are kept
    c = np.array(kw["center"])
    np.testing.assert_allclose(np.linalg.norm(forward - c, axis=1), np.linalg.norm(v - c, axis=1), rtol=1e-5)


def test_vector_rotate_zero_axis_and_fixed_axes():
    v = (1.0, 2.0, 3.0)
    np.testing.assert_array_equal(svm.vector_rotate("AXIS_ANGLE", False, v, axis=(0, 0, 0), angle=1.0)[0], v)
    np.testing.assert_allclose(svm.vector_rotate("Z_AXIS", False, v, angle=np.pi / 2)[0], [-2, 1, 3], atol=1e-6)
    np.testing.assert_allclose(svm.vector_rotate("X_AXIS", False, v, angle=np.pi / 2)[0], [1, -3, 2], atol=1e-6)


def test_normal_dot_normalises_both():
    assert svm.normal_dot((0.0, 0.0, 2.0), (0.0, 3.0, 3.0))[0] == pytest.approx(np.sqrt(0.5))


# ---- The binding's checks -----------------------------------------------------------------------------------

def test_inputs_broadcast_and_checks():
    out = svm.gamma(np.ones((5, 3)), np.linspace(0, 2, 5))
    assert out.shape == (5, 3) and out.dtype == np.float32
    assert svm.blackbody(1500.0).shape == (1, 3)
    with pytest.raises(ValueError, match=r"gamma has 4 rows, the inputs before it 5"):
        svm.gamma(np.ones((5, 3)), np.ones(4))
    with pytest.raises(ValueError, match=r"color must be 3 numbers or an array of shape \(N, 3\), got shape \(2,\)"):
        svm.gamma((1.0, 2.0), 1.0)
    with pytest.raises(ValueError, match=r"temperature must be a number or an array of shape \(N,\)"):
        svm.blackbody(np.ones((2, 2)))
    with pytest.raises(ValueError, match="temperature must be a numeric array-like"):
        svm.blackbody("hot")
