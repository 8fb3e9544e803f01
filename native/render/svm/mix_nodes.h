// Colour converter nodes as Cycles 3.4 computes them (kernel/svm/color_util.h, util/color.h, invert.h): the Mix
// node's blend modes (Mix RGB, and the Mix node of type Color), Invert, and the RGB <-> HSV / HSL conversions that
// Separate / Combine Color use.  Pure functions of float3s.
#pragma once

#include <algorithm>
#include <cmath>

#include "render/sampling_util.h"

namespace sphrect::render::svm {

// The blend modes, Blender's identifiers (blend_type), in kMixBlendNames' order.
enum class MixBlend : uint8_t {
    kMix,
    kAdd,
    kMultiply,
    kSubtract,
    kScreen,
    kDivide,
    kDifference,
    kDarken,
    kLighten,
    kOverlay,
    kDodge,
    kBurn,
    kHue,
    kSaturation,
    kValue,
    kColor,
    kSoftLight,
    kLinearLight,
    kCount
};
constexpr const char* kMixBlendNames[] = {
    "MIX",     "ADD",   "MULTIPLY", "SUBTRACT", "SCREEN",     "DIVIDE", "DIFFERENCE", "DARKEN",     "LIGHTEN",
    "OVERLAY", "DODGE", "BURN",     "HUE",      "SATURATION", "VALUE",  "COLOR",      "SOFT_LIGHT", "LINEAR_LIGHT"};
static_assert(sizeof(kMixBlendNames) / sizeof(*kMixBlendNames) == size_t(MixBlend::kCount));

// The colour models of Separate / Combine Color (Separate / Combine RGB and XYZ are 'RGB').
enum class ColorModel : uint8_t { kRgb, kHsv, kHsl, kCount };
constexpr const char* kColorModelNames[] = {"RGB", "HSV", "HSL"};

inline Vec3f Lerp3(const Vec3f& a, const Vec3f& b, float t) { return a * (1.0f - t) + b * t; }
inline Vec3f Min3(const Vec3f& a, const Vec3f& b) {
    return {std::fmin(a.x, b.x), std::fmin(a.y, b.y), std::fmin(a.z, b.z)};
}
inline Vec3f Max3(const Vec3f& a, const Vec3f& b) {
    return {std::fmax(a.x, b.x), std::fmax(a.y, b.y), std::fmax(a.z, b.z)};
}
inline Vec3f Saturate3(const Vec3f& c) {
    return {std::clamp(c.x, 0.0f, 1.0f), std::clamp(c.y, 0.0f, 1.0f), std::clamp(c.z, 0.0f, 1.0f)};
}

inline Vec3f RgbToHsv(const Vec3f& rgb) {
    const float cmax = std::fmax(rgb.x, std::fmax(rgb.y, rgb.z));
    const float cmin = std::min(rgb.x, std::min(rgb.y, rgb.z));
    const float cdelta = cmax - cmin;
    const float s = cmax != 0.0f ? cdelta / cmax : 0.0f;
    float h = 0.0f;
    if (s != 0.0f) {
        const Vec3f c = (Vec3f(cmax, cmax, cmax) - rgb) / cdelta;
        if (rgb.x == cmax)
            h = c.z - c.y;
        else if (rgb.y == cmax)
            h = 2.0f + c.x - c.z;
        else
            h = 4.0f + c.y - c.x;
        h /= 6.0f;
        if (h < 0.0f) h += 1.0f;
    }
    return {h, s, cmax};
}

inline Vec3f HsvToRgb(const Vec3f& hsv) {
    float h = hsv.x;
    const float s = hsv.y, v = hsv.z;
    if (s == 0.0f) return {v, v, v};
    if (h == 1.0f) h = 0.0f;
    h *= 6.0f;
    const float i = std::floor(h), f = h - i;
    const float p = v * (1.0f - s), q = v * (1.0f - s * f), t = v * (1.0f - s * (1.0f - f));
    if (i == 0.0f) return {v, t, p};
    if (i == 1.0f) return {q, v, p};
    if (i == 2.0f) return {p, v, t};
    if (i == 3.0f) return {p, q, v};
    if (i == 4.0f) return {t, p, v};
    return {v, p, q};
}

inline Vec3f RgbToHsl(const Vec3f& rgb) {
    const float cmax = std::fmax(rgb.x, std::fmax(rgb.y, rgb.z));
    const float cmin = std::min(rgb.x, std::min(rgb.y, rgb.z));
    const float l = std::min(1.0f, (cmax + cmin) / 2.0f);
    float h = 0.0f, s = 0.0f;
    if (cmax != cmin) {
        const float cdelta = cmax - cmin;
        s = l > 0.5f ? cdelta / (2.0f - cmax - cmin) : cdelta / (cmax + cmin);
        if (cmax == rgb.x)
            h = (rgb.y - rgb.z) / cdelta + (rgb.y < rgb.z ? 6.0f : 0.0f);
        else if (cmax == rgb.y)
            h = (rgb.z - rgb.x) / cdelta + 2.0f;
        else
            h = (rgb.x - rgb.y) / cdelta + 4.0f;
    }
    return {h / 6.0f, s, l};
}

inline Vec3f HslToRgb(const Vec3f& hsl) {
    const float h = hsl.x, s = hsl.y, l = hsl.z;
    const float nr = std::clamp(std::fabs(h * 6.0f - 3.0f) - 1.0f, 0.0f, 1.0f);
    const float ng = std::clamp(2.0f - std::fabs(h * 6.0f - 2.0f), 0.0f, 1.0f);
    const float nb = std::clamp(2.0f - std::fabs(h * 6.0f - 4.0f), 0.0f, 1.0f);
    const float chroma = (1.0f - std::fabs(2.0f * l - 1.0f)) * s;
    return {(nr - 0.5f) * chroma + l, (ng - 0.5f) * chroma + l, (nb - 0.5f) * chroma + l};
}

inline Vec3f ToColorModel(ColorModel m, const Vec3f& rgb) {
    return m == ColorModel::kHsv ? RgbToHsv(rgb) : (m == ColorModel::kHsl ? RgbToHsl(rgb) : rgb);
}
inline Vec3f FromColorModel(ColorModel m, const Vec3f& c) {
    return m == ColorModel::kHsv ? HsvToRgb(c) : (m == ColorModel::kHsl ? HslToRgb(c) : c);
}

namespace mix_detail {

inline float Overlay(float a, float b, float t) {
    const float tm = 1.0f - t;
    return a < 0.5f ? a * (tm + 2.0f * t * b) : 1.0f - (tm + 2.0f * t * (1.0f - b)) * (1.0f - a);
}
inline float Divide(float a, float b, float t) { return b != 0.0f ? (1.0f - t) * a + t * a / b : a; }
inline float Dodge(float a, float b, float t) {
    if (a == 0.0f) return a;
    float tmp = 1.0f - t * b;
    if (tmp <= 0.0f) return 1.0f;
    tmp = a / tmp;
    return tmp > 1.0f ? 1.0f : tmp;
}
inline float Burn(float a, float b, float t) {
    float tmp = (1.0f - t) + t * b;
    if (tmp <= 0.0f) return 0.0f;
    tmp = 1.0f - (1.0f - a) / tmp;
    return tmp < 0.0f ? 0.0f : (tmp > 1.0f ? 1.0f : tmp);
}
template <typename F>
Vec3f PerChannel(const Vec3f& a, const Vec3f& b, float t, F f) {
    return {f(a.x, b.x, t), f(a.y, b.y, t), f(a.z, b.z, t)};
}

}  // namespace mix_detail

// svm_mix: colour a blended with colour b by factor t (not clamped here).
inline Vec3f EvalMixColor(MixBlend blend, float t, const Vec3f& a, const Vec3f& b) {
    using namespace mix_detail;
    const Vec3f one(1, 1, 1);
    switch (blend) {
        case MixBlend::kMix: return Lerp3(a, b, t);
        case MixBlend::kAdd: return Lerp3(a, a + b, t);
        case MixBlend::kMultiply: return Lerp3(a, a * b, t);
        case MixBlend::kSubtract: return Lerp3(a, a - b, t);
        case MixBlend::kScreen: {
            const float tm = 1.0f - t;
            return one - (Vec3f(tm, tm, tm) + (one - b) * t) * (one - a);
        }
        case MixBlend::kDivide: return PerChannel(a, b, t, Divide);
        case MixBlend::kDifference: {
            const Vec3f d = a - b;
            return Lerp3(a, Vec3f(std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)), t);
        }
        case MixBlend::kDarken: return Lerp3(a, Min3(a, b), t);
        case MixBlend::kLighten: return Lerp3(a, Max3(a, b), t);
        case MixBlend::kOverlay: return PerChannel(a, b, t, Overlay);
        case MixBlend::kDodge: return PerChannel(a, b, t, Dodge);
        case MixBlend::kBurn: return PerChannel(a, b, t, Burn);
        case MixBlend::kHue: {
            const Vec3f hsv2 = RgbToHsv(b);
            if (hsv2.y == 0.0f) return a;
            Vec3f hsv = RgbToHsv(a);
            hsv.x = hsv2.x;
            return Lerp3(a, HsvToRgb(hsv), t);
        }
        case MixBlend::kSaturation: {
            Vec3f hsv = RgbToHsv(a);
            if (hsv.y == 0.0f) return a;
            hsv.y = (1.0f - t) * hsv.y + t * RgbToHsv(b).y;
            return HsvToRgb(hsv);
        }
        case MixBlend::kValue: {
            Vec3f hsv = RgbToHsv(a);
            hsv.z = (1.0f - t) * hsv.z + t * RgbToHsv(b).z;
            return HsvToRgb(hsv);
        }
        case MixBlend::kColor: {
            const Vec3f hsv2 = RgbToHsv(b);
            if (hsv2.y == 0.0f) return a;
            Vec3f hsv = RgbToHsv(a);
            hsv.x = hsv2.x;
            hsv.y = hsv2.y;
            return Lerp3(a, HsvToRgb(hsv), t);
        }
        case MixBlend::kSoftLight: {
            const Vec3f scr = one - (one - b) * (one - a);
            return a * (1.0f - t) + ((one - a) * b * a + a * scr) * t;
        }
        case MixBlend::kLinearLight: return a + (b * 2.0f - one) * t;
        case MixBlend::kCount: break;
    }
    return {};
}

// The Invert node: each channel mixed with its complement by factor fac.
inline Vec3f EvalInvert(float fac, const Vec3f& c) { return Lerp3(c, Vec3f(1, 1, 1) - c, fac); }

}  // namespace sphrect::render::svm
