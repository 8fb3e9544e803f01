// Technique `area`: uniform over the rectangle's area, pdf converted to solid
// angle, p(w) = d^2 / (A |cos theta_light|) = d^3 / (A h), h the height of the
// shading point above the light's plane.  The baseline of the paper.
//
// Robustness: the setup (height, in-plane coordinates of the shading point) is
// done in double from the (possibly float) inputs, and the pdf is evaluated from
// those local coordinates, so a shading point 1e-9 above the plane or 1e6 sizes
// away still gets the true pdf of the returned point (a float dot product
// n.(p - o) would be pure rounding noise there).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "light_sample.h"
#include "rect_light.h"

namespace sphrect {

// What the local frames of one light share, whatever the shading point: unit edge
// directions, normal and edge lengths in double.  Computed once per light (a renderer keeps
// it with the light) or once per setup by MakeAreaRect(origin, light).
template <class T>
struct RectLightFrame {
    RectLight<T> light;
    Vec3d corner;          // the corner in double
    Vec3d exh, eyh, n;     // unit edge directions; n along cross(ex, ey): the emitting side
    double wx = 0, wy = 0; // edge lengths
    bool valid = false;    // false: degenerate (zero or non-finite edges, non-finite corner)
};

template <class T>
RectLightFrame<T> MakeRectLightFrame(const RectLight<T>& light) {
    RectLightFrame<T> f;
    f.light = light;
    const Vec3d c(light.corner), ex(light.ex), ey(light.ey);
    f.corner = c;
    f.wx = Length(ex);
    f.wy = Length(ey);
    if (!(f.wx > 0 && f.wy > 0) || !std::isfinite(f.wx * f.wy) || !IsFinite(c)) return f;
    f.exh = ex / f.wx;
    f.eyh = ey / f.wy;
    f.n = Normalize(Cross(ex, ey));
    const T area = T(f.wx * f.wy);  // (in T: a float light whose area overflows is degenerate)
    f.valid = area > 0 && std::isfinite(area);
    return f;
}

template <class T>
struct AreaRect {
    RectLight<T> light;
    Vec3d o;              // shading point (double)
    Vec3d exh, eyh, az;   // unit edge directions; az: from the shading point towards the light's plane
    double x0 = 0, y0 = 0;  // the corner in the (exh, eyh) frame centred at o
    double wx = 0, wy = 0;  // edge lengths
    double h = 0;         // distance from o to the light's plane (> 0 when valid)
    bool valid = false;   // false: degenerate light, or origin behind a one-sided light / in its plane
};

// The frame around `origin` from the light's precomputed frame.  (Built as one aggregate from
// locals: zero-filling the struct first and then reading fields back from it costs more than
// the arithmetic.)
template <class T>
AreaRect<T> MakeAreaRect(const Vec3<T>& origin, const RectLightFrame<T>& f) {
    const Vec3d o(origin);
    if (!f.valid || !IsFinite(o)) {
        AreaRect<T> r;
        r.light = f.light;
        r.o = o;
        r.wx = f.wx;
        r.wy = f.wy;
        return r;
    }
    const Vec3d d = f.corner - o;
    const double z = Dot(d, f.n);  // < 0: o is on the emitting side of a one-sided light
    return AreaRect<T>{f.light, o, f.exh, f.eyh, z < 0 ? -f.n : f.n, Dot(d, f.exh), Dot(d, f.eyh), f.wx, f.wy,
                       std::abs(z), z != 0 && (f.light.two_sided || z < 0)};
}

template <class T>
AreaRect<T> MakeAreaRect(const Vec3<T>& origin, const RectLight<T>& light) {
    return MakeAreaRect(origin, MakeRectLightFrame(light));
}

// Solid-angle pdf of uniform area sampling at the point with local in-plane
// coordinates (x, y) relative to the shading point: d^3 / (A h).
template <class T>
T AreaPDFLocal(const AreaRect<T>& r, double x, double y) {
    const double d2 = x * x + y * y + r.h * r.h;
    const T pdf = T(d2 * std::sqrt(d2) / (r.wx * r.wy * r.h));
    return std::isfinite(pdf) && pdf > 0 ? pdf : T(0);
}

// Solid-angle pdf of the point p on the light; 0 for an invalid setup or where
// the pdf is not representable.
template <class T>
T RectangleAreaPDF(const AreaRect<T>& r, const Vec3<T>& p) {
    if (!r.valid) return 0;
    const Vec3d q = Vec3d(p) - Vec3d(r.light.corner);  // exact for float inputs of similar magnitude
    return AreaPDFLocal(r, r.x0 + Dot(q, r.exh), r.y0 + Dot(q, r.eyh));
}

// Vector from the shading point to the point of the light's plane with local in-plane
// coordinates (X, Y).
template <class T>
Vec3d LocalVector(const AreaRect<T>& r, double X, double Y) {
    return r.exh * X + r.eyh * Y + r.az * r.h;
}

// The sample at the point corner + a ex + b ey, whose local in-plane coordinates
// (along exh, eyh, relative to the shading point) are (X, Y), given its pdf.  The
// point is built from the corner and the edges, so it lies on the light even when o
// is far away; the direction and distance come from the local coordinates, so they
// stay exact when o is nearly in the light's plane.  `dist`, when known (> 0), is
// |(X, Y, h)|.
template <class T>
LightSample<T> LightSampleAt(const AreaRect<T>& r, double a, double b, double X, double Y, T pdf,
                             double dist = 0) {
    LightSample<T> s;
    s.point = Vec3<T>(Vec3d(r.light.corner) + Vec3d(r.light.ex) * a + Vec3d(r.light.ey) * b);
    const Vec3d d = LocalVector(r, X, Y);
    if (!(dist > 0) || !std::isfinite(dist)) dist = Length(d);
    s.dist = T(dist);
    s.dir = Vec3<T>(d / dist);
    s.pdf = pdf;
    return s;
}

// Local in-plane coordinates clamped onto the light (NaN -> the corner's).
template <class T>
void ClampLocalToLight(const AreaRect<T>& r, double& X, double& Y) {
    X = ClampNaN(X, r.x0, r.x0 + r.wx);
    Y = ClampNaN(Y, r.y0, r.y0 + r.wy);
}

// The same from the local coordinates alone, clamped onto the light so that rounding
// never leaves it.
template <class T>
LightSample<T> LightSampleFromLocal(const AreaRect<T>& r, double X, double Y, T pdf, double dist = 0) {
    ClampLocalToLight(r, X, Y);
    const double a = std::min((X - r.x0) / r.wx, 1.0), b = std::min((Y - r.y0) / r.wy, 1.0);
    return LightSampleAt(r, a, b, X, Y, pdf, dist);
}

// The point corner + a ex + b ey, (a, b) in [0,1]^2, with its area-sampling pdf.
template <class T>
LightSample<T> AreaSampleAt(const AreaRect<T>& r, double a, double b) {
    if (!r.valid) return {};
    a = ClampNaN(a, 0, 1);
    b = ClampNaN(b, 0, 1);
    const double X = r.x0 + a * r.wx, Y = r.y0 + b * r.wy;
    return LightSampleAt(r, a, b, X, Y, AreaPDFLocal(r, X, Y));
}

template <class T>
LightSample<T> SampleRectangleArea(const AreaRect<T>& r, Point2<T> uv) {
    return AreaSampleAt(r, double(uv.u), double(uv.v));
}

// Inverse of the area map: the fractions of the point along ex and ey, in [0,1] (NaN -> 0).
template <class T>
Point2<double> InvertRectangleAreaLocal(const AreaRect<T>& r, const Vec3<T>& p) {
    const Vec3d q = Vec3d(p) - Vec3d(r.light.corner);  // offsets along the edges: no large differences
    return {ClampNaN(Dot(q, r.exh) / r.wx, 0, 1), ClampNaN(Dot(q, r.eyh) / r.wy, 0, 1)};
}

template <class T>
Point2<T> InvertRectangleAreaSample(const AreaRect<T>& r, const Vec3<T>& p) {
    const Point2<double> uv = InvertRectangleAreaLocal(r, p);
    return {T(uv.u), T(uv.v)};
}

}  // namespace sphrect
