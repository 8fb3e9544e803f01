// Transparent surfaces: Blender's Transparent BSDF, and a Principled BSDF whose Alpha is below 1 (Cycles expands it
// into a Mix Shader of a white Transparent BSDF and the rest, so its transparency is 1 - Alpha).  As in Cycles,
// camera and shadow rays go straight on through them -- transparent bounces, counted apart from max_bounces, so a
// zero-bounce render still sees through -- and the light they bring is filtered by the transparency's colour.
//  - Camera rays (CameraRayThroughTransparent): at each transparent hit the ray goes on with probability
//    q = t / (t + opaque) (t the mean transparency, opaque the other shaders' summed weight), weighted by
//    transparency / q, or stops there and is shaded as an opaque hit weighted by 1 / (1 - q).  Unbiased, one shaded
//    hit per camera sample (each technique shades the same hits); an alpha texture of 0 or 1 decides with no noise.
//  - Shadow rays (ResolveShadowRays, shadow_queue.h): Embree's occlusion filter on meshes with transparent
//    materials (RenderScene::Commit) lets the ray through them and marks it (ShadowRayContext); a marked ray that
//    nothing opaque blocked then multiplies the transparencies of the surfaces it crosses, found in order
//    (ShadowTransmittance).
// More than kMaxTransparentHits transparent surfaces block, as Cycles' transparent_max_bounces (default 8) does.
#pragma once

#include <algorithm>
#include <cstdint>

#include "render/embree_rays.h"
#include "render/scene.h"
#include "shader_globals.h"
#include "surface_hit.h"

namespace sphrect::render {

// What the surface at a hit lets through, and the weight of what it does not.
struct SurfaceTransparency {
    Spectrum transparency;
    float opaque_weight = 1;
};

// A textured material's transparency at texture coordinates tc: its Material evaluated there (mix factors from
// alpha textures).  Out of line: untextured scenes never come here.
// ray: the context of the ray that crosses it (null: the camera ray that made h).
[[gnu::noinline, gnu::cold]] static SurfaceTransparency TexturedTransparency(const RenderScene& scene,
                                                                             const SurfaceHit& h,
                                                                             const svm::RayContext* ray) {
    const Material& material = scene.materials[size_t(h.material)];
    const Bsdf m = material.programmed ? EvaluateBsdfAtHit(material, scene.images, HitShaderGlobals(h, ray))
                                       : EvaluateTexturedBsdf(material, scene.images, h.tc);
    return {m.transparency, m.opaque_weight};
}

// The transparency at hit h (h.tc set: a textured material's hit comes from MakeSurfaceHit<true>) for a ray of
// context `ray` (null: the camera ray that made h), which node programs may read (the Light Path node).
static inline SurfaceTransparency TransparencyAt(const RenderScene& scene, const SurfaceHit& h,
                                                 const svm::RayContext* ray = nullptr) {
    const Bsdf& m = scene.bsdfs[size_t(h.material)];
    if (!m.has_transparency) return {};
    if (m.textured) return TexturedTransparency(scene, h, ray);
    return {m.transparency, m.opaque_weight};
}

// Where a ray that went through a surface at distance t goes on: past t by a margin relative to t (Embree's t is
// accurate to a few ulps), so that it does not find the same surface again.
inline float BeyondHit(float t) { return t + 1e-5f * (t + 1e-3f); }

// The camera ray's choice at transparent hit h: true (go on, throughput *= transparency / q) or false (stop here,
// throughput *= 1 / (1 - q)); u uniform in [0, 1).
static inline bool CameraRayThroughTransparent(const SurfaceTransparency& s, float u, Spectrum& throughput) {
    const float t = Average(s.transparency);
    if (!(t > 0)) return false;
    const float q = s.opaque_weight > 0 ? t / (t + s.opaque_weight) : 1.0f;
    if (u < q) {
        throughput = throughput * (s.transparency / q);
        return true;
    }
    throughput = throughput * (1 / (1 - q));
    return false;
}

// The Light Path node's context at the surface a queued occlusion ray (shadow_queue.h) crosses after `crossed` others:
// a light sample's shadow ray (mask kRayShadow), or a BSDF or phase ray going on to its emitter (mask: its kind).
inline svm::RayContext OcclusionRayContext(unsigned mask, int crossed) {
    return (mask & kRayShadow) ? svm::ShadowRayContext(crossed)
                               : svm::ScatteredRayContext(ScatteredRayFlags(uint8_t(mask)), crossed);
}

// The light a shadow ray keeps after the transparent surfaces along it, found nearest first; the caller knows that
// nothing opaque blocks it (the occlusion pass let it through).  0 past kMaxTransparentHits.
static inline Spectrum ShadowTransmittance(const RenderScene& scene, const RTCRay& shadow) {
    const Ray ray{{shadow.org_x, shadow.org_y, shadow.org_z},
                  {shadow.dir_x, shadow.dir_y, shadow.dir_z},
                  shadow.tnear,
                  shadow.tfar};
    Spectrum kept(1, 1, 1);
    float tnear = shadow.tnear;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int hits = 0;; ++hits) {
        RTCRayHit rh = MakeRTCRayHit(ray.o, ray.d, tnear, shadow.tfar, shadow.mask);
        rtcIntersect1(scene.rtc_scene, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return kept;
        if (hits == kMaxTransparentHits) return {};
        const svm::RayContext context = OcclusionRayContext(shadow.mask, hits);
        kept = kept * TransparencyAt(scene, MakeSurfaceHit<true>(scene, ray, rh), &context).transparency;
        if (IsBlack(kept)) return {};
        tnear = BeyondHit(rh.ray.tfar);
    }
}

}  // namespace sphrect::render
