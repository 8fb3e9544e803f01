// The renderer's rays in Embree's terms, shared with the ray-casting benchmark so that its
// baseline traces exactly what the renderer traces.
#pragma once

#include <embree3/rtcore.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "sampling_util.h"

namespace sphrect::render {

// Length of the shadow ray towards a light `dist` away (kInf: the sun), stopping just short of it.
inline float ShadowRayLength(float dist) { return std::isinf(dist) ? kInf : dist * (1 - 1e-4f); }

// Shadow-ray origin pushed off the surface along the geometric normal (scale-aware).
[[gnu::always_inline]] inline Vec3f OffsetOrigin(const Vec3f& p, const Vec3f& ng) {
    return p + ng * (1e-4f * (1 + MaxAbsComponent(p)));
}

// Embree's ray (and ray + empty hit) for the segment (tnear, tfar) of o + t d; `mask`: the kinds of the ray
// (ray_visibility.h), which meshes hidden from all of them let through (their geometry mask).
inline RTCRay MakeRTCRay(const Vec3f& o, const Vec3f& d, float tnear, float tfar, unsigned mask = 0xffffffffu) {
    return {o.x, o.y, o.z, tnear, d.x, d.y, d.z, 0, tfar, mask, 0, 0};
}

inline RTCRayHit MakeRTCRayHit(const Vec3f& o, const Vec3f& d, float tnear, float tfar, unsigned mask = 0xffffffffu) {
    RTCRayHit rh;
    rh.ray = MakeRTCRay(o, d, tnear, tfar, mask);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

// Traces n camera rays (in place) as one coherent stream: a chunk's camera rays leave one point
// (a small lens; or are parallel) and cover one tile, so Embree's packet traversal is faster on
// them than ray by ray (docs/architecture.md, measured choices).
inline void IntersectCameraRays(RTCScene scene, RTCRayHit* rays, size_t n) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect1M(scene, &ctx, rays, unsigned(n), sizeof(RTCRayHit));
}

// The context of occlusion queries.  Meshes with transparent materials have an occlusion filter (RenderScene::Commit)
// that, given crossed_transparent, does not count their transparent triangles as occluders and sets
// crossed_transparent[ray id] instead (integrator/transparency.h); without it they block like any surface.
struct ShadowRayContext {
    RTCIntersectContext rtc;  // first: the filter casts Embree's context pointer back to this
    uint8_t* crossed_transparent = nullptr;
};

// Traces n occlusion rays (in place; `stride` bytes apart, so a payload may follow each) as one
// incoherent stream: faster than a call per ray, and than the same stream flagged coherent (the
// rays start all over a tile; docs/architecture.md, measured choices).
// A blocked ray's tfar becomes -inf.
inline void OccludeShadowRays(RTCScene scene, RTCRay* rays, size_t n, size_t stride,
                              uint8_t* crossed_transparent = nullptr) {
    if (n == 0) return;
    ShadowRayContext ctx;
    rtcInitIntersectContext(&ctx.rtc);  // RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT
    ctx.crossed_transparent = crossed_transparent;
    rtcOccluded1M(scene, &ctx.rtc, rays, unsigned(n), stride);
}

}  // namespace sphrect::render
