// The two ways of choosing a scattering distance along a camera ray that the medium (medium.h) combines by
// MIS: distance (transmittance) sampling and equi-angular sampling (Kulla & Fajardo, "Importance Sampling
// Techniques for Path Tracing in Participating Media", EGSR 2012).
#pragma once

#include <cmath>

#include "sampling_util.h"

namespace sphrect::render {

// --- Distance sampling: t ~ sigma exp(-sigma t) on [0, infinity) -------------------------------

inline float SampleExponentialDistance(float sigma, float u) { return -std::log1p(-u) / sigma; }
inline float ExponentialDistancePDF(float sigma, float t) { return sigma * std::exp(-sigma * t); }

// --- Equi-angular sampling: t on [0, tmax] with density proportional to 1 / |x(t) - c|^2 -------

struct EquiAngular {
    float delta = 0;  // t of the point of the ray closest to the centre c
    float dist = 0;   // distance of c from the ray (D)
    float theta_a = 0, theta_b = 0;
    bool valid = false;  // false when c is on the ray (D = 0) or the segment is empty
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
