// Multiple-scattering GGX reflection (Heitz, Hanika, d'Eon, Dachsbacher, "Multiple-Scattering Microfacet BSDFs with
// the Smith Model", SIGGRAPH 2016), as Cycles 3.4 evaluates its Principled BSDF of distribution Multiscatter GGX
// (bsdf_microfacet_multi.h, bsdf_microfacet_multi_impl.h, the glossy "fresnel" variant): the single-scattering part
// analytically with the height-correlated G2, the higher orders by a random walk on the microsurface (its heights
// uniform, Smith's masking G1 = C1(h)^Lambda), each bounce after the first adding the light it sends towards the
// other direction.  The walk's estimate is unbiased, not exact; its random numbers come from a hash of the two
// directions, so one evaluation is a fixed function of them (MultiscatterGgxEval).  Quirks of Cycles kept so that the
// images agree: the colour of a bounce (its Fresnel) enters squared, the first bounce's Fresnel is that of the
// single-scattering half vector, at most 10 orders.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "principled_lobes.h"
#include "render/sampling_util.h"

namespace sphrect::render {

// Smith's Lambda of GGX for any direction (negative below the surface, where the walk goes on from; -0.9999 straight
// down, 0 straight up).
inline float WalkLambda(const Vec3f& w, float ax, float ay) {
    if (w.z > 0.9999f) return 0;
    if (w.z < -0.9999f) return -0.9999f;
    const float t = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / std::max(w.z * w.z, 1e-7f);
    const float v = std::sqrt(1 + t);
    return 0.5f * ((w.z <= 0 ? -v : v) - 1);
}

// The microsurface's height distribution: uniform on [-1, 1] (C1 its CDF, and the inverse).
inline float HeightCdf(float h) { return std::clamp(0.5f * (h + 1), 0.0f, 1.0f); }
inline float HeightOfCdf(float c) { return 2 * std::clamp(c, 0.0f, 1.0f) - 1; }

// Masking of direction w from a point whose height has CDF c: c^Lambda (1 straight up, 0 at the horizon and below).
inline float HeightMasking(const Vec3f& w, float c, float lambda) {
    if (w.z > 0.9999f) return 1;
    if (w.z < 1e-5f) return 0;
    return std::pow(c, lambda);
}

// The next height the walk along w meets the microsurface at, from the state (h, c = C1(h), g1 = the masking there,
// lambda of w); false when the ray escapes.
inline bool NextWalkHeight(const Vec3f& w, float& h, float& c, float& g1, float lambda, float u) {
    if (w.z > 0.9999f) return false;
    if (w.z < -0.9999f) {
        c *= u;
        h = HeightOfCdf(c);
        g1 = HeightMasking(w, c, lambda);
    } else if (std::abs(w.z) >= 1e-4f) {
        if (u > 1 - g1) return false;
        c = lambda >= 0 ? 1.0f : c * std::pow(1 - u, -1 / lambda);
        h = HeightOfCdf(c);
        g1 = HeightMasking(w, c, lambda);
    }
    return true;
}

// Visible slopes of the unit-roughness GGX for incidence cos_i of any sign (Heitz and d'Eon 2014, the sampling of the
// multiple-scattering paper's supplemental code): the x slope exactly, the y slope by its rational approximation.
inline Point2<float> SampleVisibleSlopeGgx(float cos_i, float u1, float u2) {
    if (cos_i > 0.9999f || std::abs(cos_i) < 1e-6f) {
        const float r = std::sqrt(u1 / std::max(1 - u1, 1e-7f)), phi = 2 * kPi * u2;
        return {r * std::cos(phi), r * std::sin(phi)};
    }
    const float sin_i = SafeSqrt(1 - cos_i * cos_i), tan_i = sin_i / cos_i;
    const float projected_area = 0.5f * (cos_i + 1);
    if (projected_area < 1e-4f) return {0, 0};
    const float a = 2 * u1 * projected_area / cos_i - 1;
    float inv = a * a - 1;
    if (std::abs(inv) < 1e-7f) return {0, 0};
    inv = 1 / inv;
    const float d = SafeSqrt(tan_i * tan_i * inv * inv - (a * a - tan_i * tan_i) * inv);
    const float x_plus = tan_i * inv + d;
    const float slope_x = (a < 0 || x_plus > 1 / tan_i) ? tan_i * inv - d : x_plus;
    const float s = u2 >= 0.5f ? 1.0f : -1.0f;
    const float v = u2 >= 0.5f ? 2 * (u2 - 0.5f) : 2 * (0.5f - u2);
    const float z =
        (v * (v * (v * 0.27385f - 0.73369f) + 0.46341f)) / (v * (v * (v * 0.093073f + 0.309420f) - 1) + 0.597999f);
    return {slope_x, s * z * std::sqrt(1 + slope_x * slope_x)};
}

// A microfacet normal visible from w (any hemisphere), roughness (ax, ay).
inline Vec3f SampleWalkNormal(const Vec3f& w, float ax, float ay, float u1, float u2) {
    const Vec3f w11 = Normalize(Vec3f(ax * w.x, ay * w.y, w.z));
    const Point2<float> slope = SampleVisibleSlopeGgx(w11.z, u1, u2);
    const float len = std::sqrt(w11.x * w11.x + w11.y * w11.y);
    const float c = len > 0 ? w11.x / len : 1.0f, s = len > 0 ? w11.y / len : 0.0f;
    const float sx = ax * (c * slope.u - s * slope.v), sy = ay * (s * slope.u + c * slope.v);
    return Normalize(Vec3f(-sx, -sy, 1));
}

// The share of light arriving along w (lambda its Lambda) that a microfacet reflects towards wo.
inline float WalkReflectionPhase(const Vec3f& w, float lambda, const Vec3f& wo, float ax, float ay) {
    if (w.z > 0.9999f) return 0;
    const Vec3f h = Normalize(wo - w);
    if (h.z < 0) return 0;
    const float projected = w.z < -0.9999f ? 1.0f : lambda * w.z;
    const float cos_wh = -Dot(w, h);
    if (cos_wh < 0) return 0;
    return cos_wh * 0.25f / std::max(projected * cos_wh, 1e-7f) * GgxAnisotropicD(h, ax, ay);
}

// A 64-bit hash of two directions' bits: the walk's seed.
inline uint64_t HashDirections(const Vec3f& a, const Vec3f& b) {
    uint32_t bits[6];
    std::memcpy(&bits[0], &a, sizeof(float) * 3);
    std::memcpy(&bits[3], &b, sizeof(float) * 3);
    uint64_t x = 0x9e3779b97f4a7c15ull;
    for (uint32_t v : bits) {
        x ^= v + 0x9e3779b97f4a7c15ull + (x << 6) + (x >> 2);
        x *= 0xbf58476d1ce4e5b9ull;
        x ^= x >> 31;
    }
    return x;
}

// f (not f cos) of the multiple-scattering GGX with Cycles' Fresnel blend, for view wo and light wi (shading frame,
// in the lobe's tangent frame when ax != ay): an estimate by the walk.  Cycles' evaluation (light samples) starts it
// from the shallower direction, its sampling from the view; with this walk the two differ (upward rays that meet the
// surface again restart at the top height), by up to 10% in albedo at roughness 1 (a white furnace: 0.91 against
// 1.00 from the view at cos 0.8), and Cycles' image mixes them by its MIS weights.  from_view: a BSDF sample's (the
// sampling walk's side of that mix).
// eta > 0: the Principled BSDF's variant (Fresnel blend of cspec0 at each bounce); eta = 0: the Glossy and Anisotropic
// BSDF's, whose `color` tints each bounce instead (the caller multiplies by it once more: it is the closure's weight).
inline Spectrum MultiscatterGgxEval(const Vec3f& wo, const Vec3f& wi, float ax, float ay, float eta,
                                    const Spectrum& cspec0, bool from_view = false, const Spectrum& color = {}) {
    const bool fresnel = eta > 0;
    Vec3f start = wo, exit = wi;  // Cycles' wi, wo
    if (!from_view && exit.z < start.z) std::swap(start, exit);
    if (start.z < 1e-5f || exit.z < 1e-5f) return {};
    float lambda_r = WalkLambda(-start, ax, ay);
    const float exit_lambda = WalkLambda(exit, ax, ay);
    const Vec3f h = Normalize(start + exit);
    const float f0 = fresnel ? DielectricFresnel(1, eta) : 0.0f;
    // Single scattering, with the height-correlated G2 = 1 / (1 + Lambda(start) + Lambda(exit)); f cos(exit).
    Spectrum throughput = fresnel ? InterpolatedFresnel(Dot(start, h), eta, f0, cspec0) : Spectrum(1, 1, 1);
    Spectrum eval = throughput * (GgxAnisotropicD(h, ax, ay) * 0.25f / (start.z * (-lambda_r + exit_lambda)));
    uint64_t state = HashDirections(wo, wi);
    auto uniform = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(uint32_t(state >> 40)) * 0x1p-24f;
    };
    Vec3f wr = -start;
    float hr = 1, c1 = 1, g1 = 0;
    constexpr int kOrders = 10;
    for (int order = 0; order < kOrders; ++order) {
        if (!NextWalkHeight(wr, hr, c1, g1, lambda_r, uniform())) break;
        const float uy = uniform(), ux = uniform();
        const Vec3f m = SampleWalkNormal(-wr, ax, ay, ux, uy);
        if (order > 0) {
            const float phase = WalkReflectionPhase(wr, lambda_r, exit, ax, ay);
            eval += throughput * throughput * (phase * HeightMasking(exit, HeightCdf(hr), exit_lambda));
        }
        if (order + 1 < kOrders) {
            if (fresnel && order > 0) throughput = throughput * InterpolatedFresnel(Dot(-wr, m), eta, f0, cspec0);
            wr = wr - m * (2 * Dot(wr, m));
            if (!fresnel) throughput = throughput * color;
            lambda_r = WalkLambda(wr, ax, ay);
            c1 = HeightCdf(hr);
            g1 = HeightMasking(wr, c1, lambda_r);
        }
    }
    return eval / exit.z;
}

}  // namespace sphrect::render
