// Ellipse technique `area`: uniform over the ellipse's area through Shirley & Chiu's concentric
// map of the square onto the disk (as the renderer's SampleEllipseArea), pdf converted to solid
// angle, p(w) = d^3 / (pi a b h).  The baseline, and what `spherical_ellipse` falls back to where
// its map cannot resolve (u, v).
#pragma once

#include <cmath>

#include "ellipse_light.h"

namespace sphrect {

constexpr double kEllipsePi = 3.14159265358979323846;

// Shirley & Chiu's concentric map, [0,1]^2 -> unit disk (continuous, area-preserving).
inline Point2<double> ConcentricDisk(double u, double v) {
    const double x = 2 * ClampNaN(u, 0, 1) - 1, y = 2 * ClampNaN(v, 0, 1) - 1;
    if (x == 0 && y == 0) return {0, 0};
    if (std::abs(x) > std::abs(y)) {
        const double phi = (kEllipsePi / 4) * (y / x);
        return {x * std::cos(phi), x * std::sin(phi)};
    }
    const double phi = kEllipsePi / 2 - (kEllipsePi / 4) * (x / y);
    return {y * std::cos(phi), y * std::sin(phi)};
}

// Its inverse: a point of the unit disk -> [0,1]^2.
inline Point2<double> InvertConcentricDisk(double p, double q) {
    const double r = std::hypot(p, q);
    if (!(r > 0)) return {0.5, 0.5};
    double x, y;
    if (std::abs(p) >= std::abs(q)) {  // |phi| <= pi/4 around +-x: r = x
        x = p >= 0 ? r : -r;
        y = x * std::atan(q / p) * (4 / kEllipsePi);
    } else {  // phi in [pi/4, 3pi/4] (mirrored below): r = y
        y = q >= 0 ? r : -r;
        const double phi = std::atan2(q / y, p / y);
        x = (kEllipsePi / 2 - phi) * y * (4 / kEllipsePi);
    }
    return {ClampNaN(0.5 * (x + 1), 0, 1), ClampNaN(0.5 * (y + 1), 0, 1)};
}

// Solid-angle pdf of the point p on the light; 0 for an invalid setup or where not representable.
template <class T>
T EllipseAreaPDF(const LocalEllipse<T>& r, const Vec3<T>& p) {
    if (!r.valid) return 0;
    const Point2<double> e = EllipseOffsets(r, p);
    return EllipseAreaPDFLocal(r, r.cx + e.u, r.cy + e.v);
}

// The sample at center + p axis_u + q axis_v with the area pdf of the point returned (rounded to
// T): EllipseAreaPDF of that point, bit for bit.
template <class T>
LightSample<T> EllipseAreaSampleAt(const LocalEllipse<T>& r, double p, double q) {
    LightSample<T> s = EllipseSampleAt(r, p, q, T(0));
    s.pdf = EllipseAreaPDF(r, s.point);
    return s;
}

template <class T>
LightSample<T> SampleEllipseAreaAt(const LocalEllipse<T>& r, double u, double v) {
    if (!r.valid) return {};
    const Point2<double> d = ConcentricDisk(u, v);
    return EllipseAreaSampleAt(r, d.u, d.v);
}

template <class T>
LightSample<T> SampleEllipseArea(const LocalEllipse<T>& r, Point2<T> uv) {
    return SampleEllipseAreaAt(r, double(uv.u), double(uv.v));
}

// Inverse of the area map: point on the light -> (u, v).
template <class T>
Point2<double> InvertEllipseArea(const LocalEllipse<T>& r, const Vec3<T>& p) {
    const Point2<double> e = EllipseOffsets(r, p);
    double pu = e.u / r.a, pv = e.v / r.b;
    ClampToUnitDisk(pu, pv);
    return InvertConcentricDisk(pu, pv);
}

}  // namespace sphrect
