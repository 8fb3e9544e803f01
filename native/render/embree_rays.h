// The renderer's rays in Embree's terms, shared with the ray-casting benchmark so that its
// baseline traces exactly what the renderer traces.
#pragma once

#include <embree3/rtcore.h>

#include <cmath>

#include "sampling_util.h"

namespace sphrect::render {

// Length of the shadow ray towards a light `dist` away (kInf: the sun), stopping just short of it.
inline float ShadowRayLength(float dist) { return std::isinf(dist) ? kInf : dist * (1 - 1e-4f); }

// Shadow-ray origin pushed off the surface along the geometric normal (scale-aware).
inline Vec3f OffsetOrigin(const Vec3f& p, const Vec3f& ng) { return p + ng * (1e-4f * (1 + MaxAbsComponent(p))); }

// Embree's ray (and ray + empty hit) for the segment (tnear, tfar) of o + t d.
inline RTCRay MakeRTCRay(const Vec3f& o, const Vec3f& d, float tnear, float tfar) {
    return {o.x, o.y, o.z, tnear, d.x, d.y, d.z, 0, tfar, 0xffffffffu, 0, 0};
}

inline RTCRayHit MakeRTCRayHit(const Vec3f& o, const Vec3f& d, float tnear, float tfar) {
    RTCRayHit rh;
    rh.ray = MakeRTCRay(o, d, tnear, tfar);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

}  // namespace sphrect::render
