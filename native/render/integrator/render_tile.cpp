// The integrator: direct lighting at the first hit, emission seen directly, and single
// scattering in a homogeneous medium, all estimated per camera sample.
//
// Light selection: one area light per light sample, chosen by power (LightSelector); delta
// lights are all evaluated once per camera sample (and at every scattering point).
// MIS (Veach 1997): each light sample is paired with one BSDF (or, in the medium, phase-function)
// sample whose direction finds the area lights it crosses (intersected analytically: lights are
// not in Embree's scene); the background is reached only by BSDF/phase rays (weight 1).  Lights
// do not occlude anything (they are transparent, as in Cycles).
// Visibility: shading queues every contribution with its occlusion ray (shadow_queue.h), and a
// chunk's rays are traced together after its shading.  A BSDF/phase ray that reaches no emitter
// is not traced at all.
//
// A tile, chunk by chunk (chunk.h): generate camera samples -> trace them -> per technique:
// shade (queue) -> resolve shadow rays -> sum per pixel; then add the sums to the image.
// The stages' functions (integrator/*.h) are `static inline`: this file is their only user, and
// internal linkage lets the compiler inline them into the tile loop as when they were one file
// (as plain `inline` functions a render ran more instructions: docs/architecture.md, measured choices).
#include <chrono>
#include <cstdint>

#include "batched_light_samples.h"
#include "camera_stage.h"
#include "chunk.h"
#include "film.h"
#include "render/kernel.h"
#include "shade_context.h"
#include "shade_surface.h"
#include "shade_volume.h"
#include "shadow_queue.h"

namespace sphrect::render {

ThreadScratch::ThreadScratch() = default;
ThreadScratch::~ThreadScratch() = default;

namespace {

// Thread-seconds of a stage (the stats' camera and per-technique times).
class Stopwatch {
  public:
    double Seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

  private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// ShadeCameraSample where the scene keeps CameraRayMedia (KeepsCameraRayMedia): the surface's light through the
// object volumes, and the medium's scattering, each point of it weighted by the camera ray's throughput there
// (media.ThroughputAt: past the transparent surfaces before it; the surface takes the whole ray's, ph.throughput,
// which `sink` holds).  The shadow rays' transmittance through object volumes is ResolveShadowRays'.
template <Technique K, bool kGlossy>
[[gnu::noinline]] void ShadeCameraSampleInMedia(const ShadeContext& c, const PrimaryHit& ph,
                                                const CameraRayMedia& media, const Point2<float>* light_points,
                                                const Point2<float>* bsdf_points, const ChosenLight* batched_choices,
                                                const ShadowSink& sink, uint64_t& light_ticks) {
    const RenderScene& scene = c.scene;
    PCG32 rng(ph.rng_seed, 0x5851f42dull);
    if (ph.hit)
        ShadeSurface<K, kGlossy, true>(c, ph.surface, -ph.ray.d, light_points, bsdf_points, batched_choices, rng,
                                       sink.Scaled(CameraRayTransmittance<true>(scene, &media, ph.surface.t)),
                                       light_ticks);
    const ShadowSink unweighted{sink.queue, sink.sample};
    if (scene.has_volumes)
        ShadeObjectVolumes<K>(c, ph, media, light_points, bsdf_points, rng, unweighted, light_ticks);
    else if (scene.has_medium)
        ShadeVolume<K>(c, ph, light_points, bsdf_points, rng, unweighted, light_ticks, &media);
}

// Everything a camera sample receives beyond what it sees directly, queued on `sink`; media: what its ray meets in a
// medium (null unless the scene keeps them).
template <Technique K, bool kGlossy, bool kMedium>
void ShadeCameraSample(const ShadeContext& c, const PrimaryHit& ph, const CameraRayMedia* media,
                       const Point2<float>* light_points, const Point2<float>* bsdf_points,
                       const ChosenLight* batched_choices, const ShadowSink& sink, uint64_t& light_ticks) {
    if constexpr (kMedium)
        if (media)
            return ShadeCameraSampleInMedia<K, kGlossy>(c, ph, *media, light_points, bsdf_points, batched_choices, sink,
                                                        light_ticks);
    PCG32 rng(ph.rng_seed, 0x5851f42dull);
    if (ph.hit)
        ShadeSurface<K, kGlossy, kMedium>(c, ph.surface, -ph.ray.d, light_points, bsdf_points, batched_choices, rng,
                                          sink.Scaled(SegmentTransmittance<kMedium>(c.scene.medium, ph.surface.t)),
                                          light_ticks);
    // (The run-time test only matters for the benchmark's forced all-features kernel.)
    if constexpr (kMedium)
        if (c.scene.has_medium) ShadeVolume<K>(c, ph, light_points, bsdf_points, rng, sink, light_ticks);
}

// The shading stage of one technique over a chunk's n camera samples: each sample's value
// starts as what it sees directly, and its shadow rays go to scratch.shadow_rays.
template <bool kGlossy, bool kMedium>
void ShadeCameraSamples(Technique technique, const ShadeContext& c, size_t n, ThreadScratch& scratch,
                        uint64_t& light_ticks) {
    const size_t nl = size_t(c.light_samples);
    auto& queue = scratch.shadow_rays;
    queue.clear();
    const CameraRayMedia* media = KeepsCameraRayMedia(c.scene) ? scratch.camera_ray_media.data() : nullptr;
    DispatchTechnique(technique, [&](auto tag) {
        constexpr Technique K = decltype(tag)::value;
        const bool batched = BatchesLightSamples<K>(c);
        if (batched) BatchLightSamples<K, kGlossy>(c, n, scratch, light_ticks);
        for (uint32_t s = 0; s < uint32_t(n); ++s) {
            const PrimaryHit& ph = scratch.hits[s];
            scratch.sample_values[s] = ph.seen;
            if (IsBlack(ph.throughput)) continue;  // past too many transparent surfaces
            if (c.added_shading_ticks && ph.hit) SpinTicks(c.added_shading_ticks);  // (the cost-model sweep's)
            ShadeCameraSample<K, kGlossy, kMedium>(
                c, ph, media ? &media[s] : nullptr, &scratch.light_points[s * nl], &scratch.bsdf_points[s * nl],
                batched && scratch.batched_chosen[s] ? &scratch.batched_choices[s * nl] : nullptr,
                ShadowSink{&queue, s, ph.throughput}, light_ticks);
        }
    });
}

// Sizes the per-thread buffers for chunks of chunk_pixels pixels (no allocation once they fit).
void ReserveScratch(const RenderScene& scene, ThreadScratch& scratch, int chunk_pixels, uint32_t samples,
                    uint32_t light_samples, size_t techniques) {
    const size_t chunk_samples = size_t(chunk_pixels) * samples;
    scratch.hits.resize(chunk_samples);
    scratch.camera_hits.resize(chunk_samples);
    scratch.sample_values.resize(chunk_samples);
    scratch.pixel_points.resize(chunk_samples);
    scratch.lens_points.resize(chunk_samples);
    scratch.light_points.resize(chunk_samples * light_samples);
    scratch.bsdf_points.resize(chunk_samples * light_samples);
    scratch.pixel_sums.resize(size_t(chunk_pixels) * techniques);
    if (KeepsCameraRayMedia(scene)) scratch.camera_ray_media.resize(chunk_samples);
}

template <bool kDof, bool kGlossy, bool kMedium>
void RenderTile(const KernelParams& p, const TileRect& tile, ThreadScratch& scratch, TileTally& tally) {
    const Stopwatch whole_tile;
    const RenderScene& scene = *p.scene;
    const RenderOptions& opt = *p.options;
    const uint32_t n = uint32_t(p.samples);
    const int chunk_pixels = ChunkPixels(tile, n, uint32_t(opt.light_samples));
    ReserveScratch(scene, scratch, chunk_pixels, n, uint32_t(opt.light_samples), opt.techniques.size());
    const ShadeContext ctx = MakeShadeContext<kMedium>(scene, opt);
    tally.technique.resize(opt.techniques.size());
    for (int first = 0; first < TilePixels(tile); first += chunk_pixels) {
        const TileChunk chunk{tile, first, std::min(chunk_pixels, TilePixels(tile) - first)};
        const size_t chunk_n = size_t(chunk.count) * n;

        const Stopwatch camera;
        GenerateCameraSamples<kDof>(p, chunk, ctx.sample_bsdf, scratch);
        const Stopwatch camera_trace;
        TraceCameraRays(scene.rtc_scene, scratch.hits.data(), chunk_n, scratch.camera_hits.data());
        if (ctx.added_ray_ticks) SpinTicks(ctx.added_ray_ticks * chunk_n);  // (the cost-model sweep's)
        tally.camera_trace_seconds += camera_trace.Seconds();
        FinishCameraSamples<kGlossy, kMedium>(scene, scratch.camera_hits.data(), chunk_n, scratch.hits.data(),
                                              scratch.camera_ray_media.data());
        tally.camera_seconds += camera.Seconds();
        tally.camera_rays += chunk_n;
        for (size_t s = 0; s < chunk_n; ++s) tally.surface_hits += scratch.hits[s].hit;

        // Every technique over the same camera samples.
        for (size_t k = 0; k < opt.techniques.size(); ++k) {
            TechniqueTally& tt = tally.technique[k];
            const Stopwatch shading;
            inline_rays = {};
            ShadeCameraSamples<kGlossy, kMedium>(opt.techniques[k], ctx, chunk_n, scratch, tt.light_ticks);
            tt.rays += scratch.shadow_rays.size() + inline_rays.rays;
            if (inline_rays.ticks) tt.trace_seconds += double(inline_rays.ticks) / TicksPerSecond();
            const Stopwatch trace;
            ResolveShadowRays(scene, scratch.shadow_rays, scratch.sample_values.data(), scratch.shadow_crossed);
            if (ctx.added_ray_ticks) SpinTicks(ctx.added_ray_ticks * scratch.shadow_rays.size());
            tt.trace_seconds += trace.Seconds();
            tt.dropped +=
                SumPixelSamples(scratch.sample_values.data(), chunk.count, n, &scratch.pixel_sums[k * chunk_pixels]);
            tt.total_seconds += shading.Seconds();
        }
        AddChunkToImage(p, chunk, scratch.pixel_sums.data(), chunk_pixels, scratch.hits.data());
    }
    tally.tile_seconds += whole_tile.Seconds();
}

template <bool kDof, bool kGlossy>
TileKernel SelectMedium(bool medium) {
    return medium ? &RenderTile<kDof, kGlossy, true> : &RenderTile<kDof, kGlossy, false>;
}
template <bool kDof>
TileKernel SelectGlossy(bool glossy, bool medium) {
    return glossy ? SelectMedium<kDof, true>(medium) : SelectMedium<kDof, false>(medium);
}

}  // namespace

TileKernel SelectTileKernel(bool dof, bool glossy, bool medium) {
    return dof ? SelectGlossy<true>(glossy, medium) : SelectGlossy<false>(glossy, medium);
}

}  // namespace sphrect::render
