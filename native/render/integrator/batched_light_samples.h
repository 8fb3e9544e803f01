// Light samples of rectangles taken for a whole chunk at once, before its shading: the batched
// rectangle technique (core/rectangle_batch.h) over every (surface hit, light sample) whose
// light is known before shading.  With "power" selection the light a light sample goes to
// depends on its pattern point alone, so the lights are chosen for the whole chunk and the requests
// gathered per light and sampled in SIMD batches; shading then takes its choice and sample from here
// (ChosenLight::batched) and sets up no sampler unless a BSDF ray needs a pdf.  The samples equal the scalar sampler's
// up to rounding (the batch's tests), so images change by rounding only.
//
// Requests that stay with the scalar path: techniques other than `rectangle`, the light tree
// (its choice depends on the receiver), ellipses and triangles, lights with spread (sampled on
// their clipped part) and textured rectangles sampled by their blocks.
#pragma once

#include <cstdint>
#include <vector>

#include "camera_stage.h"
#include "core/rectangle_batch.h"
#include "light_sampling_at.h"
#include "render/kernel.h"
#include "render/ticks.h"
#include "shade_context.h"

namespace sphrect::render {

// Whether light samples of technique K under this context are batched.
template <Technique K>
static inline bool BatchesLightSamples(const ShadeContext& c) {
    return K == Technique::Rectangle && c.light_selection == LightSelection::Power && !c.scene.light_selector.Empty();
}

// Whether rectangle light l is sampled by the plain map (what the batch computes) at every point.
static inline bool BatchableRectangle(const ShadeContext& c, const AreaLight& l) {
    return l.shape == AreaShape::Rectangle && !l.HasSpread() &&
           !SampledByBlocks(c.scene, l, Technique::Rectangle, c.emission_blocks);
}

// Fills scratch.batched_choices for the chunk's n camera samples: per camera sample s and light sample j, at
// s * light_samples + j, the light it goes to and, where that is a rectangle the batch samples, its sample
// (ChosenLight::batched, in scratch.batched_samples).  Camera samples that shade no surface get no choice.
static inline void BatchLightSamples(const ShadeContext& c, size_t n, ThreadScratch& scratch, uint64_t& light_ticks) {
    const uint64_t t0 = ReadTicks();
    const RenderScene& scene = c.scene;
    const size_t nl = size_t(c.light_samples), lights = scene.area_lights.size();
    scratch.batched_choices.resize(n * nl);
    scratch.batched_samples.resize(n * nl);
    // The choices, and the requests counted per light; then placed light by light (a counting sort).
    std::vector<uint32_t>& first = scratch.batch_first;
    first.assign(lights + 1, 0);
    for (size_t s = 0; s < n; ++s) {
        const PrimaryHit& ph = scratch.hits[s];
        if (!ph.hit || IsBlack(ph.throughput)) continue;
        for (size_t j = s * nl; j < (s + 1) * nl; ++j) {
            ChosenLight& light = scratch.batched_choices[j];
            light = ChooseLightByPower(scene.light_selector, scratch.light_points[j]);
            if (light.index < 0 || !BatchableRectangle(c, scene.area_lights[size_t(light.index)])) continue;
            light.batched = &scratch.batched_samples[j];
            ++first[size_t(light.index) + 1];
        }
    }
    for (size_t l = 0; l < lights; ++l) first[l + 1] += first[l];
    const size_t requests = first[lights];
    scratch.batch_slots.resize(requests);
    scratch.batch_origins.resize(requests);
    scratch.batch_points.resize(requests);
    scratch.batch_out.resize(requests);
    std::vector<uint32_t>& next = scratch.batch_next;
    next.assign(first.begin(), first.end() - 1);
    for (size_t s = 0; s < n; ++s) {
        const PrimaryHit& ph = scratch.hits[s];
        if (!ph.hit || IsBlack(ph.throughput)) continue;
        for (size_t j = s * nl; j < (s + 1) * nl; ++j) {
            const ChosenLight& light = scratch.batched_choices[j];
            if (!light.batched) continue;
            const uint32_t r = next[size_t(light.index)]++;
            scratch.batch_slots[r] = uint32_t(j);
            scratch.batch_origins[r] = ph.surface.p;
            scratch.batch_points[r] = light.u;
        }
    }
    for (size_t l = 0; l < lights; ++l)
        if (first[l + 1] > first[l])
            SampleRectangleBatch(scene.area_lights[l].frame, &scratch.batch_origins[first[l]], first[l + 1] - first[l],
                                 &scratch.batch_points[first[l]], 1, &scratch.batch_out[first[l]]);
    for (size_t r = 0; r < requests; ++r) scratch.batched_samples[scratch.batch_slots[r]] = scratch.batch_out[r];
    light_ticks += ReadTicks() - t0;
}

}  // namespace sphrect::render
