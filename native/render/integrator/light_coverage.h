// The control variate of the lights the camera sees (render/screen_lights.h): a camera sample at
// film point x of a pixel that a light's image partly covers starts from
//     sum over those lights of L_j (coverage_j - [x inside image j]),
// so that, with what it then sees, its expectation is the pixel's and its variance is that of
// f - g.  Pixels wholly outside an image need nothing, nor do pixels wholly inside one where
// nothing hides the light (g is constant there).  Where something in front hides part of the light
// (ProbeLightInPixel finds it), the pixel's share of the light seen unoccluded is estimated instead,
// with a grid of rays that cost no shading (EstimateSeenCoverage), and replaces what its camera
// samples see of that light.  Off under depth of field (no screen lights then) and in a medium (the
// light is seen attenuated, so g would not cancel), and when RenderOptions::analytic_light_coverage
// is false.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "render/camera.h"
#include "render/embree_rays.h"
#include "render/kernel.h"
#include "render/screen_lights.h"

namespace sphrect::render {

struct PartialCoverage {
    const ScreenLight* light;
    // The exact share of the pixel the image covers, in (0, 1); or, when `occluded`, an unbiased
    // estimate of the share where the light is seen unoccluded, which then replaces the camera
    // samples' sight of the light (PrimaryHit::light_seen_by_estimate).
    float coverage;
    bool occluded;
};

// EstimateSeenCoverage's rays per camera sample of the pass (a jittered grid over the pixel), and
// the most rays per pixel and pass (kSeenCoverageMaxGrid^2).  At 16 a grid point costs about a
// tenth of a camera sample, and only pixels at the edge of a light that something hides draw them.
constexpr int kSeenCoverageRaysPerSample = 16;
constexpr int kSeenCoverageMaxGrid = 128;

static inline bool UsesLightCoverage(const RenderScene& scene, const RenderOptions& opt) {
    // (A light behind a transparent surface is seen filtered: the coverage estimate does not model it.  The
    // estimate is the light's share of the pixel's 1-px box: other pixel filters estimate it from the samples.)
    return opt.analytic_light_coverage && !scene.has_medium && !scene.has_transparency &&
           !scene.screen_lights.empty() && scene.camera.filter.IsUnitBox();
}

// The screen lights whose image may overlap the tile (indices into scene.screen_lights).
static inline void ScreenLightsOverTile(const RenderScene& scene, const TileRect& tile, std::vector<int>& out) {
    out.clear();
    for (size_t i = 0; i < scene.screen_lights.size(); ++i) {
        const ScreenLight& s = scene.screen_lights[i];
        if (s.x1 > tile.x0 && s.x0 < tile.x1 && s.y1 > tile.y0 && s.y0 < tile.y1) out.push_back(int(i));
    }
}

// The rays from the camera through film points (fx[k], fy[k]) inside s's image that reach the
// light, into rays[0..n); returns n.  Each tests whether something in front hides the light, by the
// camera ray's own rule (a surface before the light's distance, FinishCameraSample): a shadow ray's
// margin (ShadowRayLength) would miss a wall the light touches.
static inline int CameraRaysToScreenLight(const RenderScene& scene, const ScreenLight& s, const float* fx,
                                          const float* fy, int count, RTCRay* rays) {
    const AreaLight& light = scene.area_lights[s.light];
    int n = 0;
    for (int k = 0; k < count; ++k) {
        if (!InsideScreenLight(s, fx[k], fy[k])) continue;
        const Ray r = GenerateCameraRay<false>(scene.camera, fx[k], fy[k], {});
        const float t = IntersectAreaLight(light, r.o, r.d, r.tmax);
        if (t < kInf && t > r.tmin) rays[n++] = MakeRTCRay(r.o, r.d, r.tmin, t);
    }
    OccludeShadowRays(scene.rtc_scene, rays, size_t(n), sizeof(RTCRay));
    return n;
}

static inline int CountBlocked(const RTCRay* rays, int n) {
    int blocked = 0;
    for (int k = 0; k < n; ++k) blocked += rays[k].tfar < 0;  // Embree sets tfar to -inf
    return blocked;
}

// How many of the 3 x 3 probe points of pixel (x, y) inside s's image see the light, and how many
// find it hidden by something in front.  Where something is, g does not cancel f: the offset would
// add the image edge's noise to the occluder's.  The probes depend only on the scene and the pixel,
// so no choice made from them can bias the image.
struct ProbeCounts {
    int reached = 0, blocked = 0;
};

static inline ProbeCounts ProbeLightInPixel(const RenderScene& scene, const ScreenLight& s, int x, int y) {
    constexpr float kProbes[3] = {0.05f, 0.5f, 0.95f};
    float fx[9], fy[9];
    for (int k = 0; k < 9; ++k) fx[k] = x + kProbes[k % 3], fy[k] = y + kProbes[k / 3];
    RTCRay rays[9];
    const int n = CameraRaysToScreenLight(scene, s, fx, fy, 9, rays);
    return {n, CountBlocked(rays, n)};
}

// The side of EstimateSeenCoverage's grid for a pass of `samples` camera samples: about
// kSeenCoverageRaysPerSample rays per camera sample (each costs one ray and no shading), at most
// kSeenCoverageMaxGrid^2.
static inline int SeenCoverageGrid(int samples) {
    const int side = int(std::ceil(std::sqrt(double(kSeenCoverageRaysPerSample) * samples)));
    return std::clamp(side, 1, kSeenCoverageMaxGrid);
}

// An unbiased estimate of the share of pixel (x, y) where the camera sees light s unoccluded, from
// a jittered grid of film points and their rays to the light.  Where the probes find the light
// mostly seen, the exact coverage c less the grid's share of blocked points, so only the
// occluder's edge is left to the grid; where mostly hidden, the grid's share of points that see
// it, which is never negative.
static inline float EstimateSeenCoverage(const RenderScene& scene, const ScreenLight& s, int x, int y, double c,
                                         ProbeCounts probes, int grid, uint64_t seed) {
    constexpr int kBatch = 64;
    PCG32 rng(seed);
    const int total = grid * grid;
    int reached = 0, blocked = 0;
    for (int first = 0; first < total; first += kBatch) {
        const int count = std::min(kBatch, total - first);
        float fx[kBatch], fy[kBatch];
        for (int k = 0; k < count; ++k) {
            const int cell = first + k;
            fx[k] = x + ((cell % grid) + rng.NextFloat()) / grid;
            fy[k] = y + ((cell / grid) + rng.NextFloat()) / grid;
        }
        RTCRay rays[kBatch];
        const int n = CameraRaysToScreenLight(scene, s, fx, fy, count, rays);
        reached += n;
        blocked += CountBlocked(rays, n);
    }
    if (2 * probes.blocked <= probes.reached) return float(c - double(blocked) / total);
    return float(reached - blocked) / total;
}

// The lights of `candidates` that partly cover pixel (x, y), with their coverage.  At most one of
// them, the first found hidden in part, gets the estimate of its seen share (a camera sample has
// one PrimaryHit::light_seen_by_estimate); others hidden in part keep the sampled estimate.
// `seed` draws the estimate's grid (one per pixel and pass of `samples` camera samples).
static inline void PartialCoverages(const RenderScene& scene, const std::vector<int>& candidates, int x, int y,
                                    int samples, uint64_t seed, std::vector<PartialCoverage>& out) {
    out.clear();
    bool estimated = false;
    for (int i : candidates) {
        const ScreenLight& s = scene.screen_lights[i];
        if (s.x1 <= x || s.x0 >= x + 1 || s.y1 <= y || s.y0 >= y + 1) continue;
        const double c = PixelCoverage(s, x, y);
        if (!(c > 0)) continue;
        const ProbeCounts probes = ProbeLightInPixel(scene, s, x, y);
        if (probes.blocked == 0) {
            if (c < 1) out.push_back({&s, float(c), false});  // wholly covered: g is constant
        } else if (!estimated) {
            out.push_back({&s, EstimateSeenCoverage(scene, s, x, y, c, probes, SeenCoverageGrid(samples), seed), true});
            estimated = true;
        }
    }
}

// The area light whose sight the pixel's estimate replaces (PartialCoverage::occluded), or -1.
static inline int LightSeenByEstimate(const std::vector<PartialCoverage>& partial) {
    for (const PartialCoverage& p : partial)
        if (p.occluded) return p.light->light;
    return -1;
}

// The starting value of a camera sample at film point (fx, fy) of a pixel with these partial coverages.
static inline Spectrum CoverageOffset(const std::vector<PartialCoverage>& partial, float fx, float fy) {
    Spectrum offset;
    for (const PartialCoverage& p : partial)
        offset += p.light->radiance *
                  (p.coverage - (!p.occluded && InsideScreenLight(*p.light, fx, fy) ? 1.0f : 0.0f));
    return offset;
}

}  // namespace sphrect::render
