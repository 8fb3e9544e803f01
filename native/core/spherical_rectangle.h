// PLACEHOLDER (to be replaced by the paper's map): delegates to area sampling.
#pragma once
#include "area_sampling.h"
namespace sphrect {
template <class T> using SphericalRectangle = AreaRect<T>;
template <class T> SphericalRectangle<T> MakeSphericalRectangle(const Vec3<T>& o, const RectLight<T>& l) { return MakeAreaRect(o, l); }
template <class T> LightSample<T> SampleSphericalRectangle(const SphericalRectangle<T>& r, Point2<T> uv) { return SampleRectangleArea(r, uv); }
template <class T> T SphericalRectanglePDF(const SphericalRectangle<T>& r, const Vec3<T>& p) { return RectangleAreaPDF(r, p); }
}
namespace sphrect {
template <class T> Point2<T> InvertSphericalRectangleSample(const SphericalRectangle<T>& r, const Vec3<T>& p) {
    const Vec3<T> d = p - r.corner;
    return {Dot(d, r.ex) / Dot(r.ex, r.ex), Dot(d, r.ey) / Dot(r.ey, r.ey)};
}
}
