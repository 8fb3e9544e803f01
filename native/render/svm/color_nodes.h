// Cycles 3.4's colour and vector nodes as pure functions (kernel/svm/{blackbody,wavelength,hsv,brightness,gamma,
// invert,ramp,math_util,vector_rotate,normal}.h and util/color.h), in float as the kernel computes them, so that a
// node program evaluating them gives Cycles' values to float rounding.  Each takes the node's inputs (its sockets,
// linked or not) and settings and returns its output; the settings come from the exporter
// (addon/sphrect_blender/io/exporter/color_node_params.py).  Tested against Cycles per node in
// tests/blender/test_color_nodes.py.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/vec3.h"
#include "math_nodes.h"  // Saturate, SafeDivide, SafeModulo, Wrap
#include "mix_nodes.h"   // RgbToHsv, HsvToRgb

namespace sphrect::render::svm {

// ---- Blender 3.4's colour spaces -------------------------------------------------------------------------------
// Blender's OCIO config has scene linear = Rec.709 primaries and finds XYZ through its aces_interchange role, which
// Cycles (ShaderManager::init_xyz_transforms) turns into a matrix within 1e-6 of the Rec.709 one below: the kernel
// then treats scene linear as Rec.709 (rec709_to_rgb is the identity) and converts XYZ and luminance with these.

// XYZ (D65) to scene-linear RGB, by rows (Cycles' xyz_to_rec709).
inline constexpr Vec3f kXyzToRgb[3] = {{3.2404542f, -1.5371385f, -0.4985314f},
                                       {-0.9692660f, 1.8760108f, 0.0415560f},
                                       {0.0556434f, -0.2040259f, 1.0572252f}};
// Luminance of scene-linear RGB (Cycles' rgb_to_y: linear_rgb_to_gray, RGB to BW).
inline constexpr Vec3f kRgbToY = {0.2126729f, 0.7151522f, 0.0721750f};

inline Vec3f XyzToRgb(const Vec3f& xyz) {
    return {Dot(kXyzToRgb[0], xyz), Dot(kXyzToRgb[1], xyz), Dot(kXyzToRgb[2], xyz)};
}

// RGB to BW (Cycles' NODE_CONVERT_CF): the luminance.
inline float RgbToBw(const Vec3f& c) { return Dot(c, kRgbToY); }

inline Vec3f MaxZero(const Vec3f& c) { return {std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f)}; }

// ---- HSV (util/color.h: rgb_to_hsv, hsv_to_rgb) ----------------------------------------------------------------

// Hue/Saturation/Value: the hue turned by hue - 0.5 (fmodf: a negative sum stays negative, as in Cycles), the
// saturation scaled and clamped to [0, 1], the value scaled; mixed with the input by fac; negatives clamped to 0.
inline Vec3f HueSaturationValue(const Vec3f& color, float hue, float saturation, float value, float fac) {
    Vec3f hsv = RgbToHsv(color);
    hsv.x = std::fmod(hsv.x + hue + 0.5f, 1.0f);
    hsv.y = Saturate(hsv.y * saturation);
    hsv.z *= value;
    const Vec3f out = HsvToRgb(hsv);
    return MaxZero({fac * out.x + (1.0f - fac) * color.x, fac * out.y + (1.0f - fac) * color.y,
                    fac * out.z + (1.0f - fac) * color.z});
}

// ---- Bright/Contrast, Gamma, Invert ----------------------------------------------------------------------------

inline Vec3f BrightContrast(const Vec3f& color, float brightness, float contrast) {
    const float a = 1.0f + contrast, b = brightness - contrast * 0.5f;
    return {std::max(a * color.x + b, 0.0f), std::max(a * color.y + b, 0.0f), std::max(a * color.z + b, 0.0f)};
}

// Gamma: positive components raised to gamma, the others kept; gamma 0 gives white.
inline Vec3f GammaColor(Vec3f color, float gamma) {
    if (gamma == 0.0f) return {1.0f, 1.0f, 1.0f};
    if (color.x > 0.0f) color.x = std::pow(color.x, gamma);
    if (color.y > 0.0f) color.y = std::pow(color.y, gamma);
    if (color.z > 0.0f) color.z = std::pow(color.z, gamma);
    return color;
}

inline Vec3f InvertColor(const Vec3f& color, float fac) {
    const auto inv = [fac](float c) { return fac * (1.0f - c) + (1.0f - fac) * c; };
    return {inv(color.x), inv(color.y), inv(color.z)};
}

// ---- Blackbody and Wavelength ------------------------------------------------------------------------------------

// Cycles' fit of the blackbody colour in Rec.709 (svm_math_blackbody_color_rec709): seven temperature bands, each
// a/t + b t + c for red and green and a cubic for blue; constant below 800 K and from 12000 K.  Components can be
// negative (outside Rec.709's gamut).
inline Vec3f BlackbodyRec709(float t) {
    static constexpr float kR[7][3] = {
        {1.61919106e+03f, -2.05010916e-03f, 5.02995757e+00f}, {2.48845471e+03f, -1.11330907e-03f, 3.22621544e+00f},
        {3.34143193e+03f, -4.86551192e-04f, 1.76486769e+00f}, {4.09461742e+03f, -1.27446582e-04f, 7.25731635e-01f},
        {4.67028036e+03f, 2.91258199e-05f, 1.26703442e-01f},  {4.59509185e+03f, 2.87495649e-05f, 1.50345020e-01f},
        {3.78717450e+03f, 9.35907826e-06f, 3.99075871e-01f}};
    static constexpr float kG[7][3] = {
        {-4.88999748e+02f, 6.04330754e-04f, -7.55807526e-02f}, {-7.55994277e+02f, 3.16730098e-04f, 4.78306139e-01f},
        {-1.02363977e+03f, 1.20223470e-04f, 9.36662319e-01f},  {-1.26571316e+03f, 4.87340896e-06f, 1.27054498e+00f},
        {-1.42529332e+03f, -4.01150431e-05f, 1.43972784e+00f}, {-1.17554822e+03f, -2.16378048e-05f, 1.30408023e+00f},
        {-5.00799571e+02f, -4.59832026e-06f, 1.09098763e+00f}};
    static constexpr float kB[7][4] = {{5.96945309e-11f, -4.85742887e-08f, -9.70622247e-05f, -4.07936148e-03f},
                                       {2.40430366e-11f, 5.55021075e-08f, -1.98503712e-04f, 2.89312858e-02f},
                                       {-1.40949732e-11f, 1.89878968e-07f, -3.56632824e-04f, 9.10767778e-02f},
                                       {-3.61460868e-11f, 2.84822009e-07f, -4.93211319e-04f, 1.56723440e-01f},
                                       {-1.97075738e-11f, 1.75359352e-07f, -2.50542825e-04f, -2.22783266e-02f},
                                       {-1.61997957e-13f, -1.64216008e-08f, 3.86216271e-04f, -7.38077418e-01f},
                                       {6.72650283e-13f, -2.73078809e-08f, 4.24098264e-04f, -7.52335691e-01f}};
    if (t >= 12000.0f) return {0.8262954810464208f, 0.9945080501520986f, 1.566307710274283f};
    if (!(t >= 800.0f)) return {5.413294490189271f, -0.20319390035873933f, -0.0822535242887164f};  // NaN too
    const int i = t >= 6365.0f   ? 6
                  : t >= 3315.0f ? 5
                  : t >= 1902.0f ? 4
                  : t >= 1449.0f ? 3
                  : t >= 1167.0f ? 2
                  : t >= 965.0f  ? 1
                                 : 0;
    const float* r = kR[i];
    const float* g = kG[i];
    const float* b = kB[i];
    const float inv = 1.0f / t;
    return {r[0] * inv + r[1] * t + r[2], g[0] * inv + g[1] * t + g[2], ((b[0] * t + b[1]) * t + b[2]) * t + b[3]};
}

// Blackbody node: the fit in scene linear (Rec.709 in Blender), negatives clamped to 0.
inline Vec3f Blackbody(float temperature) { return MaxZero(BlackbodyRec709(temperature)); }

// Wavelength node: the CIE 1931 colour-matching functions tabulated every 5 nm from 380 nm (81 rows), interpolated,
// to RGB, scaled by 1 / 2.52 and clamped at 0; black outside (375, 780) nm (Cycles truncates the table position
// towards zero, so (375, 380) extends the first segment).
inline Vec3f Wavelength(float nm) {
    static constexpr float kCie[81][3] = {
        {0.0014f, 0.0000f, 0.0065f}, {0.0022f, 0.0001f, 0.0105f}, {0.0042f, 0.0001f, 0.0201f},
        {0.0076f, 0.0002f, 0.0362f}, {0.0143f, 0.0004f, 0.0679f}, {0.0232f, 0.0006f, 0.1102f},
        {0.0435f, 0.0012f, 0.2074f}, {0.0776f, 0.0022f, 0.3713f}, {0.1344f, 0.0040f, 0.6456f},
        {0.2148f, 0.0073f, 1.0391f}, {0.2839f, 0.0116f, 1.3856f}, {0.3285f, 0.0168f, 1.6230f},
        {0.3483f, 0.0230f, 1.7471f}, {0.3481f, 0.0298f, 1.7826f}, {0.3362f, 0.0380f, 1.7721f},
        {0.3187f, 0.0480f, 1.7441f}, {0.2908f, 0.0600f, 1.6692f}, {0.2511f, 0.0739f, 1.5281f},
        {0.1954f, 0.0910f, 1.2876f}, {0.1421f, 0.1126f, 1.0419f}, {0.0956f, 0.1390f, 0.8130f},
        {0.0580f, 0.1693f, 0.6162f}, {0.0320f, 0.2080f, 0.4652f}, {0.0147f, 0.2586f, 0.3533f},
        {0.0049f, 0.3230f, 0.2720f}, {0.0024f, 0.4073f, 0.2123f}, {0.0093f, 0.5030f, 0.1582f},
        {0.0291f, 0.6082f, 0.1117f}, {0.0633f, 0.7100f, 0.0782f}, {0.1096f, 0.7932f, 0.0573f},
        {0.1655f, 0.8620f, 0.0422f}, {0.2257f, 0.9149f, 0.0298f}, {0.2904f, 0.9540f, 0.0203f},
        {0.3597f, 0.9803f, 0.0134f}, {0.4334f, 0.9950f, 0.0087f}, {0.5121f, 1.0000f, 0.0057f},
        {0.5945f, 0.9950f, 0.0039f}, {0.6784f, 0.9786f, 0.0027f}, {0.7621f, 0.9520f, 0.0021f},
        {0.8425f, 0.9154f, 0.0018f}, {0.9163f, 0.8700f, 0.0017f}, {0.9786f, 0.8163f, 0.0014f},
        {1.0263f, 0.7570f, 0.0011f}, {1.0567f, 0.6949f, 0.0010f}, {1.0622f, 0.6310f, 0.0008f},
        {1.0456f, 0.5668f, 0.0006f}, {1.0026f, 0.5030f, 0.0003f}, {0.9384f, 0.4412f, 0.0002f},
        {0.8544f, 0.3810f, 0.0002f}, {0.7514f, 0.3210f, 0.0001f}, {0.6424f, 0.2650f, 0.0000f},
        {0.5419f, 0.2170f, 0.0000f}, {0.4479f, 0.1750f, 0.0000f}, {0.3608f, 0.1382f, 0.0000f},
        {0.2835f, 0.1070f, 0.0000f}, {0.2187f, 0.0816f, 0.0000f}, {0.1649f, 0.0610f, 0.0000f},
        {0.1212f, 0.0446f, 0.0000f}, {0.0874f, 0.0320f, 0.0000f}, {0.0636f, 0.0232f, 0.0000f},
        {0.0468f, 0.0170f, 0.0000f}, {0.0329f, 0.0119f, 0.0000f}, {0.0227f, 0.0082f, 0.0000f},
        {0.0158f, 0.0057f, 0.0000f}, {0.0114f, 0.0041f, 0.0000f}, {0.0081f, 0.0029f, 0.0000f},
        {0.0058f, 0.0021f, 0.0000f}, {0.0041f, 0.0015f, 0.0000f}, {0.0029f, 0.0010f, 0.0000f},
        {0.0020f, 0.0007f, 0.0000f}, {0.0014f, 0.0005f, 0.0000f}, {0.0010f, 0.0004f, 0.0000f},
        {0.0007f, 0.0002f, 0.0000f}, {0.0005f, 0.0002f, 0.0000f}, {0.0003f, 0.0001f, 0.0000f},
        {0.0002f, 0.0001f, 0.0000f}, {0.0002f, 0.0001f, 0.0000f}, {0.0001f, 0.0000f, 0.0000f},
        {0.0001f, 0.0000f, 0.0000f}, {0.0001f, 0.0000f, 0.0000f}, {0.0000f, 0.0000f, 0.0000f}};
    float x = (nm - 380.0f) * (1.0f / 5.0f);
    // Cycles' float_to_int truncates; a NaN or huge x gives a value outside [0, 80) there too.
    if (!(x > -1.0f && x < 80.0f)) return {};
    const int i = int(x);
    x -= float(i);
    const float* a = kCie[i];
    const float* b = kCie[i + 1];
    const Vec3f xyz((1.0f - x) * a[0] + x * b[0], (1.0f - x) * a[1] + x * b[1], (1.0f - x) * a[2] + x * b[2]);
    return MaxZero(XyzToRgb(xyz) * (1.0f / 2.52f));
}

// ---- RGB Curves, Vector Curves, Float Curve ------------------------------------------------------------------
// Cycles samples Blender's CurveMapping into a table of RAMP_TABLE_SIZE (256) entries over [min_x, max_x] (the
// range of every curve's points; for RGB Curves each entry is the channel curve applied to the combined curve) and
// looks a value up by linear interpolation, extending the end segments' slopes outside the range when the mapping
// extrapolates, else clamping (kernel/svm/ramp.h).  The exporter samples the table
// (color_node_params.curve_table).

inline constexpr int kCurveTableSize = 256;  // Cycles' RAMP_TABLE_SIZE

// A sampled curve: `size` entries of `stride` floats; channel c of entry i is values[i * stride + c].
struct CurveTable {
    const float* values = nullptr;
    int size = 0;
    int stride = 1;
    float min_x = 0, max_x = 1;
    bool extrapolate = true;
};

// Channel c of the table at f (the position relative to [min_x, max_x]), as rgb_ramp_lookup / float_ramp_lookup
// with interpolation.
inline float CurveLookup(const CurveTable& t, int c, float f) {
    const auto at = [&](int i) { return t.values[size_t(i) * size_t(t.stride) + size_t(c)]; };
    const int n = t.size;
    if ((f < 0.0f || f > 1.0f) && t.extrapolate) {
        float t0, dy;
        if (f < 0.0f) {
            t0 = at(0);
            dy = t0 - at(1);
            f = -f;
        } else {
            t0 = at(n - 1);
            dy = t0 - at(n - 2);
            f = f - 1.0f;
        }
        return t0 + dy * f * float(n - 1);
    }
    f = Saturate(f) * float(n - 1);
    const int i = std::clamp(f >= -2147483648.0f && f < 2147483648.0f ? int(f) : 0, 0, n - 1);
    const float u = f - float(i);
    float a = at(i);
    if (u > 0.0f) a = (1.0f - u) * a + u * at(i + 1);
    return a;
}

// RGB Curves and Vector Curves: each component through its channel of a 3-channel table, mixed with the input by
// fac (not clamped).
inline Vec3f CurvesRgb(const CurveTable& t, float fac, const Vec3f& color) {
    const float range = t.max_x - t.min_x;
    const Vec3f rel = (color - Vec3f(t.min_x, t.min_x, t.min_x)) / range;
    const Vec3f mapped(CurveLookup(t, 0, rel.x), CurveLookup(t, 1, rel.y), CurveLookup(t, 2, rel.z));
    return color * (1.0f - fac) + mapped * fac;
}

// Float Curve: the value through a 1-channel table, mixed by fac.
inline float CurveFloat(const CurveTable& t, float fac, float value) {
    const float rel = (value - t.min_x) / (t.max_x - t.min_x);
    return (1.0f - fac) * value + fac * CurveLookup(t, 0, rel);
}

// ---- Vector Math ---------------------------------------------------------------------------------------------

// Blender's operation identifiers (ShaderNodeVectorMath.operation), in this enum's order.
enum class VectorMathOp {
    kAdd,
    kSubtract,
    kMultiply,
    kDivide,
    kMultiplyAdd,
    kCrossProduct,
    kProject,
    kReflect,
    kRefract,
    kFaceforward,
    kDotProduct,
    kDistance,
    kLength,
    kScale,
    kNormalize,
    kAbsolute,
    kMinimum,
    kMaximum,
    kFloor,
    kCeil,
    kFraction,
    kModulo,
    kWrap,
    kSnap,
    kSine,
    kCosine,
    kTangent
};
inline constexpr const char* kVectorMathOpNames[] = {
    "ADD",       "SUBTRACT", "MULTIPLY",    "DIVIDE",      "MULTIPLY_ADD", "CROSS_PRODUCT", "PROJECT",
    "REFLECT",   "REFRACT",  "FACEFORWARD", "DOT_PRODUCT", "DISTANCE",     "LENGTH",        "SCALE",
    "NORMALIZE", "ABSOLUTE", "MINIMUM",     "MAXIMUM",     "FLOOR",        "CEIL",          "FRACTION",
    "MODULO",    "WRAP",     "SNAP",        "SINE",        "COSINE",       "TANGENT"};

// The operations whose result is the Value output (the others' is the Vector output; the unused output is 0).
inline bool VectorMathGivesValue(VectorMathOp op) {
    return op == VectorMathOp::kDotProduct || op == VectorMathOp::kDistance || op == VectorMathOp::kLength;
}

struct VectorMathResult {
    float value = 0;
    Vec3f vector;
};

inline Vec3f SafeNormalize(const Vec3f& a) {
    const float len = Length(a);
    return len != 0.0f ? a * (1.0f / len) : a;
}

// Vector Math with inputs a, b, c (Vector, Vector_001, Vector_002) and scale (Scale; refract's IOR).
inline VectorMathResult VectorMath(VectorMathOp op, const Vec3f& a, const Vec3f& b, const Vec3f& c, float scale) {
    const auto each = [](const Vec3f& v, auto f) { return Vec3f(f(v.x), f(v.y), f(v.z)); };
    VectorMathResult r;
    switch (op) {
        case VectorMathOp::kAdd: r.vector = a + b; break;
        case VectorMathOp::kSubtract: r.vector = a - b; break;
        case VectorMathOp::kMultiply: r.vector = a * b; break;
        case VectorMathOp::kDivide:
            r.vector = {SafeDivide(a.x, b.x), SafeDivide(a.y, b.y), SafeDivide(a.z, b.z)};
            break;
        case VectorMathOp::kMultiplyAdd: r.vector = a * b + c; break;
        case VectorMathOp::kCrossProduct: r.vector = Cross(a, b); break;
        case VectorMathOp::kProject: {
            const float len2 = Dot(b, b);
            r.vector = len2 != 0.0f ? b * (Dot(a, b) / len2) : Vec3f();
            break;
        }
        case VectorMathOp::kReflect: {
            const Vec3f n = Normalize(b);
            r.vector = a - n * (2.0f * Dot(a, n));
            break;
        }
        case VectorMathOp::kRefract: {
            const Vec3f n = Normalize(b);
            const float d = Dot(n, a), k = 1.0f - scale * scale * (1.0f - d * d);
            r.vector = k < 0.0f ? Vec3f() : a * scale - n * (scale * d + std::sqrt(k));
            break;
        }
        case VectorMathOp::kFaceforward: r.vector = Dot(c, b) < 0.0f ? a : -a; break;
        case VectorMathOp::kDotProduct: r.value = Dot(a, b); break;
        case VectorMathOp::kDistance: r.value = Length(a - b); break;
        case VectorMathOp::kLength: r.value = Length(a); break;
        case VectorMathOp::kScale: r.vector = a * scale; break;
        case VectorMathOp::kNormalize: r.vector = SafeNormalize(a); break;
        case VectorMathOp::kAbsolute: r.vector = each(a, [](float x) { return std::abs(x); }); break;
        case VectorMathOp::kMinimum: r.vector = {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; break;
        case VectorMathOp::kMaximum: r.vector = {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; break;
        case VectorMathOp::kFloor: r.vector = each(a, [](float x) { return std::floor(x); }); break;
        case VectorMathOp::kCeil: r.vector = each(a, [](float x) { return std::ceil(x); }); break;
        case VectorMathOp::kFraction: r.vector = a - each(a, [](float x) { return std::floor(x); }); break;
        case VectorMathOp::kModulo:
            r.vector = {SafeModulo(a.x, b.x), SafeModulo(a.y, b.y), SafeModulo(a.z, b.z)};
            break;
        case VectorMathOp::kWrap: r.vector = {Wrap(a.x, b.x, c.x), Wrap(a.y, b.y, c.y), Wrap(a.z, b.z, c.z)}; break;
        case VectorMathOp::kSnap:
            r.vector = Vec3f(std::floor(SafeDivide(a.x, b.x)), std::floor(SafeDivide(a.y, b.y)),
                             std::floor(SafeDivide(a.z, b.z))) *
                       b;
            break;
        case VectorMathOp::kSine: r.vector = each(a, [](float x) { return std::sin(x); }); break;
        case VectorMathOp::kCosine: r.vector = each(a, [](float x) { return std::cos(x); }); break;
        case VectorMathOp::kTangent: r.vector = each(a, [](float x) { return std::tan(x); }); break;
    }
    return r;
}

// ---- Vector Rotate -------------------------------------------------------------------------------------------

// Blender's rotation types (ShaderNodeVectorRotate.rotation_type), in this enum's order.
enum class VectorRotateType { kAxisAngle, kXAxis, kYAxis, kZAxis, kEulerXyz };
inline constexpr const char* kVectorRotateTypeNames[] = {"AXIS_ANGLE", "X_AXIS", "Y_AXIS", "Z_AXIS", "EULER_XYZ"};

// Rodrigues' rotation of p about the unit axis by angle (util/math.h rotate_around_axis, term for term).
inline Vec3f RotateAroundAxis(const Vec3f& p, const Vec3f& axis, float angle) {
    const float c = std::cos(angle), s = std::sin(angle), k = 1 - c;
    return {(c + k * axis.x * axis.x) * p.x + (k * axis.x * axis.y - axis.z * s) * p.y +
                (k * axis.x * axis.z + axis.y * s) * p.z,
            (k * axis.x * axis.y + axis.z * s) * p.x + (c + k * axis.y * axis.y) * p.y +
                (k * axis.y * axis.z - axis.x * s) * p.z,
            (k * axis.x * axis.z - axis.y * s) * p.x + (k * axis.y * axis.z + axis.x * s) * p.y +
                (c + k * axis.z * axis.z) * p.z};
}

// The rows of Cycles' euler_to_transform (rotation X, then Y, then Z).
inline void EulerXyzRows(const Vec3f& e, Vec3f rows[3]) {
    const float cx = std::cos(e.x), cy = std::cos(e.y), cz = std::cos(e.z);
    const float sx = std::sin(e.x), sy = std::sin(e.y), sz = std::sin(e.z);
    rows[0] = {cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz};
    rows[1] = {cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz};
    rows[2] = {-sy, cy * sx, cy * cx};
}

// Vector Rotate: v about center, by the Euler rotation (its transpose when inverted) or by angle (-angle when
// inverted) about an axis (the Axis input normalised; a zero axis leaves v unchanged).
inline Vec3f VectorRotate(VectorRotateType type, bool invert, const Vec3f& v, const Vec3f& center, const Vec3f& axis_in,
                          float angle, const Vec3f& rotation) {
    const Vec3f p = v - center;
    if (type == VectorRotateType::kEulerXyz) {
        Vec3f m[3];
        EulerXyzRows(rotation, m);
        const Vec3f r = invert ? m[0] * p.x + m[1] * p.y + m[2] * p.z : Vec3f(Dot(m[0], p), Dot(m[1], p), Dot(m[2], p));
        return r + center;
    }
    Vec3f axis = type == VectorRotateType::kXAxis   ? Vec3f(1, 0, 0)
                 : type == VectorRotateType::kYAxis ? Vec3f(0, 1, 0)
                 : type == VectorRotateType::kZAxis ? Vec3f(0, 0, 1)
                                                    : axis_in;
    const float len = type == VectorRotateType::kAxisAngle ? Length(axis) : 1.0f;
    if (len == 0.0f) return v;
    return RotateAroundAxis(p, axis / len, invert ? -angle : angle) + center;
}

// ---- Normal node -------------------------------------------------------------------------------------------------

// The Normal node's Normal output: its direction (the node's sphere widget) normalised.
inline Vec3f NormalNodeDirection(const Vec3f& direction) { return Normalize(direction); }

// Its Dot output: the normalised direction with the normalised Normal input.
inline float NormalNodeDot(const Vec3f& direction, const Vec3f& normal) {
    return Dot(Normalize(direction), Normalize(normal));
}

}  // namespace sphrect::render::svm
