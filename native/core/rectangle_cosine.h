// PLACEHOLDER (to be replaced by the bilinear-warped map): delegates to area sampling.
#pragma once
#include "area_sampling.h"
namespace sphrect {
template <class T> using CosineRectangle = AreaRect<T>;
template <class T> CosineRectangle<T> MakeCosineRectangle(const Vec3<T>& o, const Vec3<T>&, const RectLight<T>& l) { return MakeAreaRect(o, l); }
template <class T> LightSample<T> SampleCosineRectangle(const CosineRectangle<T>& r, Point2<T> uv) { return SampleRectangleArea(r, uv); }
template <class T> T CosineRectanglePDF(const CosineRectangle<T>& r, const Vec3<T>& p) { return RectangleAreaPDF(r, p); }
}
