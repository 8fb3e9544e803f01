// The camera stage of a chunk: its camera samples' pattern points and rays, traced together,
// and what each sees directly -- visible lights before the first surface, the surface's own
// emission and the background.
// It is the same for every technique, which then shades the same first hits.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "camera_ray_media.h"
#include "chunk.h"
#include "light_coverage.h"
#include "render/camera.h"
#include "render/embree_rays.h"
#include "render/kernel.h"
#include "sample_dimensions.h"
#include "surface_hit.h"
#include "textured_emission.h"
#include "transparency.h"

namespace sphrect::render {

struct PrimaryHit {
    Ray ray;
    float t_end = kInf;  // end of the camera ray's segment: surface hit or escape
    bool hit = false;
    SurfaceHit surface;
    // Technique-independent part: visible lights before the surface, background; starts from the
    // camera stage's control-variate offset (light_coverage.h).
    Spectrum seen;
    // The area light whose emission this sample does not add, because the offset holds the pixel's
    // estimate of it (light_coverage.h, PartialCoverage::occluded), or -1.
    int light_seen_by_estimate = -1;
    uint64_t rng_seed = 0;
    float alpha = 1;  // the film's alpha: 0 where it sees a holdout or, with a transparent film, escapes
    // What the hit's light is multiplied by: 1, but for a ray that went through transparent surfaces (transparency.h).
    Spectrum throughput{1, 1, 1};
};

// Pattern points and camera rays of the chunk's camera samples, pixel by pixel:
// scratch.hits[c * samples + i] is sample i of chunk pixel c, its light and BSDF points at
// scratch.light_points / bsdf_points [(c * samples + i) * light_samples ...].
template <bool kDof>
static inline void GenerateCameraSamples(const KernelParams& p, const TileChunk& chunk, bool sample_bsdf,
                                         ThreadScratch& scratch) {
    const CameraModel& camera = p.view->camera;
    const uint32_t n = uint32_t(p.samples);
    const bool coverage = !kDof && UsesLightCoverage(*p.scene, *p.view, *p.options);
    if (coverage) ScreenLightsOverTile(*p.view, chunk.tile, scratch.tile_screen_lights);
    FillChunkSamplePoints<kDof>(p, chunk, camera.width, sample_bsdf, scratch);
    for (int c = 0; c < chunk.count; ++c) {
        const int x = chunk.X(c), y = chunk.Y(c);
        const uint64_t pixel_seed = PixelSeed(p.options->seed, chunk.PixelIndex(c, camera.width));
        const Point2<float>* pixel_points = &scratch.pixel_points[size_t(c) * n];
        const Point2<float>* lens_points = &scratch.lens_points[size_t(c) * n];
        PrimaryHit* hits = &scratch.hits[size_t(c) * n];
        auto& partial = scratch.partial_coverages;
        partial.clear();
        if (coverage)
            PartialCoverages(*p.scene, *p.view, scratch.tile_screen_lights, x, y, p.samples,
                             MixBits(DimensionSeed(pixel_seed, kDimLightEdge) ^ p.first_sample), partial);
        const int light_seen_by_estimate = LightSeenByEstimate(partial);
        for (uint32_t i = 0; i < n; ++i) {
            // The pixel pattern's point, through the pixel filter in x and y separately (stratification kept).
            const Point2<float> jitter = pixel_points[i];
            const float fx = FilmCoordinate(camera.filter, x, jitter.u);
            const float fy = FilmCoordinate(camera.filter, y, jitter.v);
            hits[i].ray = GenerateCameraRay<kDof>(camera, fx, fy, kDof ? lens_points[i] : Point2<float>{});
            hits[i].rng_seed = CameraSampleRngSeed(pixel_seed, p.first_sample + i);
            hits[i].seen = partial.empty() ? Spectrum() : CoverageOffset(partial, fx, fy);
            hits[i].light_seen_by_estimate = light_seen_by_estimate;
            hits[i].throughput = {1, 1, 1};
        }
    }
}

// Traces the camera rays of hits[0..n) into rtc_hits[0..n), as one stream (IntersectCameraRays).
static inline void TraceCameraRays(RTCScene scene, const PrimaryHit* hits, size_t n, RTCRayHit* rtc_hits) {
    for (size_t i = 0; i < n; ++i)
        rtc_hits[i] = MakeRTCRayHit(hits[i].ray.o, hits[i].ray.d, hits[i].ray.tmin, hits[i].ray.tmax, kRayCamera);
    IntersectCameraRays(scene, rtc_hits, n);
}

// Transmittance from the camera to t along the camera ray: the world medium's (kMedium), times the object volumes'
// (`media`: what the ray meets, null unless KeepsCameraRayMedia).
template <bool kMedium>
static inline Spectrum CameraRayTransmittance(const RenderScene& scene, const CameraRayMedia* media, float t) {
    const Spectrum tr = SegmentTransmittance<kMedium>(scene.medium, t);
    if constexpr (kMedium)
        if (media && scene.has_volumes) return tr * media->volumes.TransmittanceTo(t);
    return tr;
}

// The soft point and spot lights' discs the camera ray crosses between t_begin and its hit, and a soft sun's
// cone where it escapes (not through a transparent film), as Cycles 3.4's camera rays see them unless hidden.
template <bool kMedium, class Weighted>
[[gnu::noinline]] static void AddSoftLightsSeen(const RenderScene& scene, const PrimaryHit& out, CameraRayMedia* media,
                                                float t_begin, const Weighted& weighted, Spectrum& seen) {
    const float t_end = std::min(out.t_end, out.ray.tmax);
    for (const SoftLightRef& s : scene.soft_lights) {
        const DeltaLight& l = scene.delta_lights[s.delta];
        if (!l.visible) continue;
        const SoftLightCrossing x = CrossSoftLight(l, out.ray.o, out.ray.d);
        if (!x.hit) continue;
        const bool seen_here =
            l.kind == DeltaKind::Sun ? !out.hit && !scene.film_transparent : x.t >= t_begin && x.t < t_end;
        if (seen_here) seen += weighted(x.le * CameraRayTransmittance<kMedium>(scene, media, x.t));
    }
}

// What the camera ray sees directly from t_begin up to its hit (or escape), times `throughput` (kWeighted; else
// 1): the hit's emission and the analytic lights it crosses before it.
template <bool kMedium, bool kWeighted>
static inline void AddSeenAlongSegment(const RenderScene& scene, const PrimaryHit& out, CameraRayMedia* media,
                                       float t_begin, Spectrum& seen) {
    auto weighted = [&](const Spectrum& v) { return kWeighted ? out.throughput * v : v; };
    // Emissive meshes are seen at their hit (two-sided, like their lights); the loop below covers
    // only the analytic lights, so they are not counted twice.
    if (out.hit && scene.has_mesh_lights) {
        if (!IsBlack(scene.bsdfs[out.surface.material].emission))
            seen += weighted(EmissionSeenAtHit(scene, out.surface) *
                             CameraRayTransmittance<kMedium>(scene, media, out.t_end));
    }
    scene.analytic_light_finder.ForEachCrossing(
        out.ray.o, out.ray.d, t_begin, std::min(out.t_end, out.ray.tmax), LightsSought::VisibleToCamera,
        [&](int i, float t) {
            if (i == out.light_seen_by_estimate) return;
            seen += weighted(RadianceOfCrossedLight(scene, scene.area_lights[i], out.ray.o, out.ray.d, t) *
                             CameraRayTransmittance<kMedium>(scene, media, t));
        });
    if (!scene.soft_lights.empty()) AddSoftLightsSeen<kMedium>(scene, out, media, t_begin, weighted, seen);
}

// The camera ray's first hit, or what lies past it while it is transparent (transparency.h): the hit shading
// takes, the ray's throughput, and what it sees on the way.  Out of line: scenes without transparency skip it.
template <bool kGlossy, bool kMedium>
[[gnu::noinline]] static void FollowThroughTransparent(const RenderScene& scene, PrimaryHit& out, CameraRayMedia* media,
                                                       Spectrum& seen) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int transparent_hits = 0; out.hit; ++transparent_hits) {
        const SurfaceTransparency st = TransparencyAt(scene, out.surface);
        if (IsBlack(st.transparency)) return;
        PCG32 choice(out.rng_seed, 0x7ea5a9e1ull + uint64_t(transparent_hits));
        if (!CameraRayThroughTransparent(st, choice.NextFloat(), out.throughput)) return;
        if (transparent_hits == kMaxTransparentHits) {  // Cycles ends the path: black, opaque
            out.throughput = {};
            return;
        }
        if (media) media->passages[size_t(media->passage_count++)] = {out.t_end, out.throughput};
        const float t_begin = out.t_end;
        RTCRayHit rh = MakeRTCRayHit(out.ray.o, out.ray.d, BeyondHit(out.t_end), out.ray.tmax, kRayCamera);
        rtcIntersect1(scene.rtc_scene, &ctx, &rh);
        out.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        out.t_end = out.hit ? rh.ray.tfar : kInf;
        if (out.hit) {
            out.surface = MakeSurfaceHit<kGlossy>(scene, out.ray, rh);
            out.surface.transparent_depth = uint8_t(transparent_hits + 1);  // the Light Path node's
        }
        AddSeenAlongSegment<kMedium, true>(scene, out, media, t_begin, seen);
    }
}

// The image world's radiance a camera ray that escapes towards d sees (the camera's own image, where the world
// shows the camera another one).  Out of line: scenes without one skip it.
[[gnu::noinline]] static Spectrum EnvironmentSeen(const RenderScene& scene, const Vec3f& d) {
    const EnvironmentLight& e = scene.has_camera_environment ? scene.camera_environment : scene.environment;
    return EnvironmentRadiance(e, scene.images[size_t(e.image)], d);
}

// The camera ray's hit that shading takes (its first, or past transparent surfaces), its throughput, and what it
// sees directly (shared by all techniques).  media: what the ray meets in a medium (CameraRayMedia), or null.
template <bool kGlossy, bool kMedium>
static inline void FinishCameraSample(const RenderScene& scene, const RTCRayHit& rh, CameraRayMedia* media,
                                      PrimaryHit& out) {
    out.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    out.t_end = out.hit ? rh.ray.tfar : kInf;
    if (out.hit) out.surface = MakeSurfaceHit<kGlossy>(scene, out.ray, rh);
    Spectrum seen = out.seen;  // the coverage offset GenerateCameraSamples set
    AddSeenAlongSegment<kMedium, false>(scene, out, media, out.ray.tmin, seen);
    if (scene.has_transparency && out.hit) FollowThroughTransparent<kGlossy, kMedium>(scene, out, media, seen);
    if (!out.hit && !scene.film_transparent && (scene.world_visibility.rays() & kRayCamera)) {
        // The image world (environment_light.h) replaces the background (black then).
        const Spectrum sky = scene.has_environment || scene.has_camera_environment ? EnvironmentSeen(scene, out.ray.d)
                                                                                   : scene.background;
        seen += out.throughput * sky * CameraRayTransmittance<kMedium>(scene, media, kInf);
    }
    if (scene.film_alpha) {
        // 1 - the share of the pixel that is a hole: the holdout at the hit, or the escape through a transparent film.
        const float through = Average(out.throughput);
        const float hole = out.hit ? std::min(scene.bsdfs[out.surface.material].holdout, 1.0f)
                                   : (scene.film_transparent ? 1.0f : 0.0f);
        out.alpha = 1 - through * hole;
    }
    out.seen = seen;
}

// media: in a scene that keeps them (kMedium, KeepsCameraRayMedia), what each sample's ray meets, found here.
template <bool kGlossy, bool kMedium>
static inline void FinishCameraSamples(const RenderScene& scene, const RTCRayHit* rtc_hits, size_t n, PrimaryHit* hits,
                                       CameraRayMedia* media) {
    if constexpr (kMedium)
        if (KeepsCameraRayMedia(scene)) {
            for (size_t s = 0; s < n; ++s) {
                media[s].passage_count = 0;
                if (scene.has_volumes)
                    scene.volumes.Segments(hits[s].ray.o, hits[s].ray.d, media[s].volumes, hits[s].ray.tmin);
                FinishCameraSample<kGlossy, kMedium>(scene, rtc_hits[s], &media[s], hits[s]);
            }
            return;
        }
    for (size_t s = 0; s < n; ++s) FinishCameraSample<kGlossy, kMedium>(scene, rtc_hits[s], nullptr, hits[s]);
}

}  // namespace sphrect::render
