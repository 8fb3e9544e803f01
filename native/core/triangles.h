// Technique `triangles`: the paper's baseline.  The rectangle is split along the
// diagonal corner -> corner + ex + ey into two spherical triangles, each sampled
// with Arvo's map (spherical_triangle.h).  The triangle is chosen with probability
// proportional to its solid angle by remapping u, so that one (u, v) makes one
// sample: u < P1 -> triangle 1 with u / P1, else triangle 2 with (u - P1) / (1 - P1).
// The density is 1 / Omega on the whole rectangle.
//
// Robustness: setup and map in double.  Arvo's closed form for the sub-triangle
// loses u when a triangle's solid angle is tiny (the angle sum ~ pi swamps it), so a
// triangle whose solid angle is below kTrianglesMinSolidAngle (decided once per
// setup, as for `rectangle`) is sampled uniformly by area on the planar triangle
// instead, with that true pdf: pdf(p) = P_k x (2 d^3 / (A h)) on such a triangle k,
// P_k / Omega_k = 1 / (Omega_0 + Omega_1) on a spherical one.  This happens for the
// triangle away from the foot of a shading point very close to the light, and for
// both triangles of a distant light (where area sampling is nearly exact anyway).
#pragma once

#include <algorithm>
#include <cmath>

#include "local_rect.h"
#include "solid_angle.h"
#include "spherical_triangle.h"

namespace sphrect {

constexpr double kTrianglesMinSolidAngle = 1e-7;

template <class T>
struct TrianglesSetup {
    LocalRect<T> plane;  // frame around o, and the planar fallback's geometry
    SphericalTriangle tri[2] = {};  // (00, 10, 11) and (00, 11, 01) in light fractions (a, b)
    bool planar[2] = {false, false};  // sampled by area on the planar triangle
    double p1 = 0;      // probability of the first triangle
    double omega = 0;   // solid angle of the rectangle (stable)
    T pdf = 0;          // 1 / (Omega_0 + Omega_1): the density on a spherically sampled triangle
    bool valid = false;
    bool area_fallback = false;  // both triangles planar
};

template <class T>
TrianglesSetup<T> MakeTrianglesSetup(const Vec3<T>& origin, const RectLightFrame<T>& frame) {
    TrianglesSetup<T> r{MakeLocalRect(origin, frame)};  // the plane built in place
    const LocalRect<T>& p = r.plane;
    if (!p.valid) return r;
    // Corners relative to o from the local coordinates (no cancellation for o near the plane).
    auto corner = [&](int i, int j) { return LocalVector(p, p.x0 + i * p.wx, p.y0 + j * p.wy); };
    const Vec3d c00 = corner(0, 0), c10 = corner(1, 0), c11 = corner(1, 1), c01 = corner(0, 1);
    const double l00 = Length(c00), l10 = Length(c10), l11 = Length(c11), l01 = Length(c01);
    r.tri[0] = MakeSphericalTriangle(c00, c10, c11, l00, l10, l11);
    r.tri[1] = MakeSphericalTriangle(c00, c11, c01, l00, l11, l01);
    r.omega = RectSolidAngleLocal({p.x0, p.x0 + p.wx, p.wx}, {p.y0, p.y0 + p.wy, p.wy}, p.h);
    const double sum = r.tri[0].area + r.tri[1].area;
    r.pdf = T(1 / sum);
    if (!(r.omega > 0) || !(T(r.omega) > 0) || !(sum > 0) || !std::isfinite(r.pdf)) return r;
    r.valid = true;
    r.p1 = r.tri[0].area / sum;
    for (int k = 0; k < 2; ++k) r.planar[k] = !(r.tri[k].area >= kTrianglesMinSolidAngle);
    r.area_fallback = r.planar[0] && r.planar[1];
    if (r.area_fallback) r.p1 = 0.5;  // halves of the area: plain uniform area sampling
    return r;
}

template <class T>
TrianglesSetup<T> MakeTrianglesSetup(const Vec3<T>& origin, const RectLight<T>& light) {
    return MakeTrianglesSetup(origin, MakeRectLightFrame(light));
}

// Which triangle the light fractions (a, b) lie in: 0 below the diagonal b = a.
inline int TriangleIndex(double a, double b) { return b > a ? 1 : 0; }

// Solid-angle pdf at local in-plane coordinates (X, Y) in triangle k.
template <class T>
T TrianglesPDFLocal(const TrianglesSetup<T>& r, int k, double X, double Y) {
    if (!r.planar[k]) return r.pdf;
    const double Pk = k == 0 ? r.p1 : 1 - r.p1;
    return T(Pk * 2 * double(AreaPDFLocal(r.plane, X, Y)));  // uniform on half of the area
}

template <class T>
LightSample<T> SampleTriangles(const TrianglesSetup<T>& r, Point2<T> uv) {
    if (!r.valid) return {};
    double u = uv.u;
    int k = 0;
    if (u < r.p1) {
        u = std::min(u / r.p1, 1.0);
    } else {
        k = 1;
        u = std::min((u - r.p1) / (1 - r.p1), 1.0);
    }
    const LocalRect<T>& p = r.plane;
    double X, Y;
    if (r.planar[k]) {
        // Uniform on the planar triangle, barycentrics (1 - su, su (1 - v), su v), su = sqrt(u):
        // triangle 0 = (00, 10, 11) -> (a, b) = (su, su v); triangle 1 = (00, 11, 01) -> (su (1 - v), su).
        const double su = std::sqrt(u), v = uv.v;
        X = p.x0 + (k == 0 ? su : su * (1 - v)) * p.wx;
        Y = p.y0 + (k == 0 ? su * v : su) * p.wy;
    } else {
        const Vec3d w = SampleSphericalTriangle(r.tri[k], u, double(uv.v));
        // Intersect the ray o + t w with the light's plane (local coordinates).
        const double t = p.h / Dot(w, p.az);
        X = t * Dot(w, p.exh);
        Y = t * Dot(w, p.eyh);
    }
    LightSample<T> s = LightSampleFromLocal(p, X, Y, T(0));
    // The pdf of the returned point: the side of the diagonal by the same test as
    // TrianglesPDF on that point (a point within rounding of the diagonal gets the
    // density of the side it lands on), the distance from the exact local coordinates.
    const Point2<double> e = EdgeOffsets(p, s.point);
    const int side = TriangleIndex(e.u / p.wx, e.v / p.wy);
    ClampLocalToLight(p, X, Y);
    s.pdf = TrianglesPDFLocal(r, side, X, Y);
    return s;
}

template <class T>
T TrianglesPDF(const TrianglesSetup<T>& r, const Vec3<T>& pt) {
    if (!r.valid) return 0;
    const LocalRect<T>& p = r.plane;
    const Point2<double> e = EdgeOffsets(p, pt);
    const int k = TriangleIndex(e.u / p.wx, e.v / p.wy);
    return TrianglesPDFLocal(r, k, p.x0 + e.u, p.y0 + e.v);
}

}  // namespace sphrect
