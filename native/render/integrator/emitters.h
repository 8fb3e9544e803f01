// What the two strategies bring from the emitters: a light sample on the chosen area light,
// and the emitters a BSDF or phase sample's ray reaches, each queued with its occlusion ray.
#pragma once

#include <algorithm>
#include <cmath>

#include "shade_context.h"
#include "shadow_queue.h"
#include "textured_emission.h"
#include "timed_light_sampling.h"

namespace sphrect::render {

// A light sample on the chosen area light, with the radiance it sends back and its solid-angle
// pdf including the light's choice (pmf * pdf).  Not valid without a light, for an invalid
// sample, or where the light sends nothing (its back).
struct EmitterSample {
    bool valid = false;
    Vec3f dir;  // unit, towards the light
    float dist = 0;
    Spectrum le;
    float pdf = 0;
};

// A light sample on an emissive mesh, whose surface is Embree geometry: the shadow ray must end
// before it.  The point is moved off the light's plane towards the shading point by more than
// OffsetOrigin moves the ray's origin (each 1e-4 (1 + max |coordinate|)), so that the ray, even
// grazing, ends on the shading point's side: with n' the normal towards the origin, the end lies
// n' . (end - point) >= eps - |origin offset| > 0 from the plane.  The pdf stays the sampled
// point's (the move is ~1e-4 relative).
static inline void PullOffMeshLight(const AreaLight& l, LightSample<float>& ls) {
    const Vec3f origin = ls.point - ls.dir * ls.dist;
    const float eps = 2e-4f * (1 + std::max(MaxAbsComponent(ls.point), MaxAbsComponent(origin)));
    const Vec3f n_toward_origin = Dot(l.n, origin - ls.point) >= 0 ? l.n : -l.n;
    const Vec3f w = ls.point + n_toward_origin * eps - origin;
    const float dist = Length(w);
    if (!(dist > 0)) return;
    ls.dir = w / dist;
    ls.dist = dist;
}

// A BSDF ray's pdf_dir for a singular lobe's ray: no light sample finds what it finds, so Cycles skips MIS
// (PATH_RAY_MIS_SKIP) and it counts with weight 1, whatever the MIS mode.
constexpr float kSingularRayPdf = kInf;

// The MIS weight of an emitter a BSDF or phase ray of density pdf_dir found, against its light sample's pdf
// (computed only when needed: a singular ray's weight is 1).
template <typename LightPdf>
static inline float FoundEmitterMisWeight(const ShadeContext& c, float pdf_dir, LightPdf&& pdf_light) {
    return pdf_dir == kSingularRayPdf ? 1.0f : MisWeight(c.mis, pdf_dir, pdf_light());
}

// The light sampling a singular ray's emitter search consults: none (FoundEmitterMisWeight asks nothing), so that
// QueueSingularRays needs no TimedLightSamplingAt.
struct NoLightPdfs {
    float PDF(int, const Vec3f&) { return 0; }
    float SoftLightPDF(const DeltaLight&, int) { return 0; }
};

// The Light Path flags of the surface a BSDF ray of kind `ray` and density pdf_dir finds: a singular lobe's ray is
// also Is Singular (PATH_RAY_SINGULAR).
constexpr uint8_t ScatteredRayFlagsOf(uint8_t ray, float pdf_dir) {
    return uint8_t(ScatteredRayFlags(ray) | (pdf_dir == kSingularRayPdf ? svm::kRayIsSingular : 0));
}

template <Technique K>
static inline EmitterSample SampleChosenEmitter(const ShadeContext& c, ChosenLight light, Point2<float> u,
                                                TimedLightSamplingAt<K>& light_sampling) {
    if (light.index < 0) return {};
    LightSample<float> ls = light.batched ? *light.batched : light_sampling.Sample(light.index, u);
    if (!(ls.pdf > 0 && std::isfinite(ls.pdf))) return {};
    const AreaLight& l = c.scene.area_lights[light.index];
    if (l.on_mesh) PullOffMeshLight(l, ls);
    const Spectrum le =
        l.texture < 0 ? EmittedRadiance(l, -ls.dir) : TexturedEmissionAtPoint(c.scene, l, ls.point, -ls.dir, ls.dist);
    if (IsBlack(le)) return {};
    return {true, ls.dir, ls.dist, le, light.pmf * ls.pdf};
}

// The emissive mesh triangle hit rh of the ray (o, d), `crossed` transparent surfaces past its origin, if it is one,
// weighted against light sampling like the analytic lights below.  Its occlusion ray is queued as for every emitter
// (the surfaces before it were let through; one extra ray per hit, kept for one path through the shadow queue).
template <Technique K, bool kMedium, typename LightPdfs>
static inline void QueueMeshEmitterHit(const ShadeContext& c, const RTCRayHit& rh, const Vec3f& o, const Vec3f& d,
                                       float pdf_dir, uint8_t ray, int crossed, LightPdfs& light_sampling,
                                       const ShadowSink& sink) {
    const MeshData& m = c.scene.meshes[rh.hit.geomID];
    if (m.triangle_light.empty()) return;
    const int i = m.triangle_light[rh.hit.primID];
    if (i < 0) return;
    const float t = rh.ray.tfar;
    const AreaLight& l = c.scene.area_lights[i];
    const Spectrum le =
        l.texture < 0 ? EmittedRadiance(l, -d)
                      : TexturedEmissionAtHit(c.scene, l, rh.hit.primID, rh.hit.u, rh.hit.v, o, d, t,
                                              svm::ScatteredRayContext(ScatteredRayFlagsOf(ray, pdf_dir), crossed));
    if (IsBlack(le)) return;
    const float w = FoundEmitterMisWeight(c, pdf_dir, [&] { return light_sampling.PDF(i, o + d * t); });
    sink.Add(o, d, t, le * SegmentTransmittance<kMedium>(c.scene.medium, t) * w, ray);
}

// The emitter-search rays shading traces one at a time (a BSDF ray in a scene with emissive meshes), counted and timed
// per thread for the cost model: RenderTile reads and clears them per technique pass (TechniqueTally::rays,
// trace_seconds), as it times the occlusion stream.
struct InlineRayTally {
    uint64_t rays = 0, ticks = 0;
};
inline thread_local InlineRayTally inline_rays;

// rtcIntersect1, counted and timed in inline_rays (and with RenderOptions::added_ray_cost's wait).
static inline void IntersectInline(const ShadeContext& c, RTCIntersectContext* ctx, RTCRayHit* rh) {
    const uint64_t t0 = ReadTicks();
    rtcIntersect1(c.scene.rtc_scene, ctx, rh);
    if (c.added_ray_ticks) SpinTicks(c.added_ray_ticks);
    inline_rays.ticks += ReadTicks() - t0;
    ++inline_rays.rays;
}

// In a scene with transparent surfaces: the emitters the ray (o, d) finds from its first hit rh on, past the
// transparent surfaces (their filtering is the occlusion ray's: ResolveShadowRays) -- an emitter that may be
// transparent counts and lets the ray on, as a Cycles path adds a surface's emission before going through it.
template <Technique K, bool kMedium, typename LightPdfs>
[[gnu::noinline]] static void QueueMeshEmittersThroughTransparent(const ShadeContext& c, RTCRayHit rh, const Vec3f& o,
                                                                  const Vec3f& d, float pdf_dir, uint8_t ray,
                                                                  LightPdfs& light_sampling, const ShadowSink& sink) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int crossed = 0; rh.hit.geomID != RTC_INVALID_GEOMETRY_ID; ++crossed) {
        const bool through = c.scene.MayBeTransparent(c.scene.meshes[rh.hit.geomID], rh.hit.primID);
        if (through && crossed == kMaxTransparentHits) return;
        QueueMeshEmitterHit<K, kMedium>(c, rh, o, d, pdf_dir, ray, crossed, light_sampling, sink);
        if (!through) return;
        rh = MakeRTCRayHit(o, d, BeyondHit(rh.ray.tfar), kInf, ray);
        IntersectInline(c, &ctx, &rh);
    }
}

// The emissive mesh triangle the ray (o, d) hits first, if any (and in a scene with transparent surfaces those past
// them): one Embree ray instead of a loop over the mesh's lights.
template <Technique K, bool kMedium, typename LightPdfs>
static inline void QueueMeshEmitterAlongRay(const ShadeContext& c, const Vec3f& o, const Vec3f& d, float pdf_dir,
                                            uint8_t ray, LightPdfs& light_sampling, const ShadowSink& sink) {
    RTCRayHit rh = MakeRTCRayHit(o, d, 0, kInf, ray);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    IntersectInline(c, &ctx, &rh);
    if (c.scene.has_transparency)
        return QueueMeshEmittersThroughTransparent<K, kMedium>(c, rh, o, d, pdf_dir, ray, light_sampling, sink);
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID)
        QueueMeshEmitterHit<K, kMedium>(c, rh, o, d, pdf_dir, ray, 0, light_sampling, sink);
}

// A light sample of the image world (environment_light.h; c.environment set): its direction, radiance and
// solid-angle pdf, the light evaluated once per light sample (no choice).  Its occlusion ray goes to infinity.
static inline EmitterSample SampleEnvironmentEmitter(const ShadeContext& c, Point2<float> u) {
    const EnvironmentLight& e = *c.environment;
    const EnvironmentSample s = SampleEnvironment(e, u);
    if (!(s.pdf > 0 && std::isfinite(s.pdf))) return {};
    const Spectrum le = EnvironmentRadiance(e, c.scene.images[size_t(e.image)], s.wi);
    if (IsBlack(le)) return {};
    return {true, s.wi, kInf, le, s.pdf};
}

// The image world a BSDF or phase ray (o, d) of kind `ray` finds if it escapes, weighted against its light sample
// (Le T w).
static inline void QueueEnvironmentAlongRay(const ShadeContext& c, const Vec3f& o, const Vec3f& d, float pdf_dir,
                                            uint8_t ray, const ShadowSink& sink) {
    const EnvironmentLight& e = *c.environment;
    const Spectrum le = EnvironmentRadiance(e, c.scene.images[size_t(e.image)], d);
    if (IsBlack(le)) return;
    sink.Add(o, d, kInf,
             le * c.environment_transmittance * FoundEmitterMisWeight(c, pdf_dir, [&] { return EnvironmentPDF(e, d); }),
             ray);
}

// For the ray (o, d): the background where the ray escapes, and with MIS the image world and every area light it
// crosses, weighted against light sampling (Le T w).  A light counts when no surface lies
// before it -- the same test as for its light samples -- so a ray that reaches no emitter is
// not traced at all.  pdf_dir: the direction's pdf under BSDF/phase sampling; `sink` carries
// its weight f cos / pdf (kSingularRayPdf: a singular lobe's ray, everything it finds of weight 1, with or without
// MIS).  ray: the ray's kind (ray_visibility.h), which meshes and lights hidden from it let through.  light_sampling:
// the shading point's TimedLightSamplingAt (the found emitters' light pdfs), or NoLightPdfs for a singular ray.
template <Technique K, bool kMedium, typename LightPdfs>
static inline void QueueEmittersAlongRay(const ShadeContext& c, const Vec3f& o, const Vec3f& d, float pdf_dir,
                                         uint8_t ray, LightPdfs& light_sampling, const ShadowSink& sink) {
    const bool world_found = c.scene.world_visibility.FoundBy(ray);  // the world's Ray Visibility
    if (!IsBlack(c.sky) && world_found) sink.Add(o, d, kInf, c.sky, ray);
    // Without MIS the image world and the lights are their light samples' alone (a singular ray: its own).
    if (c.mis == MisMode::None && pdf_dir != kSingularRayPdf) return;
    if (c.environment && world_found) QueueEnvironmentAlongRay(c, o, d, pdf_dir, ray, sink);
    if (c.scene.has_mesh_lights) QueueMeshEmitterAlongRay<K, kMedium>(c, o, d, pdf_dir, ray, light_sampling, sink);
    // The analytic lights (the rest are QueueMeshEmitterAlongRay's).
    c.scene.analytic_light_finder.ForEachCrossing(o, d, 0, kInf, LightsSought::All, [&](int i, float t) {
        const AreaLight& l = c.scene.area_lights[i];
        if (!l.vis.FoundBy(ray)) return;
        const Spectrum le = RadianceOfCrossedLight(c.scene, l, o, d, t);
        if (IsBlack(le)) return;
        const float w = FoundEmitterMisWeight(c, pdf_dir, [&] { return light_sampling.PDF(i, o + d * t); });
        sink.Add(o, d, t, le * SegmentTransmittance<kMedium>(c.scene.medium, t) * w, ray);
    });
    // Soft point, spot and sun lights (delta_light.h): the cone each subtends at o.
    for (const SoftLightRef& s : c.scene.soft_lights) {
        const DeltaLight& l = c.scene.delta_lights[s.delta];
        if (!l.vis.FoundBy(ray)) continue;
        const SoftLightCrossing x = CrossSoftLight(l, o, d);
        if (!x.hit) continue;
        const float w =
            FoundEmitterMisWeight(c, pdf_dir, [&] { return light_sampling.SoftLightPDF(l, s.tree_emitter); });
        sink.Add(o, d, x.t, x.le * SegmentTransmittance<kMedium>(c.scene.medium, x.t) * w, ray);
    }
}

}  // namespace sphrect::render
