// Triangle emitters sampled by solid angle (triangle_emitter.h) for a batch of (point, triangle) requests at once:
// the setup and Arvo's map in SIMD lanes of double, each lane its own triangle, with the instruction set chosen at run
// time (Google Highway), as rectangle_batch.h does for rectangles.  The same formulas in the same precision,
// branch-free; the lanes the vector code does not take go to the scalar code itself: a point or triangle that is not
// finite, a setup that is invalid, and one whose solid angle may need the planar recomputation (its error estimate
// within a factor 2 of kTrianglesStableAreaAbove).  So validity is decided as by the scalar code, and every returned
// pdf is that of the returned point (1 / Omega of the lane's own setup).
#pragma once

#include <cstddef>

#include "light_sample.h"
#include "vec3.h"

namespace sphrect {

// A triangle emitter: vertex v0 and edges e1 = v1 - v0, e2 = v2 - v0.
struct TriangleEmitter {
    Vec3f v0, e1, e2;
};

// Request i: triangles[i] seen from origins[i], sampled at uv[i] into out[i], as
// SampleTriangleSolidAngle(MakeTriangleSolidAngleSetup(v0, e1, e2, origins[i]), origins[i], uv[i]) up to rounding.
// Returns how many requests the vector code handled.  No allocation.
size_t SampleTriangleEmitterBatch(const TriangleEmitter* triangles, const Vec3f* origins, size_t n,
                                  const Point2<float>* uv, LightSample<float>* out);

}  // namespace sphrect
