// Technique `triangles`: the paper's baseline.  The rectangle is split along the
// diagonal corner -> corner + ex + ey into two spherical triangles, each sampled
// with Arvo's map (spherical_triangle.h).  The triangle is chosen with probability
// proportional to its solid angle by remapping u, so that one (u, v) makes one
// sample: u < P1 -> triangle 1 with u / P1, else triangle 2 with (u - P1) / (1 - P1).
// The density is 1 / Omega on the whole rectangle.
//
// Robustness, to the standard of `rectangle` (docs/triangles_baseline.md): setup and map in
// double, on the triangles in the light's local frame around o (corners (X, Y, h), X, Y the
// in-plane offsets from o, h its exact height; exact edges), so nothing cancels for a grazing
// or distant o; Arvo's map in the stable form of spherical_triangle.h, whose point comes back
// as barycentrics, i.e. as light fractions, without intersecting a ray with the plane; each
// triangle's solid angle by Van Oosterom & Strackee, or by quadrant pieces where that one
// cancels (o near the plane by the diagonal or over the light).  No setup needs a fallback to
// area sampling: the pdf is 1 / (Omega_0 + Omega_1) for every point.
#pragma once

#include <algorithm>
#include <cmath>

#include "local_rect.h"
#include "solid_angle.h"
#include "spherical_triangle.h"

namespace sphrect {

// Above this first-order error estimate (relative), a triangle's solid angle is recomputed by
// quadrant pieces (PlanarTriangleSolidAngleLocal).
constexpr double kTrianglesStableAreaAbove = 1e-12;

template <class T>
struct TrianglesSetup {
    LocalRect<T> plane;             // frame around o
    SphericalTriangle tri[2] = {};  // (00, 10, 11) and (00, 11, 01) in light fractions (a, b), local frame
    double p1 = 0;                  // probability of the first triangle
    double omega = 0;               // solid angle of the rectangle (stable)
    T pdf = 0;                      // 1 / (Omega_0 + Omega_1)
    bool valid = false;
};

template <class T>
TrianglesSetup<T> MakeTrianglesSetup(const Vec3<T>& origin, const RectLightFrame<T>& frame) {
    TrianglesSetup<T> r{MakeLocalRect(origin, frame)};  // the plane built in place
    const LocalRect<T>& p = r.plane;
    if (!p.valid) return r;
    // The triangles in the local frame (exh, eyh, az) around o: corners (X, Y, h), exact edges.
    const double x1 = p.x0 + p.wx, y1 = p.y0 + p.wy, h = p.h;
    const Vec3d c00(p.x0, p.y0, h), c10(x1, p.y0, h), c11(x1, y1, h), c01(p.x0, y1, h);
    const Vec3d ex(p.wx, 0, 0), ey(0, p.wy, 0), exy(p.wx, p.wy, 0);
    const double l00 = Length(c00), l10 = Length(c10), l11 = Length(c11), l01 = Length(c01);
    r.tri[0] = MakeSphericalTriangleFromEdges(c00, ex, exy, l00, l10, l11);
    r.tri[1] = MakeSphericalTriangleFromEdges(c00, exy, ey, l00, l11, l01);
    // Seen nearly edge-on with W ~ pi, Van Oosterom & Strackee's denominator cancels (relative
    // error up to eps / h): the stable solid angle by quadrant pieces instead.
    for (int k = 0; k < 2; ++k) {
        SphericalTriangle& t = r.tri[k];
        if (!(t.area_error > kTrianglesStableAreaAbove * t.area)) continue;
        const double xs[3] = {p.x0, x1, k == 0 ? x1 : p.x0}, ys[3] = {p.y0, k == 0 ? p.y0 : y1, y1};
        t.area = PlanarTriangleSolidAngleLocal(xs, ys, h);
        t.area_error = 0;  // a few ulps of each piece
    }
    r.omega = RectSolidAngleLocal({p.x0, x1, p.wx}, {p.y0, y1, p.wy}, h);
    const double sum = r.tri[0].area + r.tri[1].area;
    r.pdf = T(1 / sum);
    if (!(r.omega > 0) || !(T(r.omega) > 0) || !(sum > 0) || !std::isfinite(r.pdf) || !(r.pdf > 0)) return r;
    r.valid = true;
    r.p1 = r.tri[0].area / sum;
    return r;
}

template <class T>
TrianglesSetup<T> MakeTrianglesSetup(const Vec3<T>& origin, const RectLight<T>& light) {
    return MakeTrianglesSetup(origin, MakeRectLightFrame(light));
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
    // Barycentrics (beta, gamma): the point 00 + beta (B - 00) + gamma (C - 00), with
    // (B, C) = (10, 11) in triangle 0 and (11, 01) in triangle 1, as light fractions (a, b).
    const Point2<double> w = SampleSphericalTriangleBarycentrics(r.tri[k], u, double(uv.v));
    const double a = ClampNaN(k == 0 ? w.u + w.v : w.u, 0, 1), b = ClampNaN(k == 0 ? w.v : w.u + w.v, 0, 1);
    const LocalRect<T>& p = r.plane;
    return LightSampleAt(p, a, b, p.x0 + a * p.wx, p.y0 + b * p.wy, r.pdf);
}

template <class T>
T TrianglesPDF(const TrianglesSetup<T>& r, const Vec3<T>& /*point on the light*/) {
    return r.valid ? r.pdf : T(0);
}

}  // namespace sphrect
