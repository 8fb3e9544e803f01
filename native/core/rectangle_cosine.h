// Technique `rectangle_cosine` (beyond the paper, whose future work asks for
// cosine sampling): warp (u, v) with a bilinear density whose corner weights are
// the clamped cosines between the shading normal and the directions to the
// light's corners (Hart et al., EGSR 2020), then apply the `rectangle` map M.
// pdf(w) = bilinear pdf(M^-1(w)) * pdf_rectangle(w) = bilinear pdf / Omega.  The one
// technique built on another: it is the `rectangle` map (rectangle.h) after a warp.
//
// The weight of the corner (i, j) is taken at M(i, j), so the warp follows
// whichever frame / formulation M uses for this setup (including its area
// fallback, where pdf_rectangle is the area pdf).  A zero or non-finite normal
// gives uniform weights (plain `rectangle`); a light wholly below the horizon
// (all corner cosines <= 0; the rectangle is convex) is invalid.
#pragma once

#include <algorithm>
#include <cmath>

#include "bilinear.h"
#include "rectangle.h"

namespace sphrect {

template <class T>
struct RectangleCosineSetup {
    RectangleSetup<T> rect;
    BilinearWeights w = {1, 1, 1, 1};
    bool valid = false;
};

template <class T>
RectangleCosineSetup<T> MakeRectangleCosineSetup(const Vec3<T>& origin, const Vec3<T>& normal,
                                                 const RectLightFrame<T>& frame) {
    RectangleCosineSetup<T> r{MakeRectangleSetup(origin, frame)};  // built in place
    if (!r.rect.valid) return r;
    const Vec3d n(normal);
    const double ln = Length(n);
    if (!(ln > 0) || !std::isfinite(ln)) {
        r.valid = true;  // no usable normal: uniform weights
        return r;
    }
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const Vec3d c = RectangleCornerVector(r.rect, i, j);
            r.w[i + 2 * j] = std::max(0.0, Dot(n, c) / (ln * Length(c)));
        }
    r.valid = r.w[0] + r.w[1] + r.w[2] + r.w[3] > 0;
    return r;
}

template <class T>
RectangleCosineSetup<T> MakeRectangleCosineSetup(const Vec3<T>& origin, const Vec3<T>& normal,
                                                 const RectLight<T>& light) {
    return MakeRectangleCosineSetup(origin, normal, MakeRectLightFrame(light));
}

template <class T>
LightSample<T> SampleRectangleCosine(const RectangleCosineSetup<T>& r, Point2<T> uv) {
    if (!r.valid) return {};
    const Point2<double> w = SampleBilinear({double(uv.u), double(uv.v)}, r.w);
    LightSample<T> s = SampleRectangleAt(r.rect, w.u, w.v);
    s.pdf = T(BilinearPDF(w, r.w) * double(s.pdf));
    if (!std::isfinite(s.pdf)) s.pdf = 0;
    return s;
}

template <class T>
T RectangleCosinePDF(const RectangleCosineSetup<T>& r, const Vec3<T>& p) {
    if (!r.valid) return 0;
    const T pdf = T(BilinearPDF(InvertRectangle(r.rect, p), r.w) * double(RectanglePDF(r.rect, p)));
    return std::isfinite(pdf) ? pdf : T(0);
}

}  // namespace sphrect
