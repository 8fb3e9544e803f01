// Uniform sampling of a cone of directions by solid angle (pbrt-v4's SampleUniformCone,
// UniformConePDF, InvertUniformConeSample), in the cone's frame: axis +z, half-angle theta_max.
//
// The cone is given by one_minus_cos = 1 - cos(theta_max) rather than by the cosine, so that
// narrow cones keep their solid angle: a sun of angular diameter 1e-4 rad has
// 1 - cos = 1.25e-9, which a float cosine rounds to 0.  Samples use the same variable:
// 1 - cos(theta) = u0 (1 - cos(theta_max)), sin^2(theta) = (1 - cos)(1 + cos).
#pragma once

#include <algorithm>
#include <cmath>

#include "vec3.h"

namespace sphrect {

// 1 - cos(theta) of two unit vectors a, b without cancellation: |a - b|^2 / 2.
template <class T>
inline T OneMinusCosBetween(const Vec3<T>& a, const Vec3<T>& b) {
    const Vec3<T> d = a - b;
    return Dot(d, d) / 2;
}

// 1 - cos(atan(r / d)) = r^2 / (h (h + d)), h = sqrt(d^2 + r^2): the cone that a disc of radius r,
// facing the viewpoint at distance d > 0 on its axis, subtends.
template <class T>
inline T OneMinusCosOfDisc(T r, T d) {
    const T h = std::sqrt(d * d + r * r);
    return r * r / (h * (h + d));
}

// Solid angle 2 pi (1 - cos(theta_max)).
template <class T>
inline T UniformConeSolidAngle(T one_minus_cos) {
    return T(2 * 3.14159265358979323846) * one_minus_cos;
}

template <class T>
inline T UniformConePDF(T one_minus_cos) {
    return 1 / UniformConeSolidAngle(one_minus_cos);
}

// The direction (unit, cone frame) of the point u in [0,1)^2: 1 - cos(theta) = u.u one_minus_cos,
// phi = 2 pi u.v.
template <class T>
inline Vec3<T> SampleUniformCone(Point2<T> u, T one_minus_cos) {
    const T x = std::min(u.u * one_minus_cos, T(2));  // 1 - cos(theta)
    const T sin_theta = std::sqrt(std::max(T(0), x * (2 - x)));
    const T phi = T(2 * 3.14159265358979323846) * u.v;
    return {std::cos(phi) * sin_theta, std::sin(phi) * sin_theta, 1 - x};
}

// The point u that SampleUniformCone maps to the unit direction w (cone frame); u.u > 1 when w lies
// outside the cone.
template <class T>
inline Point2<T> InvertUniformConeSample(const Vec3<T>& w, T one_minus_cos) {
    const T sin2 = w.x * w.x + w.y * w.y;
    const T x = w.z >= 0 ? sin2 / (1 + w.z) : 1 - w.z;  // 1 - cos(theta), without cancellation near the axis
    T phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += T(2 * 3.14159265358979323846);
    return {x / one_minus_cos, std::min(phi / T(2 * 3.14159265358979323846), std::nextafter(T(1), T(0)))};
}

}  // namespace sphrect
