// What the two strategies bring from the emitters: a light sample on the chosen area light,
// and the emitters a BSDF or phase sample's ray reaches, each queued with its occlusion ray.
#pragma once

#include <cmath>

#include "shade_context.h"
#include "shadow_queue.h"
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

template <Technique K>
static inline EmitterSample SampleChosenEmitter(const ShadeContext& c, ChosenLight light, Point2<float> u,
                                                TimedLightSamplingAt<K>& light_sampling) {
    if (light.index < 0) return {};
    const LightSample<float> ls = light_sampling.Sample(light.index, u);
    if (!(ls.pdf > 0 && std::isfinite(ls.pdf))) return {};
    const Spectrum le = EmittedRadiance(c.scene.area_lights[light.index], -ls.dir);
    if (IsBlack(le)) return {};
    return {true, ls.dir, ls.dist, le, light.pmf * ls.pdf};
}

// For the ray (o, d): the background where the ray escapes, and with MIS every area light it
// crosses, weighted against light sampling (Le T w).  A light counts when no surface lies
// before it -- the same test as for its light samples -- so a ray that reaches no emitter is
// not traced at all.  pdf_dir: the direction's pdf under BSDF/phase sampling; `sink` carries
// its weight f cos / pdf.
template <Technique K, bool kMedium>
static inline void QueueEmittersAlongRay(const ShadeContext& c, const Vec3f& o, const Vec3f& d, float pdf_dir,
                                         TimedLightSamplingAt<K>& light_sampling, const ShadowSink& sink) {
    if (!IsBlack(c.sky)) sink.Add(o, d, kInf, c.sky);
    if (c.mis == MisMode::None) return;
    const auto& lights = c.scene.area_lights;
    for (int i = 0; i < int(lights.size()); ++i) {
        const float t = IntersectAreaLight(lights[i], o, d, kInf);
        if (std::isinf(t)) continue;
        const Spectrum le = EmittedRadiance(lights[i], -d);
        if (IsBlack(le)) continue;
        const float pdf_light = light_sampling.PDF(i, o + d * t);
        sink.Add(o, d, t, le * SegmentTransmittance<kMedium>(c.scene.medium, t) * MisWeight(c.mis, pdf_dir, pdf_light));
    }
}

}  // namespace sphrect::render
