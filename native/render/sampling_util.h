// Small geometric helpers shared by the renderer: RGB, orthonormal frames and the
// standard warps of [0,1)^2 (pbrt-v4, "Sampling Algorithms").
#pragma once

#include <algorithm>
#include <cmath>

#include "core/light_sample.h"
#include "core/vec3.h"

namespace sphrect::render {

using Spectrum = Vec3f;  // linear RGB

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInf = INFINITY;

inline float Luminance(const Spectrum& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline float Average(const Spectrum& c) { return (c.x + c.y + c.z) / 3; }  // Cycles' average(): weights, alpha
inline bool IsBlack(const Spectrum& c) { return c.x == 0 && c.y == 0 && c.z == 0; }
inline float MaxAbsComponent(const Vec3f& v) { return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z))); }

// Orthonormal basis around a unit vector n (Duff et al., "Building an Orthonormal Basis, Revisited", 2017).
// The changes of basis are always inlined: called out of line from the shading steps, their
// calls cost a measurable share of a render (docs/architecture.md, measured choices).
struct Frame {
    Vec3f s, t, n;
    static Frame FromZ(const Vec3f& n) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z), b = n.x * n.y * a;
        return {{1 + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
    }
    [[gnu::always_inline]] Vec3f ToLocal(const Vec3f& v) const { return {Dot(v, s), Dot(v, t), Dot(v, n)}; }
    [[gnu::always_inline]] Vec3f FromLocal(const Vec3f& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Shirley-Chiu concentric map of the square onto the unit disc (area preserving, low distortion).
inline Point2<float> SampleUniformDiskConcentric(Point2<float> u) {
    const float x = 2 * u.u - 1, y = 2 * u.v - 1;
    if (x == 0 && y == 0) return {0, 0};
    float r, theta;
    if (std::abs(x) > std::abs(y)) {
        r = x;
        theta = (kPi / 4) * (y / x);
    } else {
        r = y;
        theta = kPi / 2 - (kPi / 4) * (x / y);
    }
    return {r * std::cos(theta), r * std::sin(theta)};
}

// Malley's method: project the concentric disc onto the hemisphere; pdf = cos(theta) / pi.
inline Vec3f SampleCosineHemisphere(Point2<float> u) {
    const Point2<float> d = SampleUniformDiskConcentric(u);
    const float z = std::sqrt(std::max(0.0f, 1 - d.u * d.u - d.v * d.v));
    return {d.u, d.v, z};
}
inline float CosineHemispherePDF(float cos_theta) { return std::max(cos_theta, 0.0f) * kInvPi; }

inline float SafeSqrt(float x) { return std::sqrt(std::max(0.0f, x)); }

}  // namespace sphrect::render
