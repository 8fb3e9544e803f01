// Arvo, "Stratified Sampling of Spherical Triangles" (SIGGRAPH 1995): an
// area-preserving map from [0,1]^2 to a spherical triangle ABC.  Double precision
// (the callers keep a float interface).
//
//  * u picks the sub-triangle A B C' of area u * area: C' on the arc AC, found from
//    the angle alpha at A and the sub-area (Arvo's closed form for cos |AC'|);
//  * v picks the point on the arc B C' with z = cos |BP| linear in v:
//    1 - z = v (1 - C'.B).  1 - C'.B is evaluated as |C' - B|^2 / 2, which keeps v
//    meaningful for tiny triangles (1 - C'.B in floating point loses it).
#pragma once

#include <algorithm>
#include <cmath>

#include "solid_angle.h"
#include "vec3.h"

namespace sphrect {

struct SphericalTriangle {
    Vec3d A, B, C;              // unit vertices
    Vec3d C_perp;               // unit vector along the arc A -> C, orthogonal to A
    double cos_alpha = 1, sin_alpha = 0, alpha = 0;  // angle at A
    double cos_c = 1;           // cos |AB|
    double area = 0;            // solid angle
};

// a, b, c: the vertices as vectors from the viewpoint (any length), with their lengths
// (callers sharing vertices between triangles compute each length once).
inline SphericalTriangle MakeSphericalTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c, double la, double lb,
                                               double lc) {
    SphericalTriangle t;
    t.A = a / la;
    t.B = b / lb;
    t.C = c / lc;
    t.area = SphericalTriangleSolidAngle(a, b, c, la, lb, lc);
    // Angle at A between the planes (A, B) and (A, C); its cosine and sine straight from the
    // same two numbers (no cos/sin of the angle).
    const Vec3d nab = Cross(t.A, t.B), nac = Cross(t.A, t.C);
    const double y = Length(Cross(nab, nac)), x = Dot(nab, nac);
    t.alpha = std::atan2(y, x);
    const double r = std::sqrt(x * x + y * y);
    if (r > 0 && std::isfinite(r)) {
        t.cos_alpha = x / r;
        t.sin_alpha = y / r;
    } else {
        t.cos_alpha = std::cos(t.alpha);
        t.sin_alpha = std::sin(t.alpha);
    }
    t.cos_c = Dot(t.A, t.B);
    t.C_perp = Normalize(t.C - t.A * Dot(t.C, t.A));
    return t;
}

inline SphericalTriangle MakeSphericalTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    return MakeSphericalTriangle(a, b, c, Length(a), Length(b), Length(c));
}

// The unit direction M(u, v) in the triangle.
inline Vec3d SampleSphericalTriangle(const SphericalTriangle& t, double u, double v) {
    // Sub-triangle A B C' with area u * area (Arvo's eq. for cos b' = cos |AC'|).
    const double area_u = u * t.area;
    const double s = std::sin(area_u - t.alpha), c = std::cos(area_u - t.alpha);
    const double p = c - t.cos_alpha;        // Arvo's u
    const double q = s + t.sin_alpha * t.cos_c;  // Arvo's v
    double cos_b = ((q * c - p * s) * t.cos_alpha - q) / ((q * s + p * c) * t.sin_alpha);
    cos_b = std::min(std::max(cos_b, -1.0), 1.0);
    if (!std::isfinite(cos_b)) cos_b = 1;
    const double sin_b = std::sqrt((1 - cos_b) * (1 + cos_b));
    const Vec3d Cu = t.A * cos_b + t.C_perp * sin_b;
    // Point on the arc B -> C' with 1 - cos|BP| = v (1 - cos|BC'|).
    const Vec3d e = Cu - t.B;
    const double one_minus_z = v * 0.5 * Dot(e, e);
    const double z = 1 - one_minus_z;
    const double sin_z = std::sqrt(std::max(0.0, one_minus_z * (2 - one_minus_z)));
    const Vec3d w = Cu - t.B * Dot(Cu, t.B);
    const double lw = Length(w);
    if (!(lw > 0)) return t.B;
    return t.B * z + w * (sin_z / lw);
}

}  // namespace sphrect
