// Technique `area`: uniform over the rectangle's area, pdf converted to solid
// angle, p(w) = d^2 / (A |cos theta_light|).  The baseline of the paper.
#pragma once

#include <cmath>
#include <limits>

#include "light_sample.h"
#include "rect_light.h"

namespace sphrect {

template <class T>
struct AreaRect {
    Vec3<T> origin, corner, ex, ey;
    Vec3<T> n;          // unit normal of the light
    T area = 0;
    bool valid = false;  // false: degenerate light, or origin behind a one-sided light / in its plane
};

template <class T>
AreaRect<T> MakeAreaRect(const Vec3<T>& origin, const RectLight<T>& light) {
    AreaRect<T> r;
    r.origin = origin;
    r.corner = light.corner;
    r.ex = light.ex;
    r.ey = light.ey;
    const Vec3<T> c = Cross(light.ex, light.ey);
    r.area = Length(c);
    if (!(r.area > 0) || !std::isfinite(r.area)) return r;
    r.n = c / r.area;
    const T h = Dot(r.n, origin - light.corner);  // signed height above the light's plane
    r.valid = light.two_sided ? h != 0 : h > 0;
    return r;
}

// Solid-angle pdf of the point p on the light; 0 where the conversion is not finite
// (grazing: the area pdf cannot be expressed in solid angle).
template <class T>
T RectangleAreaPDF(const AreaRect<T>& r, const Vec3<T>& p) {
    if (!r.valid) return 0;
    const Vec3<T> d = p - r.origin;
    const T d2 = Dot(d, d);
    const T cosl = std::abs(Dot(r.n, d)) / std::sqrt(d2);
    const T pdf = d2 / (r.area * cosl);
    return std::isfinite(pdf) && pdf > 0 ? pdf : T(0);
}

template <class T>
LightSample<T> SampleRectangleArea(const AreaRect<T>& r, Point2<T> uv) {
    LightSample<T> s;
    s.point = r.corner + r.ex * uv.u + r.ey * uv.v;
    const Vec3<T> d = s.point - r.origin;
    s.dist = Length(d);
    if (!r.valid || !(s.dist > 0)) return s;
    s.dir = d / s.dist;
    s.pdf = RectangleAreaPDF(r, s.point);
    return s;
}

}  // namespace sphrect
