// Deferred visibility: shading queues every contribution with the occlusion ray it depends on
// -- to a light sample, a delta light, or the light or background a BSDF/phase ray reaches --
// and a chunk's rays are traced together after its shading (ResolveShadowRays).
#pragma once

#include <cstdint>
#include <vector>

#include "render/embree_rays.h"
#include "render/kernel.h"
#include "transparency.h"

namespace sphrect::render {

// A shadow ray whose contribution counts for camera sample `sample` if nothing blocks it.
// Traced in place as one Embree stream: the stride skips the payload.
struct DeferredShadowRay {
    RTCRay ray;
    Spectrum contribution;
    uint32_t sample;
};

// Where shading sends its shadow rays: the queue, the camera sample they belong to, and the
// factor the caller multiplies this estimate by (transmittance, MIS and pdf weights, 1 / samples).
struct ShadowSink {
    std::vector<DeferredShadowRay>* queue;
    uint32_t sample;
    Spectrum scale{1, 1, 1};

    ShadowSink Scaled(const Spectrum& f) const { return {queue, sample, scale * f}; }
    ShadowSink Scaled(float f) const { return {queue, sample, scale * f}; }
    // Queues `contribution` (times scale), seen from o along d if nothing lies within `dist` that rays of kinds `mask`
    // see (ray_visibility.h: a light sample's shadow ray, a BSDF ray's own kind; 0: nothing blocks it).
    [[gnu::always_inline]] void Add(const Vec3f& o, const Vec3f& d, float dist, const Spectrum& contribution,
                                    unsigned mask = kRayShadow) const {
        queue->push_back({MakeRTCRay(o, d, 0, ShadowRayLength(dist), mask), contribution * scale, sample});
    }
};

// The unblocked rays' contributions through the object volumes they cross (object_volumes.h).  Out of line: scenes
// without them skip it.
[[gnu::noinline]] static void AttenuateThroughVolumes(const RenderScene& scene, std::vector<DeferredShadowRay>& queue) {
    for (DeferredShadowRay& q : queue)
        if (q.ray.tfar >= 0)
            q.contribution =
                q.contribution * scene.volumes.Transmittance({q.ray.org_x, q.ray.org_y, q.ray.org_z},
                                                             {q.ray.dir_x, q.ray.dir_y, q.ray.dir_z}, q.ray.tfar);
}

// Traces the queued shadow rays (one stream, OccludeShadowRays) and adds the unblocked
// contributions to their camera samples; in a scene with transparent surfaces, each filtered by those it crosses
// (transparency.h; `crossed` is scratch space), and with object volumes, by their transmittance.
static inline void ResolveShadowRays(const RenderScene& scene, std::vector<DeferredShadowRay>& queue,
                                     Spectrum* sample_values, std::vector<uint8_t>& crossed) {
    if (queue.empty()) return;
    if (!scene.has_transparency) {
        OccludeShadowRays(scene.rtc_scene, &queue[0].ray, queue.size(), sizeof(DeferredShadowRay));
        if (scene.has_volumes) AttenuateThroughVolumes(scene, queue);  // only the unblocked walk through them
        for (const DeferredShadowRay& q : queue)
            if (q.ray.tfar >= 0) sample_values[q.sample] += q.contribution;
        return;
    }
    crossed.assign(queue.size(), 0);
    for (size_t i = 0; i < queue.size(); ++i) queue[i].ray.id = unsigned(i);
    OccludeShadowRays(scene.rtc_scene, &queue[0].ray, queue.size(), sizeof(DeferredShadowRay), crossed.data());
    if (scene.has_volumes) AttenuateThroughVolumes(scene, queue);
    for (size_t i = 0; i < queue.size(); ++i) {
        const DeferredShadowRay& q = queue[i];
        if (q.ray.tfar < 0) continue;
        sample_values[q.sample] += crossed[i] ? q.contribution * ShadowTransmittance(scene, q.ray) : q.contribution;
    }
}

}  // namespace sphrect::render
