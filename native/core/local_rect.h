// The light seen from one shading point o: its rectangle in a frame centred at o, and the
// samples built from that frame.  Every technique's setup starts from it.
//
// Robustness: the frame (height, in-plane coordinates of o) is computed in double from the
// (possibly float) inputs, and a sample's direction, distance and pdf come from those local
// coordinates, so a shading point 1e-9 above the plane or 1e6 sizes away still gets the true
// values of the returned point (a float dot product n.(p - o) would be pure rounding noise).
#pragma once

#include <algorithm>
#include <cmath>

#include "light_sample.h"
#include "rect_light.h"

namespace sphrect {

template <class T>
struct LocalRect {
    RectLight<T> light;
    Vec3d o;                // shading point (double)
    Vec3d exh, eyh, az;     // unit edge directions; az: from the shading point towards the light's plane
    double x0 = 0, y0 = 0;  // the corner in the (exh, eyh) frame centred at o
    double wx = 0, wy = 0;  // edge lengths
    double h = 0;           // distance from o to the light's plane (> 0 when valid)
    bool valid = false;     // false: degenerate light, or origin behind a one-sided light / in its plane
};

// The frame around `origin` from the light's precomputed frame.  (Built as one aggregate from
// locals: zero-filling the struct first and then reading fields back from it costs more than
// the arithmetic.)
template <class T>
LocalRect<T> MakeLocalRect(const Vec3<T>& origin, const RectLightFrame<T>& f) {
    const Vec3d o(origin);
    if (!f.valid || !IsFinite(o)) {
        LocalRect<T> r;
        r.light = f.light;
        r.o = o;
        r.wx = f.wx;
        r.wy = f.wy;
        return r;
    }
    const Vec3d d = f.corner - o;
    const double z = Dot(d, f.n);  // < 0: o is on the emitting side of a one-sided light
    return LocalRect<T>{f.light,
                        o,
                        f.exh,
                        f.eyh,
                        z < 0 ? -f.n : f.n,
                        Dot(d, f.exh),
                        Dot(d, f.eyh),
                        f.wx,
                        f.wy,
                        std::abs(z),
                        z != 0 && (f.light.two_sided || z < 0)};
}

template <class T>
LocalRect<T> MakeLocalRect(const Vec3<T>& origin, const RectLight<T>& light) {
    return MakeLocalRect(origin, MakeRectLightFrame(light));
}

// Vector from the shading point to the point of the light's plane with local in-plane
// coordinates (X, Y).
template <class T>
Vec3d LocalVector(const LocalRect<T>& r, double X, double Y) {
    return r.exh * X + r.eyh * Y + r.az * r.h;
}

// Solid-angle density of the uniform area density 1 / A at local in-plane coordinates (x, y):
// dA = d^2 / cos(theta_light) dw = d^3 / h dw, so p(w) = d^3 / (A h).  0 where not representable.
template <class T>
T AreaPDFLocal(const LocalRect<T>& r, double x, double y) {
    const double d2 = x * x + y * y + r.h * r.h;
    const T pdf = T(d2 * std::sqrt(d2) / (r.wx * r.wy * r.h));
    return std::isfinite(pdf) && pdf > 0 ? pdf : T(0);
}

// The sample at the point corner + a ex + b ey, whose local in-plane coordinates
// (along exh, eyh, relative to the shading point) are (X, Y), given its pdf.  The
// point is built from the corner and the edges, so it lies on the light even when o
// is far away; the direction and distance come from the local coordinates, so they
// stay exact when o is nearly in the light's plane.  `dist`, when known (> 0), is
// |(X, Y, h)|.
template <class T>
LightSample<T> LightSampleAt(const LocalRect<T>& r, double a, double b, double X, double Y, T pdf, double dist = 0) {
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
void ClampLocalToLight(const LocalRect<T>& r, double& X, double& Y) {
    X = ClampNaN(X, r.x0, r.x0 + r.wx);
    Y = ClampNaN(Y, r.y0, r.y0 + r.wy);
}

// The same from the local coordinates alone, clamped onto the light so that rounding
// never leaves it.
template <class T>
LightSample<T> LightSampleFromLocal(const LocalRect<T>& r, double X, double Y, T pdf, double dist = 0) {
    ClampLocalToLight(r, X, Y);
    const double a = std::min((X - r.x0) / r.wx, 1.0), b = std::min((Y - r.y0) / r.wy, 1.0);
    return LightSampleAt(r, a, b, X, Y, pdf, dist);
}

// Offsets of a point on the light from its corner along the unit edges (exh, eyh): the
// difference of two nearby points, never of two large coordinates.
template <class T>
Point2<double> EdgeOffsets(const LocalRect<T>& r, const Vec3<T>& p) {
    const Vec3d q = Vec3d(p) - Vec3d(r.light.corner);  // exact for float inputs of similar magnitude
    return {Dot(q, r.exh), Dot(q, r.eyh)};
}

}  // namespace sphrect
