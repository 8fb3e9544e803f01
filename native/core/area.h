// Technique `area`: uniform over the rectangle's area, pdf converted to solid angle,
// p(w) = d^3 / (A h) (AreaPDFLocal, local_rect.h).  The baseline of the paper, and the map
// `rectangle` falls back to where its own cannot resolve (u, v).
#pragma once

#include "local_rect.h"

namespace sphrect {

// The point corner + a ex + b ey, (a, b) in [0,1]^2, with its area-sampling pdf.
template <class T>
LightSample<T> SampleAreaAt(const LocalRect<T>& r, double a, double b) {
    if (!r.valid) return {};
    a = ClampNaN(a, 0, 1);
    b = ClampNaN(b, 0, 1);
    const double X = r.x0 + a * r.wx, Y = r.y0 + b * r.wy;
    return LightSampleAt(r, a, b, X, Y, AreaPDFLocal(r, X, Y));
}

template <class T>
LightSample<T> SampleArea(const LocalRect<T>& r, Point2<T> uv) {
    return SampleAreaAt(r, double(uv.u), double(uv.v));
}

// Solid-angle pdf of the point p on the light; 0 for an invalid setup or where the pdf is
// not representable.
template <class T>
T AreaPDF(const LocalRect<T>& r, const Vec3<T>& p) {
    if (!r.valid) return 0;
    const Point2<double> e = EdgeOffsets(r, p);
    return AreaPDFLocal(r, r.x0 + e.u, r.y0 + e.v);
}

// Inverse of the area map: the fractions of the point along ex and ey, in [0,1] (NaN -> 0).
template <class T>
Point2<double> InvertArea(const LocalRect<T>& r, const Vec3<T>& p) {
    const Point2<double> e = EdgeOffsets(r, p);
    return {ClampNaN(e.u / r.wx, 0, 1), ClampNaN(e.v / r.wy, 0, 1)};
}

}  // namespace sphrect
