// PLACEHOLDER (to be replaced by the real Arvo two-triangle technique): delegates to area sampling.
#pragma once
#include "area_sampling.h"
namespace sphrect {
template <class T> using TwoTriangles = AreaRect<T>;
template <class T> TwoTriangles<T> MakeTwoTriangles(const Vec3<T>& o, const RectLight<T>& l) { return MakeAreaRect(o, l); }
template <class T> LightSample<T> SampleTwoTriangles(const TwoTriangles<T>& r, Point2<T> uv) { return SampleRectangleArea(r, uv); }
template <class T> T TwoTrianglesPDF(const TwoTriangles<T>& r, const Vec3<T>& p) { return RectangleAreaPDF(r, p); }
}
