// Arvo, "Stratified Sampling of Spherical Triangles" (SIGGRAPH 1995): an
// area-preserving map from [0,1]^2 to a spherical triangle ABC, in double (the callers
// keep a float interface).  The same map as the paper's, computed in other variables
// (docs/triangles_baseline.md derives them):
//
//  * u picks the sub-triangle A B C' of solid angle u * area, C' on the arc AC.  The paper
//    solves for cos |AC'|, which loses u for a small or thin triangle (its cos(uA - alpha)
//    - cos(alpha) cancels, and cos b' ~ 1 hides a short arc b').  Here tan(b'/2) comes from
//    the area of a triangle with two sides and the included angle, (T1), and C' is the point
//    a + t (c - a) of the planar edge by the law of sines, (T2);
//  * v picks the point P on the arc B C' with 1 - cos |BP| = v (1 - cos |BC'|): the half
//    angle of |BP| from that of |BC'|, (T3), and P = b + s (c' - b) by the law of sines again.
//
// Everything is computed from the vertex a and the edges b - a, c - a of the planar triangle
// abc (vectors from the viewpoint, any length: the map is the same for any planar triangle
// that projects to ABC), and the point is returned as barycentrics in that triangle, so a
// caller with exact edges (a light's local frame) gets the point without intersecting a ray
// with the plane, and nothing cancels for a distant or grazing triangle.
#pragma once

#include <algorithm>
#include <cmath>

#include "solid_angle.h"
#include "vec3.h"

namespace sphrect {

struct SphericalTriangle {
    Vec3d A, B, C;                        // unit vertices
    Vec3d a, eb, ec;                      // the planar triangle: vertex a, edges b - a, c - a
    double la = 0, lb = 0;                // |a|, |b|
    double area = 0;                      // solid angle
    double area_error = 0;                // first-order bound of its rounding error (absolute)
    double cos_alpha = 1, sin_alpha = 0;  // angle at A
    double tan_half_c = 0;                // tan(|AB| / 2)
    double a_cross_ec = 0, a_dot_ec = 0;  // |a x (c - a)|, a . (c - a): the edge ac seen from o
    double tan_half_b = 0;                // tan(|AC| / 2): the largest tan(b'/2)
};

// tan(w/2) of the angle w between two vectors from |x cross y|, x . y and |x||y|, in the form
// that does not cancel: sin w / (1 + cos w) or (1 - cos w) / sin w.
inline double TanHalfAngle(double cross, double dot, double lengths) {
    return dot >= 0 ? cross / (lengths + dot) : (lengths - dot) / cross;
}

// From the vertex a, the edges eb = b - a, ec = c - a and the vertex lengths (callers with
// exact edges, or sharing vertices between triangles, pass them).
inline SphericalTriangle MakeSphericalTriangleFromEdges(const Vec3d& a, const Vec3d& eb, const Vec3d& ec, double la,
                                                        double lb, double lc) {
    SphericalTriangle t;
    const Vec3d b = a + eb, c = a + ec;
    t.A = a / la;
    t.B = b / lb;
    t.C = c / lc;
    t.a = a;
    t.eb = eb;
    t.ec = ec;
    t.la = la;
    t.lb = lb;
    // The triple product from the edges: a . (b x c) of the vertices cancels for a distant triangle.
    const double triple = std::abs(Dot(a, Cross(eb, ec)));
    const double den = SphericalTriangleDenominator(a, b, c, la, lb, lc);
    t.area = 2 * std::atan2(triple, den);
    // Van Oosterom & Strackee's W = 2 atan2(N, D): D (four terms of size <= |a||b||c|) is the
    // part that can cancel, when the triangle is seen nearly edge-on (N small) and W ~ pi.
    constexpr double eps = 1.1102230246251565e-16;
    t.area_error = 2 * triple * (8 * eps * la * lb * lc) / (triple * triple + den * den) + 8 * eps * t.area;
    // Angle at A between the planes (a, b) and (a, c): (a x eb) x (a x ec) = a (a . (eb x ec)).
    const Vec3d nab = Cross(a, eb), nac = Cross(a, ec);
    const double y = la * triple, x = Dot(nab, nac), r = std::sqrt(x * x + y * y);
    if (r > 0 && std::isfinite(r)) {
        t.cos_alpha = x / r;
        t.sin_alpha = y / r;
    }
    // tan(c/2) = sin c / (1 + cos c) = (1 - cos c) / sin c, whichever does not cancel.
    t.tan_half_c = TanHalfAngle(Length(nab), Dot(a, b), la * lb);
    t.a_cross_ec = Length(nac);
    t.a_dot_ec = Dot(a, ec);
    t.tan_half_b = TanHalfAngle(t.a_cross_ec, Dot(a, c), la * lc);
    return t;
}

// a, b, c: the vertices as vectors from the viewpoint (any length), with their lengths.
inline SphericalTriangle MakeSphericalTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c, double la, double lb,
                                               double lc) {
    return MakeSphericalTriangleFromEdges(a, b - a, c - a, la, lb, lc);
}

inline SphericalTriangle MakeSphericalTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    return MakeSphericalTriangle(a, b, c, Length(a), Length(b), Length(c));
}

// M(u, v) as barycentrics (beta, gamma) of the planar triangle: the point
// a + beta (b - a) + gamma (c - a), which projects to the direction M(u, v).
inline Point2<double> SampleSphericalTriangleBarycentrics(const SphericalTriangle& t, double u, double v) {
    // (T1) Sub-triangle A B C' of area A' = u * area with sides c = |AB|, b' = |AC'| and the
    // angle alpha between them: tan(A'/2) = X sin(alpha) / (1 + X cos(alpha)),
    // X = tan(b'/2) tan(c/2), i.e. X = sin(A'/2) / sin(alpha - A'/2), where alpha > A'/2.
    const double half = 0.5 * u * t.area, sh = std::sin(half), ch = std::cos(half);
    const double sin_rest = t.sin_alpha * ch - t.cos_alpha * sh;  // sin(alpha - A'/2)
    const double tb = sh / (sin_rest * t.tan_half_c);             // tan(b'/2)
    // (T2) C' = a + tc (c - a): in the planar triangle (o, a, c') the angle at o is b' and at
    // c' is psi - b' (psi the angle between a and c - a), so tc |c - a| / sin b' = |a| / sin(psi - b').
    // Near u = 1, alpha - A'/2 can be within the area's rounding of 0 (a triangle seen edge-on
    // whose angle at A is half its area): there A' hardly depends on b', so b' beyond |AC|
    // (or alpha - A'/2 <= 0) is C' = C.
    const double tc = sin_rest > 0 && tb < t.tan_half_b
                          ? ClampNaN(2 * t.la * t.la * tb / (t.a_cross_ec * (1 - tb * tb) - 2 * t.a_dot_ec * tb), 0, 1)
                          : 1.0;
    // (T3) P = b + s (c' - b), f = c' - b from the edges.  With phi1 = |BC'| and m = |b||c'|,
    // sin^2(phi1/2) = (m - b.c') / 2m and cos^2(phi1/2) = (m + b.c') / 2m, the one that would
    // cancel through |b x f|^2 = m^2 - (b.c')^2; then sin^2(phi/2) = v sin^2(phi1/2) is
    // 1 - cos |BP| = v (1 - cos |BC'|), and s by the law of sines in (o, b, p).
    const Vec3d f = t.ec * tc - t.eb, cp = t.a + t.ec * tc;
    const Vec3d b = t.a + t.eb;
    const double g = Length(Cross(b, f)), hb = Dot(b, f), k = Dot(b, cp), m = t.lb * Length(cp);
    double s1, c1;  // sin^2, cos^2 of phi1 / 2
    if (k >= 0) {
        c1 = (m + k) / (2 * m);
        s1 = g * g / (2 * m * (m + k));
    } else {
        s1 = (m - k) / (2 * m);
        c1 = g * g / (2 * m * (m - k));
    }
    const double sh2 = v * s1, ch2 = (1 - v) + v * c1;  // sin^2, cos^2 of phi / 2
    const double sin_phi = 2 * std::sqrt(sh2 * ch2), cos_phi = ch2 - sh2;
    // (The denominator is |f||b| sin(psi_b - phi) > 0 for phi <= phi1; rounding at v ~ 1 -> P = C'.)
    const double den = g * cos_phi - hb * sin_phi;
    const double s = den > 0 ? ClampNaN(t.lb * t.lb * sin_phi / den, 0, 1) : sin_phi > 0 ? 1.0 : 0.0;
    return {1 - s, s * tc};
}

// The unit direction M(u, v) in the triangle.
inline Vec3d SampleSphericalTriangle(const SphericalTriangle& t, double u, double v) {
    const Point2<double> w = SampleSphericalTriangleBarycentrics(t, u, v);
    const Vec3d p = t.a + t.eb * w.u + t.ec * w.v;
    const double l = Length(p);
    return l > 0 && std::isfinite(l) ? p / l : t.A;
}

}  // namespace sphrect
