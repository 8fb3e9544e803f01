// Technique `triangles` (triangles.h) over a batch of shading points at once: the rectangle's two spherical triangles
// set up and Arvo's map run in SIMD lanes of double, one lane per point, with the instruction set chosen at run time
// (Google Highway), as rectangle_batch.h does for `rectangle`.  The same formulas in the same precision, branch-free;
// what differs from the scalar code is rounding only.  The lanes the vector code does not take go to the scalar code
// itself, so their samples are the reference's bit for bit: a point that is not finite, a setup that is invalid, one
// whose triangle's solid angle may need the planar recomputation (its error estimate within a factor 2 of
// kTrianglesStableAreaAbove), one whose solid angle is below 1e-30 sr (1 / Omega nearing float's range), and one where
// a triangle's angle at its first vertex is undefined.  So validity is decided as by the scalar code, and the pdf is
// that of the returned point (1 / (Omega_0 + Omega_1) of the lane's own setup).
#pragma once

#include <cstddef>

#include "light_sample.h"
#include "rect_light.h"

namespace sphrect {

// One rectangle light seen from n shading points: point i's m samples at uv[i m + k] go to out[i m + k] (k < m), each
// as SampleTriangles(MakeTrianglesSetup(origins[i], frame), uv[i m + k]) up to rounding.  Returns how many of the
// points the vector code handled.  No allocation.
size_t SampleTrianglesBatch(const RectLightFrame<float>& frame, const Vec3f* origins, size_t n, const Point2<float>* uv,
                            int m, LightSample<float>* out);

}  // namespace sphrect
