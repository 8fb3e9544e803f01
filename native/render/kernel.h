// The per-tile integrator kernel, specialised at compile time on the scene's features
// (depth of field, glossy materials, medium) and, inside, on the light-sampling technique.
// This is what the Renderer sees of it; the kernel itself is in integrator/ (render_tile.cpp
// drives the stages, one header each).
#pragma once

#include <cstdint>
#include <vector>

#include "core/patterns.h"
#include "options.h"
#include "camera_view.h"
#include "scene.h"

namespace sphrect::render {

struct TileRect {
    int x0, y0, x1, y1;  // pixels [x0, x1) x [y0, y1)
};

struct PrimaryHit;
struct CameraRayMedia;
struct PartialCoverage;
struct DeferredShadowRay;
struct ChosenLight;
struct LightTreeReceiver;
struct LightTreeSample;
struct LightSampleRequests;
struct TriangleSampleRequests;

// Per-thread buffers reused across tiles.
struct ThreadScratch {
    std::vector<PrimaryHit> hits;
    std::vector<RTCRayHit> camera_hits;          // Embree's answers for `hits`' rays
    std::vector<Spectrum> sample_values;         // radiance per camera sample of a chunk
    std::vector<DeferredShadowRay> shadow_rays;  // queued by shading, traced after it
    std::vector<uint8_t> shadow_crossed;         // per shadow ray: it crossed a transparent surface
    std::vector<Point2<float>> pixel_points, lens_points, light_points, bsdf_points;  // per camera sample of a chunk
    SobolPointsBatch sobol_points;                   // (their points drawn together, sample_dimensions.h)
    std::vector<Vec3d> pixel_sums;                   // per technique, per pixel of a chunk
    std::vector<int> tile_screen_lights;             // light_coverage.h: the lights over the tile,
    std::vector<PartialCoverage> partial_coverages;  // and those partly covering the pixel
    std::vector<CameraRayMedia> camera_ray_media;    // per camera sample, where the scene keeps them
    // Light samples taken for a chunk at once (integrator/batched_light_samples.h): per (camera sample, light sample)
    // the light chosen and its sample; the batches' requests (per point, per sample).
    std::vector<ChosenLight> batched_choices;
    std::vector<uint8_t> batched_chosen;            // per camera sample
    std::vector<LightTreeReceiver> tree_receivers;  // the chunk's light samples under the tree: receiver and number,
    std::vector<float> tree_u;                      // and the tree's choice
    std::vector<LightTreeSample> tree_samples;
    std::vector<LightSample<float>> batched_samples;
    std::vector<LightSampleRequests> batch_requests;
    std::vector<TriangleSampleRequests> triangle_requests;
    ThreadScratch();
    ~ThreadScratch();
};

struct TechniqueTally {
    uint64_t light_ticks = 0;  // ReadTicks() units (ticks.h), counted by TimedLightSamplingAt
    double total_seconds = 0;  // whole per-technique pass (light sampling and tracing included)
    double trace_seconds = 0;  // tracing its rays: the occlusion stream, and BSDF rays' emitter search (InlineRayTally)
    uint64_t rays = 0;         // rays traced: the shadow-ray queue's lengths and the emitter-search rays
    uint64_t dropped = 0;      // non-finite samples left out of the image

    TechniqueTally& operator+=(const TechniqueTally& o) {
        light_ticks += o.light_ticks;
        total_seconds += o.total_seconds;
        trace_seconds += o.trace_seconds;
        rays += o.rays;
        dropped += o.dropped;
        return *this;
    }
};

struct TileTally {
    std::vector<TechniqueTally> technique;
    double tile_seconds = 0;          // the tiles, whole: every stage and technique, the image's accumulation
    double camera_seconds = 0;        // the camera stage (camera_trace_seconds included)
    double camera_trace_seconds = 0;  // tracing its camera rays
    uint64_t camera_rays = 0;
    uint64_t surface_hits = 0;  // camera samples whose ray hit a surface

    // (Both tallies have one entry per technique.)
    TileTally& operator+=(const TileTally& o) {
        tile_seconds += o.tile_seconds;
        camera_seconds += o.camera_seconds;
        camera_trace_seconds += o.camera_trace_seconds;
        camera_rays += o.camera_rays;
        surface_hits += o.surface_hits;
        for (size_t k = 0; k < o.technique.size(); ++k) technique[k] += o.technique[k];
        return *this;
    }
};

struct KernelParams {
    const RenderScene* scene;
    const CameraView* view;  // the camera rendered from (camera_view.h)
    const RenderOptions* options;
    int samples;            // camera samples per pixel in this pass
    uint32_t first_sample;  // global index of the pass's first sample
    uint32_t pass;          // pass number (seeds the non-progressive patterns)
    double* const* sums;    // per technique, RGB per pixel
    uint32_t* counts;
    double* alpha_sums;  // per pixel, shared by the techniques (the camera samples are)
};

using TileKernel = void (*)(const KernelParams&, const TileRect&, ThreadScratch&, TileTally&);
TileKernel SelectTileKernel(bool dof, bool glossy, bool medium);

}  // namespace sphrect::render
