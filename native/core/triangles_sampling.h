// Technique `triangles`: the paper's baseline.  The rectangle is split along the
// diagonal corner -> corner + ex + ey into two spherical triangles, each sampled
// with Arvo's map (spherical_triangle.h).  The triangle is chosen with probability
// proportional to its solid angle by remapping u, so that one (u, v) makes one
// sample: u < P1 -> triangle 1 with u / P1, else triangle 2 with (u - P1) / (1 - P1).
// The density is 1 / Omega on the whole rectangle.
//
// Robustness: setup and map in double.  Arvo's closed form for the sub-triangle
// loses u when a triangle's solid angle is tiny (the angle sum ~ pi swamps it), so
// below kTwoTrianglesMinSolidAngle (decided once per setup, as for `rectangle`) the
// technique samples the area uniformly and returns that true pdf.
#pragma once

#include <algorithm>
#include <cmath>

#include "area_sampling.h"
#include "light_sample.h"
#include "rect_light.h"
#include "spherical_rectangle.h"
#include "spherical_triangle.h"

namespace sphrect {

constexpr double kTwoTrianglesMinSolidAngle = 1e-7;

template <class T>
struct TwoTriangles {
    AreaRect<T> plane;  // frame around o, and the fallback's area map
    SphericalTriangle tri[2];
    double p1 = 0;      // probability of the first triangle
    double omega = 0;
    T pdf = 0;
    bool valid = false;
    bool area_fallback = false;
};

template <class T>
TwoTriangles<T> MakeTwoTriangles(const Vec3<T>& origin, const RectLight<T>& light) {
    TwoTriangles<T> r;
    r.plane = MakeAreaRect(origin, light);
    const AreaRect<T>& p = r.plane;
    if (!p.valid) return r;
    // Corners relative to o from the local coordinates (no cancellation for o near the plane).
    auto corner = [&](int i, int j) { return p.exh * (p.x0 + i * p.wx) + p.eyh * (p.y0 + j * p.wy) + p.az * p.h; };
    const Vec3d c00 = corner(0, 0), c10 = corner(1, 0), c11 = corner(1, 1), c01 = corner(0, 1);
    r.tri[0] = MakeSphericalTriangle(c00, c10, c11);
    r.tri[1] = MakeSphericalTriangle(c00, c11, c01);
    r.omega = srect::RectSolidAngleLocal(p.x0, p.wx, p.y0, p.wy, p.h);
    r.pdf = T(1 / r.omega);
    if (!(r.omega > 0) || !(T(r.omega) > 0) || !std::isfinite(r.pdf)) return r;
    r.valid = true;
    r.p1 = r.tri[0].area / (r.tri[0].area + r.tri[1].area);
    r.area_fallback = !(std::min(r.tri[0].area, r.tri[1].area) >= kTwoTrianglesMinSolidAngle);
    return r;
}

template <class T>
LightSample<T> SampleTwoTriangles(const TwoTriangles<T>& r, Point2<T> uv) {
    if (!r.valid) return {};
    if (r.area_fallback) return SampleRectangleArea(r.plane, uv);
    double u = uv.u;
    int k = 0;
    if (u < r.p1) {
        u = std::min(u / r.p1, 1.0);
    } else {
        k = 1;
        u = std::min((u - r.p1) / (1 - r.p1), 1.0);
    }
    const Vec3d w = SampleSphericalTriangle(r.tri[k], u, double(uv.v));
    // Intersect the ray o + t w with the light's plane (local coordinates).
    const double t = r.plane.h / Dot(w, r.plane.az);
    return LightSampleFromLocal(r.plane, t * Dot(w, r.plane.exh), t * Dot(w, r.plane.eyh), r.pdf);
}

template <class T>
T TwoTrianglesPDF(const TwoTriangles<T>& r, const Vec3<T>& p) {
    if (!r.valid) return 0;
    if (r.area_fallback) return RectangleAreaPDF(r.plane, p);
    return r.pdf;
}

}  // namespace sphrect
