// An elliptical emitter (a disk is the special case): centre c and two orthogonal semi-axes
// axis_u, axis_v; its frame; and the light seen from one shading point, in a frame centred at
// that point (what every ellipse technique's setup starts from, as local_rect.h is for
// rectangles).  The emitting side of a one-sided light is the one cross(axis_u, axis_v) points to.
//
// Robustness as in local_rect.h: the frame is computed in double from the (possibly float)
// inputs, and a sample's point is built from the centre and the axes (so it lies on the light
// when o is far away) while its direction, distance and pdf come from the local coordinates (so
// they stay exact when o is nearly in the light's plane).
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "light_sample.h"
#include "vec3.h"

namespace sphrect {

template <class T>
struct EllipseLight {
    Vec3<T> center;
    Vec3<T> axis_u;  // semi-axis
    Vec3<T> axis_v;  // semi-axis, orthogonal to axis_u
    bool two_sided = true;
};

// Empty string when the ellipse is usable; otherwise what is wrong with it.  (Unlike
// ValidateRectLight, zero axes are reported: the bindings refuse them.  The core still answers a
// degenerate ellipse with pdf 0.)
template <class T>
std::string ValidateEllipseLight(const EllipseLight<T>& e) {
    if (!IsFinite(e.center) || !IsFinite(e.axis_u) || !IsFinite(e.axis_v))
        return "ellipse center and axes must be finite";
    const double lu = Length(Vec3d(e.axis_u)), lv = Length(Vec3d(e.axis_v));
    if (!(lu > 0) || !(lv > 0)) return "ellipse axes axis_u and axis_v must be non-zero";
    if (std::abs(Dot(Vec3d(e.axis_u), Vec3d(e.axis_v))) > 1e-4 * lu * lv)
        return "ellipse axes axis_u and axis_v must be orthogonal (|cos angle| = " +
               std::to_string(std::abs(Dot(Vec3d(e.axis_u), Vec3d(e.axis_v))) / (lu * lv)) + ")";
    return {};
}

// What the local frames of one light share, whatever the shading point (computed once per light).
template <class T>
struct EllipseLightFrame {
    EllipseLight<T> light;
    Vec3d center;         // in double
    Vec3d uh, vh, n;      // unit axis directions; n along cross(axis_u, axis_v): the emitting side
    double a = 0, b = 0;  // semi-axis lengths
    bool valid = false;   // false: degenerate (zero or non-finite axes, non-finite centre)
};

template <class T>
EllipseLightFrame<T> MakeEllipseLightFrame(const EllipseLight<T>& light) {
    EllipseLightFrame<T> f;
    f.light = light;
    const Vec3d c(light.center), u(light.axis_u), v(light.axis_v);
    f.center = c;
    f.a = Length(u);
    f.b = Length(v);
    if (!(f.a > 0 && f.b > 0) || !std::isfinite(f.a * f.b) || !IsFinite(c)) return f;
    f.uh = u / f.a;
    f.vh = v / f.b;
    f.n = Normalize(Cross(u, v));
    const T area = T(3.14159265358979323846 * f.a * f.b);  // (in T: an area that overflows is degenerate)
    f.valid = area > 0 && std::isfinite(area);
    return f;
}

// The ellipse in a frame centred at the shading point: in-plane coordinates along (uh, vh), the
// light's plane at height h along az.
template <class T>
struct LocalEllipse {
    EllipseLight<T> light;
    Vec3d o;
    Vec3d center;
    Vec3d uh, vh, az;       // az: from the shading point towards the light's plane
    double cx = 0, cy = 0;  // the centre in the (uh, vh) frame centred at o
    double a = 0, b = 0;    // semi-axis lengths
    double h = 0;           // distance from o to the light's plane (> 0 when valid)
    bool valid = false;     // false: degenerate light, or origin behind a one-sided light / in its plane
};

template <class T>
LocalEllipse<T> MakeLocalEllipse(const Vec3<T>& origin, const EllipseLightFrame<T>& f) {
    const Vec3d o(origin);
    if (!f.valid || !IsFinite(o)) {
        LocalEllipse<T> r;
        r.light = f.light;
        r.o = o;
        r.a = f.a;
        r.b = f.b;
        return r;
    }
    const Vec3d d = f.center - o;
    const double z = Dot(d, f.n);  // < 0: o is on the emitting side of a one-sided light
    return LocalEllipse<T>{f.light,      o,
                           f.center,     f.uh,
                           f.vh,         z < 0 ? -f.n : f.n,
                           Dot(d, f.uh), Dot(d, f.vh),
                           f.a,          f.b,
                           std::abs(z),  z != 0 && (f.light.two_sided || z < 0)};
}

template <class T>
LocalEllipse<T> MakeLocalEllipse(const Vec3<T>& origin, const EllipseLight<T>& light) {
    return MakeLocalEllipse(origin, MakeEllipseLightFrame(light));
}

// Solid-angle density of the uniform area density 1 / (pi a b) at the local vector (x, y, h):
// p(w) = d^3 / (pi a b h) (as AreaPDFLocal).  0 where not representable.
template <class T>
T EllipseAreaPDFLocal(const LocalEllipse<T>& r, double x, double y) {
    const double d2 = x * x + y * y + r.h * r.h;
    const T pdf = T(d2 * std::sqrt(d2) / (3.14159265358979323846 * r.a * r.b * r.h));
    return std::isfinite(pdf) && pdf > 0 ? pdf : T(0);
}

// (p, q) scaled onto the closed unit disk (NaN -> the centre).
inline void ClampToUnitDisk(double& p, double& q) {
    if (!std::isfinite(p) || !std::isfinite(q)) {
        p = q = 0;
        return;
    }
    const double r2 = p * p + q * q;
    if (r2 > 1) {
        const double s = 1 / std::sqrt(r2);
        p = std::clamp(p * s, -1.0, 1.0);
        q = std::clamp(q * s, -1.0, 1.0);
    }
}

// The sample at the point center + p axis_u + q axis_v ((p, q) in the unit disk, clamped onto
// it) given its pdf: the point from the centre and the axes, distance from the local vector
// (cx + p a, cy + q b, h), and the direction from it too unless `dir` (a unit vector in the local
// frame, more precise than the centre's offsets when the point is much nearer o than the centre
// is) is given.
template <class T>
LightSample<T> EllipseSampleAt(const LocalEllipse<T>& r, double p, double q, T pdf, const Vec3d* dir = nullptr) {
    ClampToUnitDisk(p, q);
    LightSample<T> s;
    s.point = Vec3<T>(r.center + Vec3d(r.light.axis_u) * p + Vec3d(r.light.axis_v) * q);
    const double x = r.cx + p * r.a, y = r.cy + q * r.b;
    const double dist = std::sqrt(x * x + y * y + r.h * r.h);
    s.dist = T(dist);
    s.dir = Vec3<T>(dir ? r.uh * dir->x + r.vh * dir->y + r.az * dir->z : (r.uh * x + r.vh * y + r.az * r.h) / dist);
    s.pdf = pdf;
    return s;
}

// Offsets of a point on the light from the centre along the unit axes (uh, vh): the difference of
// two nearby points, never of two large coordinates.
template <class T>
Point2<double> EllipseOffsets(const LocalEllipse<T>& r, const Vec3<T>& p) {
    const Vec3d d = Vec3d(p) - r.center;
    return {Dot(d, r.uh), Dot(d, r.vh)};
}

}  // namespace sphrect
