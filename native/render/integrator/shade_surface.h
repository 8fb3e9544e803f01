// Direct light reflected at the camera ray's surface hit: per light sample one sample of the
// area lights (technique K) and, for MIS and the background, one BSDF sample; delta lights
// once.  Everything is queued on a ShadowSink with its occlusion ray.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>

#include "emitters.h"
#include "resampled_light_choice.h"
#include "render/bsdf.h"
#include "shader_globals.h"
#include "surface_hit.h"

namespace sphrect::render {

// A surface point as shading sees it: the hit, its material, the shading frame, the direction
// towards the camera in it, and where its occlusion rays start (off the surface, on the camera's side).
struct SurfaceShadingPoint {
    const SurfaceHit& hit;
    const Bsdf& material;
    Frame frame;
    Vec3f wo;
    Vec3f origin;
};

// Where a ray leaving towards world direction `dir` (wi in the shading frame) starts: off the camera's side,
// or for a translucent material off the other side; false where the direction reaches no lobe (the geometric
// and shading normals disagree on its side, or it is below and the material is not translucent).
template <bool kGlossy>
static inline bool RayOriginTowards(const SurfaceShadingPoint& sp, const Vec3f& wi, const Vec3f& dir, Vec3f& origin) {
    const float side = Dot(dir, sp.hit.ng);
    if (wi.z > 0 && side > 0) {
        origin = sp.origin;
        return true;
    }
    if constexpr (kGlossy) {
        if (sp.material.has_translucent && wi.z < 0 && side < 0) {
            origin = OffsetOrigin(sp.hit.p, -sp.hit.ng);
            return true;
        }
    }
    return false;
}

// A light sample's shadow ray.
struct ShadowRay {
    Vec3f origin, dir;
    float dist;
};

// The shadow ray of a light sample towards `dir` (wi in the shading frame), `dist` away: from RayOriginTowards' origin,
// or, near the terminator of a smooth mesh with a shadow terminator offset, from the smooth surface, towards the same
// point of the light (the same direction for one infinitely far), and then also for directions below the flat
// triangle (terminator.h, as Cycles 3.4).  False where RayOriginTowards finds no origin.
template <bool kGlossy>
static inline bool ShadowRayTowards(const SurfaceShadingPoint& sp, const Vec3f& wi, const Vec3f& dir, float dist,
                                    ShadowRay& ray) {
    // Under a normal map or Bump, Cycles tells reflection from transmission, and offsets the terminator, by the
    // shading normal before it (sd->N): a direction below that one no reflection lobe sees (shader_bsdf_is_
    // transmission), however the mapped normal leans.
    float cos_n = wi.z;
    if constexpr (kGlossy) {  // (normal maps and Bumps take the glossy kernel)
        if (sp.hit.mapped && wi.z > 0) {
            cos_n = Dot(dir, sp.hit.ns_unmapped);
            if (!(cos_n > 0)) return false;
        }
    }
    if (sp.hit.terminator_offset > 0 && wi.z > 0) {
        const float cos_ng = Dot(dir, sp.hit.ng);
        const float amount = TerminatorOffsetAmount(cos_n, cos_ng, sp.hit.terminator_offset);
        if (amount > 0) {
            ray = {TerminatorShadowOrigin(sp.hit.p, sp.hit.ng, sp.hit.terminator_lift, amount, cos_ng), dir, dist};
            if (dist < kInf) {
                const Vec3f to_light = sp.hit.p + dir * dist - ray.origin;
                ray.dist = Length(to_light);
                if (!(ray.dist > 0)) return false;
                ray.dir = to_light / ray.dist;
            }
            return true;
        }
    }
    ray.dir = dir;
    ray.dist = dist;
    return RayOriginTowards<kGlossy>(sp, wi, dir, ray.origin);
}

// A light sample of a light whose visibility is not the default (LightVisibility): f of the lobes it lights, with
// their pdf alone for the MIS weight against pdf_light (0: none), 1 for a light without Multiple Importance; no
// shadow ray without Cast Shadow.  The value is QueueSurfaceLightSample's (pdf_div: its pdf) or
// QueueSurfaceDeltaLight's (1), computed in their order, so that a light that lights every class gives theirs bit for
// bit.  Out of line: scenes whose lights are all visible never come here.
template <bool kGlossy, bool kMedium>
[[gnu::noinline, gnu::cold]] static void QueueLightWithVisibility(const ShadeContext& c, const SurfaceShadingPoint& sp,
                                                                  const Vec3f& dir, float dist, const Spectrum& le,
                                                                  float pdf_light, float pdf_div,
                                                                  const LightVisibility& vis, const ShadowSink& sink) {
    const Vec3f wi = sp.frame.ToLocal(dir);
    ShadowRay ray;
    if (!ShadowRayTowards<kGlossy>(sp, wi, dir, dist, ray)) return;
    const uint8_t classes = vis.rays() & kRayBsdfClasses;
    const Spectrum f = EvalBsdf<kGlossy>(LobesLitBy(sp.material, classes), sp.wo, wi);
    if (IsBlack(f)) return;
    const float w = pdf_light > 0 && c.mis != MisMode::None && vis.use_mis()
                        ? MisWeight(c.mis, pdf_light, BsdfPDFOfClasses<kGlossy>(sp.material, sp.wo, wi, classes))
                        : 1.0f;
    sink.Add(ray.origin, ray.dir, ray.dist,
             f * le * SegmentTransmittance<kMedium>(c.scene.medium, dist) * (std::abs(wi.z) * w / pdf_div),
             vis.ShadowMask());
}

// A light sample e seen through transmittance t: f Le t cos w / pdf, w its MIS weight against the BSDF sample (an area
// light's point, or a direction of the image world: e.dist kInf).
template <bool kGlossy>
static inline void QueueSurfaceEmitterSample(const ShadeContext& c, const SurfaceShadingPoint& sp,
                                             const EmitterSample& e, const Spectrum& t, const ShadowSink& sink) {
    const Vec3f wi = sp.frame.ToLocal(e.dir);
    ShadowRay ray;
    if (!ShadowRayTowards<kGlossy>(sp, wi, e.dir, e.dist, ray)) return;
    const Spectrum f = EvalBsdf<kGlossy>(sp.material, sp.wo, wi);
    if (IsBlack(f)) return;
    const float w = c.mis == MisMode::None ? 1.0f : MisWeight(c.mis, e.pdf, BsdfPDF<kGlossy>(sp.material, sp.wo, wi));
    sink.Add(ray.origin, ray.dir, ray.dist, f * e.le * t * (std::abs(wi.z) * w / e.pdf));
}

// Light sampling: f Le T cos w / (pmf pdf) for a point on the chosen light, w its MIS weight
// against the BSDF sample.
template <Technique K, bool kGlossy, bool kMedium>
static inline void QueueSurfaceLightSample(const ShadeContext& c, const SurfaceShadingPoint& sp, ChosenLight light,
                                           TimedLightSamplingAt<K>& light_sampling, const ShadowSink& sink) {
    const EmitterSample e = SampleChosenEmitter<K>(c, light, light.u, light_sampling);
    if (!e.valid) return;
    if (const LightVisibility& vis = c.scene.area_lights[light.index].vis; !vis.IsDefault())
        return QueueLightWithVisibility<kGlossy, kMedium>(c, sp, e.dir, e.dist, e.le, e.pdf, e.pdf, vis, sink);
    QueueSurfaceEmitterSample<kGlossy>(c, sp, e, SegmentTransmittance<kMedium>(c.scene.medium, e.dist), sink);
}

// BSDF sampling: finds the area lights (MIS partner of the light sample) and the background,
// with the sample's weight f cos / pdf.
template <Technique K, bool kGlossy, bool kMedium>
static inline void QueueSurfaceBsdfSample(const ShadeContext& c, const SurfaceShadingPoint& sp, Point2<float> u,
                                          TimedLightSamplingAt<K>& light_sampling, const ShadowSink& sink) {
    const BsdfSample bs = SampleBsdf<kGlossy>(sp.material, sp.wo, u);
    if (!(bs.pdf > 0)) return;
    const Vec3f wi_world = sp.frame.FromLocal(bs.wi);
    Vec3f origin;
    if (!RayOriginTowards<kGlossy>(sp, bs.wi, wi_world, origin)) return;
    // The ray's kind matters only where a mesh or light hides from some (RenderScene::ray_visibility).
    const uint8_t ray = c.scene.ray_visibility ? SampledRayKind<kGlossy>(sp.material, u) : kRayDiffuse;
    QueueEmittersAlongRay<K, kMedium>(c, origin, wi_world, bs.pdf, ray, light_sampling,
                                      sink.Scaled(bs.f * (std::abs(bs.wi.z) / bs.pdf)));
}

// Light sampling of the image world: f Le T cos w / pdf, w its MIS weight against the BSDF sample.
template <bool kGlossy, bool kMedium>
static inline void QueueSurfaceEnvironmentSample(const ShadeContext& c, const SurfaceShadingPoint& sp, Point2<float> u,
                                                 const ShadowSink& sink) {
    const EmitterSample e = SampleEnvironmentEmitter(c, u);
    if (!e.valid) return;
    if (const LightVisibility& vis = c.scene.world_visibility; !vis.IsDefault())
        return QueueLightWithVisibility<kGlossy, kMedium>(c, sp, e.dir, e.dist, e.le, e.pdf, e.pdf, vis, sink);
    QueueSurfaceEmitterSample<kGlossy>(c, sp, e, c.environment_transmittance, sink);
}

// One point, spot or sun light: f Li T cos; a soft one's direction from the point u, weighted against the
// BSDF sample by MIS (its pdf pmf * the cone's, pmf the light's choice: 1 when evaluated once).
template <bool kGlossy, bool kMedium>
static inline void QueueSurfaceDeltaLight(const ShadeContext& c, const SurfaceShadingPoint& sp, const DeltaLight& d,
                                          Point2<float> u, float pmf, const ShadowSink& sink) {
    const DeltaIllumination di = IlluminateFromDelta(d, sp.hit.p, u);
    if (IsBlack(di.li)) return;
    if (!d.vis.IsDefault())
        return QueueLightWithVisibility<kGlossy, kMedium>(c, sp, di.wi, di.dist, di.li, di.pdf > 0 ? pmf * di.pdf : 0,
                                                          1, d.vis, sink);
    const Vec3f wi = sp.frame.ToLocal(di.wi);
    ShadowRay ray;
    if (!ShadowRayTowards<kGlossy>(sp, wi, di.wi, di.dist, ray)) return;
    const Spectrum f = EvalBsdf<kGlossy>(sp.material, sp.wo, wi);
    if (IsBlack(f)) return;
    const float w = di.pdf > 0 && c.mis != MisMode::None
                        ? MisWeight(c.mis, pmf * di.pdf, BsdfPDF<kGlossy>(sp.material, sp.wo, wi))
                        : 1.0f;
    sink.Add(ray.origin, ray.dir, ray.dist,
             f * di.li * SegmentTransmittance<kMedium>(c.scene.medium, di.dist) * (std::abs(wi.z) * w));
}

// The light sample of the emitter `light` that was chosen (none if it is neither): a point or spot light the tree
// chose, f Li T cos / pmf (MIS if soft), or a point on an area light.
template <Technique K, bool kGlossy, bool kMedium>
static inline void QueueChosenLightSample(const ShadeContext& c, const SurfaceShadingPoint& sp, ChosenLight light,
                                          TimedLightSamplingAt<K>& light_sampling, const ShadowSink& sink) {
    if (light.delta >= 0)
        return QueueSurfaceDeltaLight<kGlossy, kMedium>(c, sp, c.scene.delta_lights[light.delta], light.u, light.pmf,
                                                        sink.Scaled(1.0f / light.pmf));
    QueueSurfaceLightSample<K, kGlossy, kMedium>(c, sp, light, light_sampling, sink);
}

// Light selection "ris": the light sample resampled from c.ris_candidates candidates, the first from light_point, the
// others from it shifted by rng (resampled_light_choice.h); only the kept one's shadow ray stays queued.
template <Technique K, bool kGlossy, bool kMedium>
static inline void QueueResampledLightSample(const ShadeContext& c, const SurfaceShadingPoint& sp,
                                             Point2<float> light_point, TimedLightSamplingAt<K>& light_sampling,
                                             PCG32& rng, const ShadowSink& sink) {
    LightSampleReservoir reservoir(sink);
    const ShadowSink candidate_sink = reservoir.CandidateSink();
    for (int k = 0; k < c.ris_candidates; ++k) {
        const Point2<float> point = k == 0 ? light_point : ShiftedCandidatePoint(light_point, rng);
        QueueChosenLightSample<K, kGlossy, kMedium>(c, sp, light_sampling.Choose(point), light_sampling,
                                                    candidate_sink);
        reservoir.Weigh(rng.NextFloat());
    }
    reservoir.Finish();
}

// The delta lights evaluated once per camera sample (ForEachDeltaLightEvaluatedOnce: all with "power",
// suns with "tree"); a soft one sampled once per light sample instead, with its light point (of
// light_points[0, light_samples)), like the lights chosen per light sample.
template <bool kGlossy, bool kMedium>
static inline void QueueSurfaceDeltaLights(const ShadeContext& c, const SurfaceShadingPoint& sp,
                                           const Point2<float>* light_points, const ShadowSink& sink) {
    ForEachDeltaLightEvaluatedOnce(c.scene, c.light_selection, [&](const DeltaLight& d) {
        if (!IsSoft(d)) return QueueSurfaceDeltaLight<kGlossy, kMedium>(c, sp, d, {}, 1, sink);
        const ShadowSink pair_sink = sink.Scaled(1.0f / c.light_samples);
        for (int j = 0; j < c.light_samples; ++j)
            QueueSurfaceDeltaLight<kGlossy, kMedium>(c, sp, d, light_points[j], 1, pair_sink);
    });
}

// The singular lobes' rays (bsdf/singular.h): each lobe's mirror direction and, for a glass, its refracted one (past
// the critical angle none: its reflection then has F = 1), traced once per camera sample with the lobe's weight; the
// emitters each finds count with weight 1 (QueueEmittersAlongRay's kSingularRayPdf).  A ray leaving on the wrong
// side of the geometric normal is dropped for a reflection, as Cycles' bsdf_reflection_sample does.
template <Technique K, bool kMedium>
[[gnu::noinline]] static void QueueSingularRays(const ShadeContext& c, const SurfaceShadingPoint& sp,
                                                const ShadowSink& sink) {
    NoLightPdfs light_sampling;
    for (int i = 0; i < sp.material.num_singular; ++i) {
        const SingularScatter s = ScatterSingular(sp.material.singular[i], sp.wo);
        const Vec3f reflected = sp.frame.FromLocal(s.reflect_dir);
        if (!IsBlack(s.reflect_weight) && Dot(reflected, sp.hit.ng) > 0)
            QueueEmittersAlongRay<K, kMedium>(c, sp.origin, reflected, kSingularRayPdf, kRayGlossy, light_sampling,
                                              sink.Scaled(s.reflect_weight));
        if (!s.refracts || IsBlack(s.refract_weight)) continue;
        const Vec3f refracted = sp.frame.FromLocal(s.refract_dir);
        const Vec3f origin = Dot(refracted, sp.hit.ng) < 0 ? OffsetOrigin(sp.hit.p, -sp.hit.ng) : sp.origin;
        QueueEmittersAlongRay<K, kMedium>(c, origin, refracted, kSingularRayPdf, kRayGlossy | kRayTransmission,
                                          light_sampling, sink.Scaled(s.refract_weight));
    }
}

// The hit's material: the scene's, or for a textured one its Material evaluated at the hit's texture coordinates
// into `storage` (its emission the material's own: emission is not textured); a normal-mapped one in the
// Principled form (MixIntoBsdf of weight 1: a Lambert lobe as `lambert`) with its bump shadowing; a glass
// lobe seen from its back face with the inverse IOR.
// Out of line and cold: inlined into the shading loop, its material construction cost every scene instructions,
// textured or not (docs/architecture.md, measured choices).
[[gnu::noinline, gnu::cold]] static Bsdf HitSpecificBsdf(const RenderScene& scene, const SurfaceHit& h,
                                                         const Frame& frame) {
    const Bsdf& m = scene.bsdfs[size_t(h.material)];
    auto textured = [&] {
        const Material& material = scene.materials[size_t(h.material)];
        return material.programmed ? EvaluateBsdfAtHit(material, scene.images, HitShaderGlobals(h))
                                   : EvaluateTexturedBsdf(material, scene.images, h.tc);
    };
    Bsdf out = m.textured ? textured() : m;  // built in place: a textured hit copies no Bsdf
    if (m.textured) out.emission = m.emission;
    if (m.normal_mapped) {
        if (!out.principled) {
            Bsdf principled = MakeEmptyMixBsdf();
            MixIntoBsdf<MixOverflow::kLenient>(principled, out, 1);
            principled.emission = out.emission;
            out = principled;
        }
        out.bump_shadowing = true;
        out.unmapped_normal = frame.ToLocal(h.ns_unmapped);
    }
    if (m.anisotropic && Dot(h.tangent, h.tangent) > 0) SetHitTangent(out, frame.ToLocal(h.tangent));
    if (m.has_dielectric && h.backfacing) {  // seen from inside: the relative IOR inverts
        for (int i = 0; i < out.num_lobes; ++i)
            if (out.lobes[i].fresnel_ior > 0) out.lobes[i].fresnel_ior = 1 / out.lobes[i].fresnel_ior;
        for (int i = 0; i < out.num_singular; ++i)
            if (out.singular[i].fresnel == SingularFresnel::kDielectric) out.singular[i].ior = 1 / out.singular[i].ior;
    }
    return out;
}

// Whether the hit shades with its scene material as it is (no hit-specific Bsdf).
template <bool kGlossy>
static inline bool ShadesWithSceneBsdf(const RenderScene& scene, const SurfaceHit& h) {
    const Bsdf& m = scene.bsdfs[size_t(h.material)];
    if constexpr (!kGlossy) return true;  // Commit() sends scenes with any of these to the glossy kernel
    return !m.textured && !m.normal_mapped && !m.anisotropic && !(m.has_dielectric && h.backfacing);
}

template <bool kGlossy>
static inline const Bsdf& BsdfAtHit(const RenderScene& scene, const SurfaceHit& h, const Frame& frame,
                                    std::optional<Bsdf>& storage) {
    const Bsdf& m = scene.bsdfs[size_t(h.material)];
    if (ShadesWithSceneBsdf<kGlossy>(scene, h)) return m;
    storage.emplace(HitSpecificBsdf(scene, h, frame));
    return *storage;
}

// The light tree's receiver normal at a surface hit shading with `material`: none for a translucent surface, which
// receives light from both sides (no horizon).
template <bool kGlossy>
static inline Vec3f TreeReceiverNormal(const SurfaceHit& h, const Bsdf& material) {
    return kGlossy && material.has_translucent ? Vec3f() : h.ns;
}

// Whether the hit's light-tree receiver (TreeReceiverNormal of the Bsdf it shades with) is that of its scene
// material, so known before its hit-specific Bsdf is built: a textured, normal-mapped or anisotropic hit changes
// only lobes' inputs, normals the hit carries already and tangents -- all but a translucent lobe's presence.
template <bool kGlossy>
static inline bool TreeReceiverKnownEarly(const RenderScene& scene, const SurfaceHit& h) {
    return ShadesWithSceneBsdf<kGlossy>(scene, h) || !scene.bsdfs[size_t(h.material)].may_be_translucent;
}

// Whether a hit on material m takes light samples alone (no MIS partner): a purely diffuse
// material with the lights sampled by solid angle (not `area`, for rectangles nor for the scene's
// ellipses), unless RenderOptions::bsdf_samples_on_diffuse (ShadeContext).  There the light sample's density already
// follows the integrand but for the cosine (`rectangle_projected`: including the cosine, so that an unoccluded light's
// estimate has no variance and a BSDF sample could only add noise), so the BSDF sample's share of MIS is small where it
// is not noise, and its ray, light finding and light pdf cost a quarter of the render: over the blend_scenes dropping
// it lowers MSE x time except where the light technique is weak (docs/architecture.md, measured choices). Each hit's
// choice depends only on the hit, so the image stays unbiased.
template <Technique K>
static inline bool LightSamplesAlone(const ShadeContext& c, const Bsdf& m) {
    return c.diffuse_light_samples_alone && !m.glossy && K != Technique::Area;
}

// rectangle_ltc's glossy lobe at a hit: the BSDF's most likely sampled microfacet lobe (its GGX alpha; an anisotropic
// one's geometric mean, which the isotropic fit follows roughly), weighed by that probability against the rest's.
template <bool kGlossy>
static inline GlossyLobe<float> GlossyLobeAt(const Bsdf& m, const Vec3f& wo_world) {
    if constexpr (kGlossy) {
        if (!m.glossy) return {};
        float p = m.specular_probability;
        float alpha = m.principled ? std::sqrt(m.alpha * m.specular_alpha_y) : m.alpha;
        if (m.principled)
            for (int i = 0; i < m.num_lobes; ++i)
                if (m.lobes[i].probability > p) {
                    p = m.lobes[i].probability;
                    alpha = std::sqrt(m.lobes[i].alpha * m.lobes[i].alpha_y);
                }
        if (p > 0) return {wo_world, alpha, p, 1 - p};
    }
    return {};
}

// Direct light at surface hit h towards wo_world: light_samples (light sample, BSDF sample)
// pairs averaged, as many light samples of the image world, then the delta lights evaluated once (soft ones once per
// light sample), then the singular lobes' rays (once).  Light sample j's emitter and its point come from
// light_points[j] (LightSamplingAt::Choose), or where the chunk chose it (batched_choices, else null) from
// batched_choices[j], with its sample where that was taken too; under "ris" (never batched) resampled from candidates
// shifted by rng (QueueResampledLightSample); else rng is only advanced for the medium that may follow.
// light_ticks counts the time in light sampling.
template <Technique K, bool kGlossy, bool kMedium>
static inline void ShadeSurface(const ShadeContext& c_scene, const SurfaceHit& h, const Vec3f& wo_world,
                                const Point2<float>* light_points, const Point2<float>* bsdf_points,
                                const ChosenLight* batched_choices, PCG32& rng, const ShadowSink& sink,
                                uint64_t& light_ticks) {
    const RenderScene& scene = c_scene.scene;
    const Frame frame = Frame::FromZ(h.ns);
    std::optional<Bsdf> textured;  // a textured material's inputs at this hit (not constructed otherwise)
    const SurfaceShadingPoint sp{h, BsdfAtHit<kGlossy>(scene, h, frame, textured), frame, frame.ToLocal(wo_world),
                                 OffsetOrigin(h.p, h.ng)};
    if (sp.wo.z <= 0) return;
    const ShadeContext without_mis = WithoutMis(c_scene);
    const ShadeContext& c = LightSamplesAlone<K>(c_scene, sp.material) ? without_mis : c_scene;
    const ShadowSink pair_sink = sink.Scaled(1.0f / c.light_samples);
    // Without lights to choose and BSDF samples (only delta lights evaluated once) there is nothing to sample.
    const int n_pairs = (HasChoosableLights(scene, c.light_selection) || c.sample_bsdf) ? c.light_samples : 0;
    const Vec3f tree_normal = TreeReceiverNormal<kGlossy>(h, sp.material);
    // rectangle_projected (and rectangle_ltc) sample only the light above the horizon of its normal: a translucent
    // surface gets none (the technique then switches to `rectangle`, rectangle_projected.h).
    const Vec3f technique_normal =
        (K == Technique::RectangleProjected || K == Technique::RectangleLtc) && kGlossy && sp.material.has_translucent
            ? Vec3f()
            : h.ns;
    const bool resampled = c.light_selection == LightSelection::Ris;
    TimedLightSamplingAt<K> light_sampling(scene, c.light_selection, h.p, technique_normal, tree_normal,
                                           resampled ? n_pairs * c.ris_candidates : n_pairs, c.ellipse_technique,
                                           light_ticks, c.emission_blocks);
    if constexpr (K == Technique::RectangleLtc)
        light_sampling.FollowGlossyLobe(GlossyLobeAt<kGlossy>(sp.material, wo_world));
    for (int j = 0; j < n_pairs; ++j) {
        if constexpr (kMedium) SkipFormerLightChoiceNumber(scene.light_selector, rng);  // ShadeVolume's follow
        if (resampled) {
            QueueResampledLightSample<K, kGlossy, kMedium>(c, sp, light_points[j], light_sampling, rng, pair_sink);
        } else {
            const ChosenLight light = batched_choices ? batched_choices[j] : light_sampling.Choose(light_points[j]);
            QueueChosenLightSample<K, kGlossy, kMedium>(c, sp, light, light_sampling, pair_sink);
        }
        if (c.sample_bsdf)
            QueueSurfaceBsdfSample<K, kGlossy, kMedium>(c, sp, bsdf_points[j], light_sampling, pair_sink);
    }
    // The image world, a light of its own: sampled once per light sample whatever the light selection.
    if (c.environment)
        for (int j = 0; j < c.light_samples; ++j)
            QueueSurfaceEnvironmentSample<kGlossy, kMedium>(c, sp, light_points[j], pair_sink);
    QueueSurfaceDeltaLights<kGlossy, kMedium>(c, sp, light_points, sink);
    if constexpr (kGlossy) {
        if (sp.material.num_singular > 0) QueueSingularRays<K, kMedium>(c, sp, sink);
    }
}

}  // namespace sphrect::render
