// Light samples taken for a whole chunk at once, before its shading: the batched `rectangle`, `rectangle_cosine`
// (core/rectangle_batch.h) and `triangles` (core/triangles_batch.h) techniques and, under every solid-angle technique,
// the batched emissive triangles (core/triangle_batch.h), over every (surface hit, light sample) whose light is known
// before shading: the lights are chosen for the whole chunk (by power from the pattern point alone, or by the light
// tree at the hit, with the receiver normal shading will use) and the requests gathered per light and sampled in SIMD
// batches; shading then takes its choice and sample from here (ChosenLight::batched) and sets up no sampler unless a
// BSDF ray needs a pdf.  The samples equal the scalar sampler's up to rounding (the batch's tests), so images change by
// rounding only.
//
// Requests that stay with the scalar path: `area`, ellipses, rectangles under the other techniques, lights with
// spread (sampled on their clipped part) and textured rectangles sampled by their blocks.  Under the tree, hits whose
// material may have a translucent lobe only where its textures say (then the tree's receiver normal is known only at
// shading, TreeReceiverKnownEarly) choose their lights at shading.
#pragma once

#include <cstdint>
#include <vector>

#include "camera_stage.h"
#include "core/rectangle_batch.h"
#include "core/triangle_batch.h"
#include "core/triangles_batch.h"
#include "light_sampling_at.h"
#include "render/kernel.h"
#include "render/ticks.h"
#include "shade_context.h"
#include "shade_surface.h"

namespace sphrect::render {

// Whether light samples of technique K under this context are batched (not under "ris": its candidates are drawn and
// weighed at shading).
template <Technique K>
static inline bool BatchesLightSamples(const ShadeContext& c) {
    return K != Technique::Area && c.light_selection != LightSelection::Ris &&
           HasChoosableLights(c.scene, c.light_selection);
}

// Whether rectangle light l is sampled by technique K's plain map (what the batch computes) at every point.
template <Technique K>
static inline bool BatchableRectangle(const ShadeContext& c, const AreaLight& l) {
    return (K == Technique::Rectangle || K == Technique::RectangleCosine || K == Technique::Triangles) &&
           l.shape == AreaShape::Rectangle && !l.HasSpread() && !SampledByBlocks(c.scene, l, K, c.emission_blocks);
}

// Emissive triangles are sampled by solid angle under every technique but `area` (LightSamplingAt::Sample).
template <Technique K>
static inline bool BatchableTriangle(const AreaLight& l) {
    return K != Technique::Area && l.shape == AreaShape::Triangle;
}

// Requests of emissive triangles, one sample each, in the order they come (each lane its own triangle).
struct TriangleSampleRequests {
    std::vector<uint32_t> slots;
    std::vector<TriangleEmitter> triangles;
    std::vector<Vec3f> origins;
    std::vector<Point2<float>> points;
    std::vector<LightSample<float>> out;

    void Clear() {
        slots.clear();
        triangles.clear();
        origins.clear();
        points.clear();
    }
    void Add(const AreaLight& l, const Vec3f& origin, uint32_t slot, Point2<float> u) {
        slots.push_back(slot);
        triangles.push_back({l.v0, l.e1, l.e2});
        origins.push_back(origin);
        points.push_back(u);
    }
    void Sample(LightSample<float>* samples) {
        out.resize(slots.size());
        SampleTriangleEmitterBatch(triangles.data(), origins.data(), slots.size(), points.data(), out.data());
        for (size_t r = 0; r < slots.size(); ++r) samples[slots[r]] = out[r];
    }
};

// Requests of one kind, light by light (a counting sort over the lights that have requests, so that a chunk costs
// nothing per light of a scene of thousands): request r is a point `origins[r]` (its shading normal `normals[r]`, for
// rectangle_cosine) with m sample points `points[r m + k]`, whose samples go to `out[r m + k]` and from there to the
// chunk's slots `slots[r] + k`; light l's requests are [first[l], first[l] + count[l]), lights `lights` in the order
// counted.
struct LightSampleRequests {
    int m = 1;
    std::vector<uint32_t> count, first, slots;  // count and first per light of the scene, 0 outside a chunk
    std::vector<int> lights;                    // those with requests
    std::vector<Vec3f> origins, normals;
    std::vector<Point2<float>> points;
    std::vector<LightSample<float>> out;

    void Start(size_t scene_lights, int samples_per_request) {
        m = samples_per_request;
        if (count.size() != scene_lights) {  // (the first chunk; the counts are restored to 0 after each)
            count.assign(scene_lights, 0);
            first.assign(scene_lights, 0);
        }
        lights.clear();
    }
    void Count(int light) {
        if (count[size_t(light)]++ == 0) lights.push_back(light);
    }
    // After the counting: the requests' storage, and each light's first place (its next while placing).
    void Size() {
        uint32_t n = 0;
        for (const int l : lights) {
            first[size_t(l)] = n;
            n += count[size_t(l)];
        }
        slots.resize(n);
        origins.resize(n);
        normals.resize(n);
        points.resize(size_t(n) * size_t(m));
        out.resize(size_t(n) * size_t(m));
    }
    // Request of light `light` at `origin` for the slots [slot, slot + m), the choices' points from `choices`.
    void Place(int light, const Vec3f& origin, const Vec3f& normal, uint32_t slot, const ChosenLight* choices) {
        const uint32_t r = first[size_t(light)]++;
        slots[r] = slot;
        origins[r] = origin;
        normals[r] = normal;
        for (int k = 0; k < m; ++k) points[size_t(r) * m + k] = choices[k].u;
    }
    // Samples them by technique K, light by light, into samples[slot]; the counts back to 0.
    template <Technique K>
    void Sample(const RenderScene& scene, LightSample<float>* samples) {
        for (const int l : lights) {
            const size_t n = count[size_t(l)], r = first[size_t(l)] - n;  // (Place advanced first by n)
            count[size_t(l)] = 0;
            const RectLightFrame<float>& frame = scene.area_lights[size_t(l)].frame;
            if constexpr (K == Technique::RectangleCosine)
                SampleRectangleCosineBatch(frame, &origins[r], &normals[r], n, &points[r * m], m, &out[r * m]);
            else if constexpr (K == Technique::Triangles)
                SampleTrianglesBatch(frame, &origins[r], n, &points[r * m], m, &out[r * m]);
            else
                SampleRectangleBatch(frame, &origins[r], n, &points[r * m], m, &out[r * m]);
        }
        for (size_t r = 0; r < slots.size(); ++r)
            for (int k = 0; k < m; ++k) samples[slots[r] + k] = out[r * m + k];
    }
};

// Fills scratch.batched_choices for the chunk's n camera samples: per camera sample s and light sample j, at
// s * light_samples + j, the light it goes to and, where that is a rectangle the batch samples, its sample
// (ChosenLight::batched, in scratch.batched_samples); scratch.batched_chosen[s] says whether s's lights were chosen
// here (not for camera samples that shade no surface, nor under the tree for hits TreeReceiverKnownEarly rejects).  A
// point whose light samples all go to the same rectangle is one request of them all (one setup, as the scalar sampler
// kept for the point's samples); other points' samples are requests of one each.
template <Technique K, bool kGlossy>
static inline void BatchLightSamples(const ShadeContext& c, size_t n, ThreadScratch& scratch, uint64_t& light_ticks) {
    const uint64_t t0 = ReadTicks();
    const RenderScene& scene = c.scene;
    const size_t nl = size_t(c.light_samples), lights = scene.area_lights.size();
    scratch.batched_choices.resize(n * nl);
    scratch.batched_samples.resize(n * nl);
    scratch.batched_chosen.assign(n, 0);
    scratch.batch_requests.resize(2);
    scratch.triangle_requests.resize(1);
    LightSampleRequests &per_point = scratch.batch_requests[0], &per_sample = scratch.batch_requests[1];
    TriangleSampleRequests& triangles = scratch.triangle_requests[0];
    triangles.Clear();
    per_point.Start(lights, int(nl));
    per_sample.Start(lights, 1);
    // Whether camera sample s's choices are one request (all the same batched light) and that light.
    auto one_request = [&](size_t s) {
        const ChosenLight* choices = &scratch.batched_choices[s * nl];
        if (nl < 2 || !choices[0].batched || scene.area_lights[size_t(choices[0].index)].shape != AreaShape::Rectangle)
            return -1;
        for (size_t j = 1; j < nl; ++j)
            if (choices[j].index != choices[0].index) return -1;
        return choices[0].index;
    };
    const bool tree = c.light_selection == LightSelection::Tree;
    auto chosen = [&](size_t s) { return scratch.batched_chosen[s] != 0; };
    for (size_t s = 0; s < n; ++s) {
        const PrimaryHit& ph = scratch.hits[s];
        scratch.batched_chosen[s] =
            ph.hit && !IsBlack(ph.throughput) && (!tree || TreeReceiverKnownEarly<kGlossy>(scene, ph.surface));
    }
    // Under the tree, every choice of the chunk in one batched descent (LightTree::SampleBatch, the same floats as
    // LightTreeAt's), at the receiver shading will use.
    if (tree) {
        auto& receivers = scratch.tree_receivers;
        auto& u = scratch.tree_u;
        receivers.clear();
        u.clear();
        for (size_t s = 0; s < n; ++s) {
            if (!chosen(s)) continue;
            const SurfaceHit& h = scratch.hits[s].surface;
            const Vec3f normal = TreeReceiverNormal<kGlossy>(h, scene.bsdfs[size_t(h.material)]);
            for (size_t j = s * nl; j < (s + 1) * nl; ++j) {
                receivers.emplace_back(h.p, normal);
                u.push_back(scratch.light_points[j].v);
            }
        }
        scratch.tree_samples.resize(receivers.size());
        scene.light_tree().SampleBatch(receivers.data(), u.data(), receivers.size(), scratch.tree_samples.data());
    }
    size_t tree_sample = 0;
    for (size_t s = 0; s < n; ++s) {
        if (!chosen(s)) continue;
        const PrimaryHit& ph = scratch.hits[s];
        for (size_t j = s * nl; j < (s + 1) * nl; ++j) {
            ChosenLight& light = scratch.batched_choices[j];
            light = tree ? ChosenFromTree(scene, scratch.tree_samples[tree_sample++], scratch.light_points[j])
                         : ChooseLightByPower(scene.light_selector, scratch.light_points[j]);
            if (light.index < 0) continue;
            const AreaLight& l = scene.area_lights[size_t(light.index)];
            if (BatchableRectangle<K>(c, l) || BatchableTriangle<K>(l)) light.batched = &scratch.batched_samples[j];
        }
        if (const int l = one_request(s); l >= 0) {
            per_point.Count(l);
            continue;
        }
        for (size_t j = s * nl; j < (s + 1) * nl; ++j) {
            const ChosenLight& light = scratch.batched_choices[j];
            if (!light.batched) continue;
            const AreaLight& l = scene.area_lights[size_t(light.index)];
            if (l.shape == AreaShape::Triangle)
                triangles.Add(l, ph.surface.p, uint32_t(j), light.u);
            else
                per_sample.Count(light.index);
        }
    }
    per_point.Size();
    per_sample.Size();
    for (size_t s = 0; s < n; ++s) {
        if (!chosen(s)) continue;
        const SurfaceHit& h = scratch.hits[s].surface;  // (the normal: the technique's, ShadeSurface)
        if (const int l = one_request(s); l >= 0) {
            per_point.Place(l, h.p, h.ns, uint32_t(s * nl), &scratch.batched_choices[s * nl]);
            continue;
        }
        for (size_t j = s * nl; j < (s + 1) * nl; ++j)
            if (const ChosenLight& light = scratch.batched_choices[j];
                light.batched && scene.area_lights[size_t(light.index)].shape == AreaShape::Rectangle)
                per_sample.Place(light.index, h.p, h.ns, uint32_t(j), &light);
    }
    per_point.Sample<K>(scene, scratch.batched_samples.data());
    per_sample.Sample<K>(scene, scratch.batched_samples.data());
    triangles.Sample(scratch.batched_samples.data());
    light_ticks += ReadTicks() - t0;
}

}  // namespace sphrect::render
