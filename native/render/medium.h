// Homogeneous participating medium filling the scene: transmittance, Henyey-Greenstein phase
// function, and the two ways of choosing a scattering distance along a camera ray that are
// combined by MIS -- distance (transmittance) sampling and equi-angular sampling (Kulla &
// Fajardo, "Importance Sampling Techniques for Path Tracing in Participating Media", EGSR 2012).
#pragma once

#include <array>
#include <cmath>

#include "sampling_util.h"

namespace sphrect::render {

struct HomogeneousMedium {
    Spectrum sigma_s, sigma_t;  // scattering and extinction (= scattering + absorption), 1/m
    float g = 0;                // Henyey-Greenstein anisotropy, in (-1, 1)
    float sigma_sampling = 0;   // extinction used by distance sampling: mean of sigma_t's channels
};

// exp(-sigma_t d) per channel; a channel with sigma_t = 0 is 1 even at d = infinity.
inline Spectrum Transmittance(const HomogeneousMedium& m, float d) {
    auto tr = [d](float s) { return s > 0 ? std::exp(-s * d) : 1.0f; };
    return {tr(m.sigma_t.x), tr(m.sigma_t.y), tr(m.sigma_t.z)};
}

// Transmittance along a segment of length d in a kernel compiled with a medium (kMedium), or 1.
template <bool kMedium>
inline Spectrum SegmentTransmittance(const HomogeneousMedium& m, float d) {
    if constexpr (kMedium) return Transmittance(m, d);
    return {1, 1, 1};
}

// p(cos theta) with cos theta = dot(wi, d), wi pointing to the light and d the camera ray's
// direction: light travelling along -wi is scattered into -d (towards the camera), so the
// scattering angle's cosine is dot(-wi, -d).  g > 0 favours wi ~ d (forward scattering).
inline float HenyeyGreenstein(float cos_theta, float g) {
    const float denom = 1 + g * g - 2 * g * cos_theta;
    return (1 - g * g) / (4 * kPi * denom * std::sqrt(denom));
}

// Direction wi with density HenyeyGreenstein(dot(wi, axis), g) (inverse of its cdf in cos theta).
inline Vec3f SampleHenyeyGreenstein(const Vec3f& axis, float g, Point2<float> u) {
    float cos_theta;
    if (std::abs(g) < 1e-3f) {
        cos_theta = 1 - 2 * u.u;
    } else {
        const float q = (1 - g * g) / (1 - g + 2 * g * u.u);
        cos_theta = (1 + g * g - q * q) / (2 * g);
    }
    cos_theta = std::clamp(cos_theta, -1.0f, 1.0f);
    const float sin_theta = SafeSqrt(1 - cos_theta * cos_theta), phi = 2 * kPi * u.v;
    return Frame::FromZ(axis).FromLocal({sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta});
}

// How the scattering distance along a camera ray is chosen: both strategies below combined by
// MIS, or one of them alone.
enum class MediumSampling { Mis, Distance, EquiAngular };

constexpr std::array<MediumSampling, 3> kAllMediumSamplings = {MediumSampling::Mis, MediumSampling::Distance,
                                                               MediumSampling::EquiAngular};

constexpr const char* MediumSamplingName(MediumSampling m) {
    switch (m) {
        case MediumSampling::Mis: return "mis";
        case MediumSampling::Distance: return "distance";
        case MediumSampling::EquiAngular: return "equiangular";
    }
    return "?";
}

// --- Distance sampling: t ~ sigma exp(-sigma t) on [0, infinity) -------------------------------

inline float SampleExponentialDistance(float sigma, float u) { return -std::log1p(-u) / sigma; }
inline float ExponentialDistancePDF(float sigma, float t) { return sigma * std::exp(-sigma * t); }

// --- Equi-angular sampling: t on [0, tmax] with density proportional to 1 / |x(t) - c|^2 -------

struct EquiAngular {
    float delta = 0;           // t of the point of the ray closest to the centre c
    float dist = 0;            // distance of c from the ray (D)
    float theta_a = 0, theta_b = 0;
    bool valid = false;        // false when c is on the ray (D = 0) or the segment is empty
};

inline EquiAngular MakeEquiAngular(const Vec3f& o, const Vec3f& d, float tmax, const Vec3f& c) {
    EquiAngular e;
    e.delta = Dot(c - o, d);
    e.dist = Length(o + d * e.delta - c);
    if (!(e.dist > 1e-7f * (1 + MaxAbsComponent(c))) || !(tmax > 0)) return e;
    e.theta_a = std::atan2(-e.delta, e.dist);
    e.theta_b = std::isinf(tmax) ? kPi / 2 : std::atan2(tmax - e.delta, e.dist);
    e.valid = e.theta_b > e.theta_a;
    return e;
}

inline float SampleEquiAngular(const EquiAngular& e, float u) {
    return e.delta + e.dist * std::tan(e.theta_a + u * (e.theta_b - e.theta_a));
}

inline float EquiAngularPDF(const EquiAngular& e, float t) {
    if (!e.valid) return 0;
    const float x = t - e.delta;
    return e.dist / ((e.theta_b - e.theta_a) * (e.dist * e.dist + x * x));
}

}  // namespace sphrect::render
