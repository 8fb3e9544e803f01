// Single scattering in the homogeneous medium along the camera ray: scattering distances by
// transmittance and equi-angular sampling, combined by MIS, and at each scattering point the
// light in-scattered towards the camera (one light and one phase sample; delta lights once).
// Everything is queued on a ShadowSink with its occlusion ray.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "camera_ray_media.h"
#include "camera_stage.h"
#include "emitters.h"
#include "render/medium.h"
#include "render/medium_stretches.h"
#include "render/object_volumes.h"

namespace sphrect::render {

// The medium has no normal: the cosine-weighted techniques (NeedsShadingNormal) would drop light behind a made-up
// horizon, so scattering points use the spherical rectangle.
template <Technique K>
constexpr Technique kMediumTechnique = NeedsShadingNormal(K) ? Technique::Rectangle : K;

// A scattering point x on the camera ray of direction ray_dir, in a medium of anisotropy g (the world's, or the
// volumes' there).  Phase values and pdfs are w.r.t. wi, the direction towards the light
// (HenyeyGreenstein(dot(wi, ray_dir), g)).
struct ScatteringPoint {
    Vec3f x;
    Vec3f ray_dir;
    float g;
};

// A light sample in the medium of a light whose visibility is not the default (LightVisibility): none from a light
// hidden from volume scatter (Cycles' SHADER_EXCLUDE_SCATTER), weight 1 without Multiple Importance (pdf_light 0: no
// MIS), no shadow ray without Cast Shadow.  QueueMediumLightSample's value (pdf_div: its pdf) or
// QueueMediumDeltaLight's (1), in their order.  Out of line: scenes whose lights are all visible never come here.
[[gnu::noinline, gnu::cold]] static void QueueMediumLightWithVisibility(const ShadeContext& c,
                                                                        const ScatteringPoint& sp, const Vec3f& dir,
                                                                        float dist, const Spectrum& le, float pdf_light,
                                                                        float pdf_div, const LightVisibility& vis,
                                                                        const ShadowSink& sink) {
    if (!(vis.rays() & kRayVolumeScatter)) return;
    const float phase = HenyeyGreenstein(Dot(dir, sp.ray_dir), sp.g);
    const float w = pdf_light > 0 && vis.use_mis() ? MisWeight(c.mis, pdf_light, phase) : 1.0f;
    sink.Add(sp.x, dir, dist, le * Transmittance(c.scene.medium, dist) * (phase * w / pdf_div), vis.ShadowMask());
}

// A light sample e seen through transmittance t: phase Le t w / pdf, w its MIS weight against the phase sample (an
// area light's point, or a direction of the image world: e.dist kInf).
static inline void QueueMediumEmitterSample(const ShadeContext& c, const ScatteringPoint& sp, const EmitterSample& e,
                                            const Spectrum& t, const ShadowSink& sink) {
    const float phase = HenyeyGreenstein(Dot(e.dir, sp.ray_dir), sp.g);
    const float w = MisWeight(c.mis, e.pdf, phase);
    sink.Add(sp.x, e.dir, e.dist, e.le * t * (phase * w / e.pdf));
}

// Light sampling: phase Le T w / (pmf pdf), w its MIS weight against the phase sample.
template <Technique K>
static inline void QueueMediumLightSample(const ShadeContext& c, const ScatteringPoint& sp, ChosenLight light,
                                          TimedLightSamplingAt<K>& light_sampling, const ShadowSink& sink) {
    const EmitterSample e = SampleChosenEmitter<K>(c, light, light.u, light_sampling);
    if (!e.valid) return;
    if (const LightVisibility& vis = c.scene.area_lights[light.index].vis; !vis.IsDefault())
        return QueueMediumLightWithVisibility(c, sp, e.dir, e.dist, e.le, e.pdf, e.pdf, vis, sink);
    QueueMediumEmitterSample(c, sp, e, Transmittance(c.scene.medium, e.dist), sink);
}

// Phase sampling (the weight phase / pdf is 1): finds the area lights and the background.
template <Technique K>
static inline void QueueMediumPhaseSample(const ShadeContext& c, const ScatteringPoint& sp, Point2<float> u,
                                          TimedLightSamplingAt<K>& light_sampling, const ShadowSink& sink) {
    const float g = sp.g;
    const Vec3f wi = SampleHenyeyGreenstein(sp.ray_dir, g, u);
    const float pdf_phase = HenyeyGreenstein(Dot(wi, sp.ray_dir), g);
    QueueEmittersAlongRay<K, true>(c, sp.x, wi, pdf_phase, kRayVolumeScatter, light_sampling, sink);
}

// Light sampling of the image world: phase Le T w / pdf, w its MIS weight against the phase sample.
static inline void QueueMediumEnvironmentSample(const ShadeContext& c, const ScatteringPoint& sp, Point2<float> u,
                                                const ShadowSink& sink) {
    const EmitterSample e = SampleEnvironmentEmitter(c, u);
    if (!e.valid) return;
    if (const LightVisibility& vis = c.scene.world_visibility; !vis.IsDefault())
        return QueueMediumLightWithVisibility(c, sp, e.dir, e.dist, e.le, e.pdf, e.pdf, vis, sink);
    QueueMediumEmitterSample(c, sp, e, c.environment_transmittance, sink);
}

// One point, spot or sun light: phase Li T; a soft one's direction from the point u, weighted against the phase
// sample by MIS (pmf: the light's choice, 1 when evaluated once).
static inline void QueueMediumDeltaLight(const ShadeContext& c, const ScatteringPoint& sp, const DeltaLight& d,
                                         Point2<float> u, float pmf, const ShadowSink& sink) {
    const HomogeneousMedium& med = c.scene.medium;
    const DeltaIllumination di = IlluminateFromDelta(d, sp.x, u);
    if (IsBlack(di.li)) return;
    if (!d.vis.IsDefault())
        return QueueMediumLightWithVisibility(c, sp, di.wi, di.dist, di.li, di.pdf > 0 ? pmf * di.pdf : 0, 1, d.vis,
                                              sink);
    const float phase = HenyeyGreenstein(Dot(di.wi, sp.ray_dir), sp.g);
    const float w = di.pdf > 0 ? MisWeight(c.mis, pmf * di.pdf, phase) : 1.0f;
    sink.Add(sp.x, di.wi, di.dist, di.li * Transmittance(med, di.dist) * (phase * w));
}

// The delta lights evaluated once (ForEachDeltaLightEvaluatedOnce); soft ones sampled with the point u.
static inline void QueueMediumDeltaLights(const ShadeContext& c, const ScatteringPoint& sp, Point2<float> u,
                                          const ShadowSink& sink) {
    ForEachDeltaLightEvaluatedOnce(c.scene, c.light_selection,
                                   [&](const DeltaLight& d) { QueueMediumDeltaLight(c, sp, d, u, 1, sink); });
}

// Light scattered towards the camera at sp: sigma_s * integral of phase * Le * T over the lights (T: the world
// medium's here, object volumes' as the shadow rays are resolved).
// The light sample's emitter is chosen here from light_point (by power: the same for every
// scattering point of the camera sample; by the tree: at sp.x, with no normal; "ris" chooses as the tree here: its
// resampling is the surfaces', whose candidates the BSDF weighs).
template <Technique K>
static inline void InScatteredLight(const ShadeContext& c, const ScatteringPoint& sp, const Spectrum& sigma_s,
                                    Point2<float> light_point, Point2<float> phase_point, const ShadowSink& sink,
                                    uint64_t& light_ticks) {
    constexpr Technique MK = kMediumTechnique<K>;
    const ShadowSink out = sink.Scaled(sigma_s);
    TimedLightSamplingAt<MK> light_sampling(c.scene, c.light_selection, sp.x, sp.ray_dir, Vec3f(0, 0, 0), 1,
                                            c.ellipse_technique, light_ticks, c.emission_blocks);
    const ChosenLight light = light_sampling.Choose(light_point);
    if (light.delta >= 0)  // a point or spot light the tree chose: phase Li T / pmf
        QueueMediumDeltaLight(c, sp, c.scene.delta_lights[light.delta], light.u, light.pmf,
                              out.Scaled(1.0f / light.pmf));
    QueueMediumLightSample<MK>(c, sp, light, light_sampling, out);
    if (c.sample_bsdf) QueueMediumPhaseSample<MK>(c, sp, phase_point, light_sampling, out);
    QueueMediumDeltaLights(c, sp, light_point, out);
    if (c.environment) QueueMediumEnvironmentSample(c, sp, light_point, out);
}

// Distance sampling: t ~ sigma exp(-sigma t), kept inside the segment.
static inline ScatterDistance SampleDistanceByTransmittance(const HomogeneousMedium& med, float t_end, float u) {
    const float t = SampleExponentialDistance(med.sigma_sampling, u);
    if (!(t < t_end)) return {};
    return {t, ExponentialDistancePDF(med.sigma_sampling, t)};
}

// Equi-angular sampling about the centre of `ea`.
static inline ScatterDistance SampleDistanceEquiAngular(const EquiAngular& ea, float t_end, float u) {
    const float t = SampleEquiAngular(ea, u);
    const float pdf = EquiAngularPDF(ea, t);
    if (!(t > 0 && t < t_end && pdf > 0 && std::isfinite(pdf))) return {};
    return {t, pdf};
}

// Equi-angular sampling of the segment about a light picked by power (any area, point or spot
// light; u picks it); invalid when the scene has none.
static inline EquiAngular EquiAngularAboutALight(const RenderScene& scene, const Ray& ray, float t_end, float u) {
    if (scene.medium_centre_selector.Empty()) return {};
    return MakeEquiAngular(ray.o, ray.d, t_end, scene.medium_centres[scene.medium_centre_selector.Select(u)]);
}

// Queues the in-scattered light at distance d.t along the ray, weighted by T(t) w / pdf (and the camera ray's
// throughput there, given `media`) and averaged over the light samples.
template <Technique K>
static inline void QueueInScatteringAt(const ShadeContext& c, const Ray& ray, ScatterDistance d, float w,
                                       Point2<float> light_point, Point2<float> phase_point, const ShadowSink& sink,
                                       uint64_t& light_ticks, const CameraRayMedia* media) {
    Spectrum weight = Transmittance(c.scene.medium, d.t) * (w / d.pdf);
    if (media) weight = weight * media->ThroughputAt(d.t);
    InScatteredLight<K>(c, {ray.o + ray.d * d.t, ray.d, c.scene.medium.g}, c.scene.medium.sigma_s, light_point,
                        phase_point, sink.Scaled(weight * (1.0f / c.light_samples)), light_ticks);
}

// Single scattering along the camera ray's segment [0, t_end): integral of T(t) * inscattered(t),
// with distance sampling and equi-angular sampling (about a light's centre), combined by
// one-sample-per-strategy MIS (the renderer's heuristic; balance when MIS is off).  The
// equi-angular centre is a random light; for each choice the combination is unbiased, so the
// mixture is too.
template <Technique K>
static inline void ShadeVolume(const ShadeContext& c, const PrimaryHit& ph, const Point2<float>* light_points,
                               const Point2<float>* bsdf_points, PCG32& rng, const ShadowSink& sink,
                               uint64_t& light_ticks, const CameraRayMedia* media = nullptr) {
    const RenderScene& scene = c.scene;
    const Ray& ray = ph.ray;
    const MisMode strategy_mis = c.mis == MisMode::None ? MisMode::Balance : c.mis;
    for (int j = 0; j < c.light_samples; ++j) {
        // The light sample's emitter comes from the pattern's light point (InScatteredLight, at
        // each scattering point), the centre for equi-angular sampling independently from rng.
        SkipFormerLightChoiceNumber(scene.light_selector, rng);
        const EquiAngular ea = EquiAngularAboutALight(scene, ray, ph.t_end, rng.NextFloat());
        const bool use_equi = c.medium_sampling != MediumSampling::Distance && ea.valid;
        const bool use_distance = c.medium_sampling != MediumSampling::EquiAngular || !ea.valid;
        const float u_distance = rng.NextFloat(), u_equi = rng.NextFloat();
        if (use_distance) {
            const ScatterDistance d = SampleDistanceByTransmittance(scene.medium, ph.t_end, u_distance);
            const float w = use_equi ? MisWeight(strategy_mis, d.pdf, EquiAngularPDF(ea, d.t)) : 1.0f;
            if (d.pdf > 0 && w > 0)
                QueueInScatteringAt<K>(c, ray, d, w, light_points[j], bsdf_points[j], sink, light_ticks, media);
        }
        if (use_equi) {
            const ScatterDistance d = SampleDistanceEquiAngular(ea, ph.t_end, u_equi);
            const float w =
                use_distance ? MisWeight(strategy_mis, d.pdf, ExponentialDistancePDF(scene.medium.sigma_sampling, d.t))
                             : 1.0f;
            if (d.pdf > 0 && w > 0)
                QueueInScatteringAt<K>(c, ray, d, w, light_points[j], bsdf_points[j], sink, light_ticks, media);
        }
    }
}

// --- Object volumes: the camera ray's stretches through media (object_volumes.h) -----------------------------------

// Equi-angular sampling of [a, b) (the stretches' span) about `centre`; t is measured from the camera.
struct SpanEquiAngular {
    EquiAngular ea;
    float a = 0;
};

static inline float SpanEquiAngularPDF(const SpanEquiAngular& e, float t) { return EquiAngularPDF(e.ea, t - e.a); }

// The equi-angular sampling of the span o + t d, t in [0, span), about a light chosen with probability proportional to
// its power times the integral of 1 / r^2 over the span, (theta_b - theta_a) / D: the light the ray passes close to is
// chosen where it dominates the in-scattering (by power alone, a ray grazing a lamp was centred on a far spot as often
// as on the lamp, and gained nothing there: docs/study_volumes.md).  So are the most powerful lights
// (RenderScene::medium_centres_weighed); the others together weigh their share of the power times the mean of the
// weighed ones' integrals, and are then chosen by power among themselves.  The choice depends on the ray only, so each
// choice's MIS with distance sampling stays unbiased and so does the mixture.
static inline EquiAngular EquiAngularAboutANearLight(const RenderScene& scene, const Vec3f& o, const Vec3f& d,
                                                     float span, float u) {
    const LightSelector& by_power = scene.medium_centre_selector;
    if (by_power.Empty()) return {};
    const std::vector<uint32_t>& weighed = scene.medium_centres_weighed;
    std::array<EquiAngular, RenderScene::kMaxCentresWeighedPerRay> about;
    std::array<double, RenderScene::kMaxCentresWeighedPerRay> weight;
    double total = 0, closeness_sum = 0;
    int closeness_count = 0;
    for (size_t k = 0; k < weighed.size(); ++k) {
        about[k] = MakeEquiAngular(o, d, span, scene.medium_centres[weighed[k]]);
        weight[k] = 0;
        if (!about[k].valid) continue;
        const double closeness = double(about[k].theta_b - about[k].theta_a) / about[k].dist;
        weight[k] = double(by_power.pmf[weighed[k]]) * closeness;
        closeness_sum += closeness;
        ++closeness_count;
        total += weight[k];
    }
    const double rest = closeness_count && !scene.medium_centre_rest_selector.Empty()
                            ? scene.medium_centre_rest_share * closeness_sum / closeness_count
                            : 0;
    total += rest;
    if (!(total > 0) || !std::isfinite(total))
        return MakeEquiAngular(o, d, span, scene.medium_centres[by_power.Select(u)]);
    double x = double(u) * total;
    for (size_t k = 0; k < weighed.size(); ++k) {
        if (weight[k] > 0 && x < weight[k]) return about[k];
        x -= weight[k];
    }
    if (rest > 0) {
        const float u_rest = float(std::clamp(x / rest, 0.0, double(kOneMinusEpsilonF)));
        return MakeEquiAngular(o, d, span, scene.medium_centres[scene.medium_centre_rest_selector.Select(u_rest)]);
    }
    for (size_t k = weighed.size(); k-- > 0;)  // x rounded past the last weight
        if (weight[k] > 0) return about[k];
    return {};
}

// Queues the in-scattered light at distance d.t along the ray inside stretch s, weighted by T(t) w / pdf and averaged
// over the light samples.
template <Technique K>
static inline void QueueInScatteringInStretch(const ShadeContext& c, const Ray& ray, const MediumStretch& s,
                                              ScatterDistance d, float w, Point2<float> light_point,
                                              Point2<float> phase_point, const ShadowSink& sink, uint64_t& light_ticks,
                                              const CameraRayMedia& media) {
    if (IsBlack(s.k.sigma_s)) return;
    const Spectrum weight = TransmittanceInStretch(s, d.t) * media.ThroughputAt(d.t) * (w / d.pdf);
    InScatteredLight<K>(c, {ray.o + ray.d * d.t, ray.d, s.k.g}, s.k.sigma_s, light_point, phase_point,
                        sink.Scaled(weight * (1.0f / c.light_samples)), light_ticks);
}

// Single scattering along the camera ray's [0, t_end) through object volumes (and the world medium), as ShadeVolume
// does in the world medium alone: distance sampling (now through the stretches) and equi-angular sampling over their
// span about a light chosen by its importance along it (EquiAngularAboutANearLight), combined by MIS.  `media`: the
// ray's stretches through the volumes and its throughput along them.
template <Technique K>
[[gnu::noinline]] static void ShadeObjectVolumes(const ShadeContext& c, const PrimaryHit& ph,
                                                 const CameraRayMedia& media, const Point2<float>* light_points,
                                                 const Point2<float>* bsdf_points, PCG32& rng, const ShadowSink& sink,
                                                 uint64_t& light_ticks) {
    const RenderScene& scene = c.scene;
    const Ray& ray = ph.ray;
    const MediumStretches st = MakeMediumStretches(media.volumes, ph.t_end, scene.has_medium ? &scene.medium : nullptr);
    if (st.count == 0) return;
    const float a = st.stretch[0].t0, b = st.stretch[st.count - 1].t1;
    const MisMode strategy_mis = c.mis == MisMode::None ? MisMode::Balance : c.mis;
    for (int j = 0; j < c.light_samples; ++j) {
        SkipFormerLightChoiceNumber(scene.light_selector, rng);
        SpanEquiAngular se;
        se.a = a;
        se.ea = EquiAngularAboutANearLight(scene, ray.o + ray.d * a, ray.d, b - a, rng.NextFloat());
        const bool use_equi = c.medium_sampling != MediumSampling::Distance && se.ea.valid;
        const bool use_distance = c.medium_sampling != MediumSampling::EquiAngular || !se.ea.valid;
        const float u_distance = rng.NextFloat(), u_equi = rng.NextFloat();
        if (use_distance) {
            const ScatterDistance d = SampleDistanceThroughStretches(st, u_distance);
            const MediumStretch* s = d.pdf > 0 ? st.At(d.t) : nullptr;
            const float w = use_equi ? MisWeight(strategy_mis, d.pdf, SpanEquiAngularPDF(se, d.t)) : 1.0f;
            if (s && w > 0)
                QueueInScatteringInStretch<K>(c, ray, *s, d, w, light_points[j], bsdf_points[j], sink, light_ticks,
                                              media);
        }
        if (use_equi) {
            ScatterDistance d = SampleDistanceEquiAngular(se.ea, b - a, u_equi);
            d.t += a;
            const MediumStretch* s = d.pdf > 0 ? st.At(d.t) : nullptr;
            const float w = use_distance ? MisWeight(strategy_mis, d.pdf, DistanceThroughStretchesPDF(st, d.t)) : 1.0f;
            if (s && w > 0)
                QueueInScatteringInStretch<K>(c, ray, *s, d, w, light_points[j], bsdf_points[j], sink, light_ticks,
                                              media);
        }
    }
}

}  // namespace sphrect::render
