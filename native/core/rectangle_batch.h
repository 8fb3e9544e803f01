// Techniques `rectangle` and `rectangle_cosine` over a batch of shading points at once: the setup (MakeRectangleSetup)
// and map (SampleRectangle) of rectangle.h evaluated for SIMD lanes of points in double, with
// the instruction set chosen at run time (Google Highway: AVX-512, AVX2, SSE4 or scalar), so
// one binary runs on any x86-64 and uses the widest vectors the machine has.
//
// The same formulas as rectangle.h in the same precision, branch-free: a lane takes every
// branch's value and keeps its own.  What differs from the scalar code is rounding only (its
// own sin, cos and atan, and a few operations reordered); the tests hold every lane to the
// scalar reference (tests/native/test_rectangle_batch.cpp, tolerances stated there).  Lanes the
// vector code does not handle take the scalar path itself, so their samples are the reference's
// bit for bit: a point that is not finite, a setup that is invalid, or one whose error estimate
// (19) is within a factor of 2 of calling for the Newton polish (20) or the area fallback (21).
// So the batch decides validity, polish and fallback exactly as the scalar code, and the pdf it
// returns is that of the returned point (1 / Omega of the lane's own setup).
#pragma once

#include <cstddef>

#include "light_sample.h"
#include "rect_light.h"

namespace sphrect {

// One rectangle light seen from n shading points: point i's m samples at uv[i m + k] go to
// out[i m + k] (k < m), each as SampleRectangle(MakeRectangleSetup(origins[i], frame), uv[i m + k])
// up to rounding.  Returns how many of the points the vector code handled (the others took the
// scalar path).  No allocation.
size_t SampleRectangleBatch(const RectLightFrame<float>& frame, const Vec3f* origins, size_t n, const Point2<float>* uv,
                            int m, LightSample<float>* out);

// The same for technique `rectangle_cosine` (rectangle_cosine.h), point i with shading normal normals[i]: each
// sample SampleRectangleCosine(MakeRectangleCosineSetup(origins[i], normals[i], frame), uv) up to rounding.  The
// corner weights and the bilinear warp run in the lanes too; a point without a usable normal or below the light's
// horizon takes the scalar path, as do the lanes `rectangle`'s batch gives it.
size_t SampleRectangleCosineBatch(const RectLightFrame<float>& frame, const Vec3f* origins, const Vec3f* normals,
                                  size_t n, const Point2<float>* uv, int m, LightSample<float>* out);

// The instruction set the batch runs on here (e.g. "AVX3", "AVX2"), for benchmarks and reports.
const char* RectangleBatchTarget();

}  // namespace sphrect
