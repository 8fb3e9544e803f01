// A planar triangle emitter (vertex v0, edges e1 = v1 - v0, e2 = v2 - v0) seen from one point, sampled uniformly
// by solid angle: the spherical triangle of its vertices (in double, relative to the point, so nothing cancels for a
// distant light) mapped by Arvo's map (spherical_triangle.h), which resolves small, thin and distant triangles; what
// can be lost is its solid angle, seen nearly edge-on (Van Oosterom & Strackee's denominator cancels: area_error),
// which is then recomputed from the triangle in its plane's frame, as triangles.h does.  Invalid (pdf 0) when the
// point lies in the triangle's plane, where the triangle subtends no solid angle, or when anything is not finite.
// (The renderer's emissive triangles; the batched form is triangle_batch.h.)
#pragma once

#include <cmath>

#include "light_sample.h"
#include "solid_angle.h"
#include "spherical_triangle.h"
#include "triangles.h"  // kTrianglesStableAreaAbove

namespace sphrect {

struct TriangleSolidAngleSetup {
    SphericalTriangle tri;
    Vec3d a;        // v0 - origin
    Vec3d n;        // unit normal (double)
    double h = 0;   // n . (v0 - origin): signed distance of the plane
    float pdf = 0;  // 1 / Omega
    bool valid = false;
};

inline TriangleSolidAngleSetup MakeTriangleSolidAngleSetup(const Vec3f& v0f, const Vec3f& e1f, const Vec3f& e2f,
                                                           const Vec3f& origin) {
    TriangleSolidAngleSetup r;
    const Vec3d o(origin), v0(v0f), e1(e1f), e2(e2f);
    r.a = v0 - o;
    const Vec3d b = r.a + e1, c = r.a + e2;
    r.n = Normalize(Cross(e1, e2));
    r.h = Dot(r.n, r.a);
    if (!(std::abs(r.h) > 0) || !IsFinite(r.n)) return r;
    r.tri = MakeSphericalTriangle(r.a, b, c);
    if (r.tri.area_error > kTrianglesStableAreaAbove * r.tri.area) {
        const Vec3d ux = Normalize(e1), uy = Cross(r.n, ux);
        const double xs[3] = {Dot(r.a, ux), Dot(b, ux), Dot(c, ux)}, ys[3] = {Dot(r.a, uy), Dot(b, uy), Dot(c, uy)};
        r.tri.area = PlanarTriangleSolidAngleLocal(xs, ys, std::abs(r.h));
        r.tri.area_error = 0;
    }
    if (!(r.tri.area > 0) || !std::isfinite(r.tri.area)) return r;
    r.pdf = float(1 / r.tri.area);
    r.valid = r.pdf > 0 && std::isfinite(r.pdf);
    return r;
}

inline LightSample<float> SampleTriangleSolidAngle(const TriangleSolidAngleSetup& r, const Vec3f& origin,
                                                   Point2<float> u) {
    if (!r.valid) return {};
    const Vec3d w = SampleSphericalTriangle(r.tri, u.u, u.v);
    // The direction's hit on the triangle's plane, o + t w with t = h / (n . w), in double.
    const double t = r.h / Dot(r.n, w);
    LightSample<float> s;
    if (!(t > 0) || !std::isfinite(t)) return s;
    const Vec3d q = w * t;
    s.point = origin + Vec3f(q);
    s.dist = float(t);
    s.dir = Vec3f(w);
    s.pdf = r.pdf;
    if (!(s.dist > 0) || !std::isfinite(s.dist)) s.pdf = 0;
    return s;
}

}  // namespace sphrect
