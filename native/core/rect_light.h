// A rectangular emitter: corner s and two orthogonal edges ex, ey, and its frame
// (what every technique's setup needs of the light alone, computed once per light).
// The emitting side of a one-sided light is the one cross(ex, ey) points to.
#pragma once

#include <cmath>
#include <string>

#include "vec3.h"

namespace sphrect {

template <class T>
struct RectLight {
    Vec3<T> corner;
    Vec3<T> ex;
    Vec3<T> ey;
    bool two_sided = true;

    Vec3<T> Normal() const { return Normalize(Cross(ex, ey)); }
    T Area() const { return Length(Cross(ex, ey)); }
};

// Empty string when the rectangle is usable; otherwise what is wrong with it.
// Zero-length edges are *not* an error here: they are a degenerate light that
// every technique answers with pdf 0 (the renderer skips such lights).
template <class T>
std::string ValidateRectLight(const RectLight<T>& r) {
    if (!IsFinite(r.corner) || !IsFinite(r.ex) || !IsFinite(r.ey)) return "rectangle corner and edges must be finite";
    const double lx = std::sqrt(double(Dot(r.ex, r.ex))), ly = std::sqrt(double(Dot(r.ey, r.ey)));
    if (lx > 0 && ly > 0 && std::abs(double(Dot(r.ex, r.ey))) > 1e-4 * lx * ly)
        return "rectangle edges edge_x and edge_y must be orthogonal (|cos angle| = " +
               std::to_string(std::abs(double(Dot(r.ex, r.ey))) / (lx * ly)) + ")";
    return {};
}

// What the local frames of one light share, whatever the shading point: unit edge
// directions, normal and edge lengths in double.  Computed once per light (a renderer keeps
// it with the light) or once per setup by MakeLocalRect(origin, light).
template <class T>
struct RectLightFrame {
    RectLight<T> light;
    Vec3d corner;           // the corner in double
    Vec3d exh, eyh, n;      // unit edge directions; n along cross(ex, ey): the emitting side
    double wx = 0, wy = 0;  // edge lengths
    bool valid = false;     // false: degenerate (zero or non-finite edges, non-finite corner)
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

// The sub-rectangle [u0, u1] x [v0, v1] of the light, in lengths along its unit edges from its corner
// (0 <= u0 < u1 <= wx, 0 <= v0 < v1 <= wy): another rectangle for every technique, its corner computed in
// double from the light's (the float light is what the samples' points are built from).  Invalid when the
// light is, or when the sub-rectangle is empty.
template <class T>
RectLightFrame<T> SubRectLightFrame(const RectLightFrame<T>& f, double u0, double v0, double u1, double v1) {
    RectLightFrame<T> s = f;
    s.corner = f.corner + f.exh * u0 + f.eyh * v0;
    s.wx = u1 - u0;
    s.wy = v1 - v0;
    s.light.corner = Vec3<T>(s.corner);
    s.light.ex = Vec3<T>(f.exh * s.wx);
    s.light.ey = Vec3<T>(f.eyh * s.wy);
    const T area = T(s.wx * s.wy);
    s.valid = f.valid && s.wx > 0 && s.wy > 0 && area > 0 && std::isfinite(area);
    return s;
}

}  // namespace sphrect
