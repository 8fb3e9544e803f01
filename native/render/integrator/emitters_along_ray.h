// What a BSDF or phase sample's ray brings: the emitters it reaches, each queued with the
// occlusion ray up to it.
#pragma once

#include <cmath>

#include "shade_context.h"
#include "shadow_queue.h"
#include "timed_light_sampling.h"

namespace sphrect::render {

// For the ray (o, d): the background where the ray escapes, and with MIS every area light it
// crosses, weighted against light sampling (Le T w).  A light counts when no surface lies
// before it -- the same test as for its light samples -- so a ray that reaches no emitter is
// not traced at all.  pdf_dir: the direction's pdf under BSDF/phase sampling; `sink` carries
// its weight f cos / pdf.
template <Technique K, bool kMedium>
inline void QueueEmittersAlongRay(const ShadeContext& c, const Vec3f& o, const Vec3f& d, float pdf_dir,
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
