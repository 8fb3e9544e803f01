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
//
// Pixel filters (render/pixel_filter.h): a pixel's camera samples land at film points drawn from the
// filter f around its centre, so g's integral is the light's share of f, C = integral of f over the
// image.  For a box of any width that is the area of the image in the box, exact; for the Gaussian and
// Blackman-Harris it is estimated, unbiased, from inside-tests at a jittered grid of film points drawn
// through the same inverse CDF as the camera samples (FilteredCoverage): a test costs a few products and
// no ray, so the grid is dense (kFilteredCoveragePointsPerSample) and C's noise far below the camera samples'.
// The control variate stays unbiased with an unbiased estimate of its mean.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "render/camera.h"
#include "render/camera_view.h"
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
// FilteredCoverage's inside-tests per camera sample: a test costs a few products and no ray.
constexpr int kFilteredCoveragePointsPerSample = 64;

static inline bool UsesLightCoverage(const RenderScene& scene, const CameraView& view, const RenderOptions& opt) {
    // (A light behind a transparent surface is seen filtered: the coverage estimate does not model it.)
    return opt.analytic_light_coverage && !scene.has_medium && !scene.has_volumes && !scene.has_transparency &&
           !view.screen_lights.empty();
}

// How far beyond its pixel a pixel's camera samples may land (the filter's support less the pixel).
static inline double FootprintMargin(const PixelFilter& filter) {
    return filter.IsUnitBox() ? 0.0 : std::max(0.0, PixelFilterRadius(filter.type, filter.width) - 0.5);
}

// The film box pixel (x, y)'s camera samples land in: the pixel itself for the 1-px box, else the
// filter's support around the pixel's centre.
struct FilmBox {
    double x0, y0, x1, y1;
};
static inline FilmBox PixelFootprint(const PixelFilter& filter, int x, int y) {
    if (filter.IsUnitBox()) return {double(x), double(y), x + 1.0, y + 1.0};
    const double r = PixelFilterRadius(filter.type, filter.width);
    return {x + 0.5 - r, y + 0.5 - r, x + 0.5 + r, y + 0.5 + r};
}

// The screen lights whose image may overlap the footprint of a pixel of the tile (indices into
// view.screen_lights).
static inline void ScreenLightsOverTile(const CameraView& view, const TileRect& tile, std::vector<int>& out) {
    out.clear();
    const double m = FootprintMargin(view.camera.filter);
    for (size_t i = 0; i < view.screen_lights.size(); ++i) {
        const ScreenLight& s = view.screen_lights[i];
        if (s.x1 > tile.x0 - m && s.x0 < tile.x1 + m && s.y1 > tile.y0 - m && s.y0 < tile.y1 + m) out.push_back(int(i));
    }
}

// The rays from the camera through film points (fx[k], fy[k]) inside s's image that reach the
// light, into rays[0..n); returns n.  Each tests whether something in front hides the light, by the
// camera ray's own rule (a surface before the light's distance, FinishCameraSample): a shadow ray's
// margin (ShadowRayLength) would miss a wall the light touches.
static inline int CameraRaysToScreenLight(const RenderScene& scene, const CameraView& view, const ScreenLight& s,
                                          const float* fx, const float* fy, int count, RTCRay* rays) {
    const AreaLight& light = scene.area_lights[s.light];
    int n = 0;
    for (int k = 0; k < count; ++k) {
        if (!InsideScreenLight(s, fx[k], fy[k])) continue;
        const Ray r = GenerateCameraRay<false>(view.camera, fx[k], fy[k], {});
        const float t = IntersectAreaLight(light, r.o, r.d, r.tmax);
        if (t < kInf && t > r.tmin) rays[n++] = MakeRTCRay(r.o, r.d, r.tmin, t, kRayCamera);
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

static inline ProbeCounts ProbeLightInPixel(const RenderScene& scene, const CameraView& view, const ScreenLight& s,
                                            int x, int y) {
    // Quantiles of the filter's distribution in x and in y: near the pixel's corners for the 1-px box; for
    // wider filters further out, so that an occluder in the support's outer ring, where a few camera
    // samples land, is found too.
    constexpr float kPixelProbes[3] = {0.05f, 0.5f, 0.95f}, kFilterProbes[3] = {0.01f, 0.5f, 0.99f};
    const PixelFilter& filter = view.camera.filter;
    const float* probes = filter.IsUnitBox() ? kPixelProbes : kFilterProbes;
    float fx[9], fy[9];
    for (int k = 0; k < 9; ++k)
        fx[k] = FilmCoordinate(filter, x, probes[k % 3]), fy[k] = FilmCoordinate(filter, y, probes[k / 3]);
    RTCRay rays[9];
    const int n = CameraRaysToScreenLight(scene, view, s, fx, fy, 9, rays);
    return {n, CountBlocked(rays, n)};
}

// The side of a jittered grid of about `per_sample` film points per camera sample of a pass of
// `samples`, at most kSeenCoverageMaxGrid^2 points.
static inline int CoverageGrid(int samples, int per_sample) {
    const int side = int(std::ceil(std::sqrt(double(per_sample) * samples)));
    return std::clamp(side, 1, kSeenCoverageMaxGrid);
}

// Film point `cell` of a jittered grid x grid over the filter's distribution around pixel (x, y).
static inline void FilmGridPoint(const PixelFilter& filter, int x, int y, int cell, int grid, PCG32& rng, float& fx,
                                 float& fy) {
    const float u = ((cell % grid) + rng.NextFloat()) / grid;
    const float v = ((cell / grid) + rng.NextFloat()) / grid;
    fx = FilmCoordinate(filter, x, u);
    fy = FilmCoordinate(filter, y, v);
}

// The share of pixel (x, y)'s filter that s's image covers, given the share `box` of its footprint
// (PixelFootprint): a box filter's is that share, exact; the others' an unbiased estimate from
// inside-tests at a jittered grid of film points drawn as the camera samples are.  (Where the estimate
// is 0 or 1 the image's edge still crosses the footprint: g is not constant there, so the caller keeps
// the control variate; only the exact box share decides that.)
static inline double FilteredCoverage(const ScreenLight& s, const PixelFilter& filter, int x, int y, double box,
                                      int grid, uint64_t seed) {
    if (filter.type == PixelFilterType::Box || box == 0 || box == 1) return box;
    PCG32 rng(seed);
    const int total = grid * grid;
    int inside = 0;
    for (int cell = 0; cell < total; ++cell) {
        float fx, fy;
        FilmGridPoint(filter, x, y, cell, grid, rng, fx, fy);
        inside += InsideScreenLight(s, fx, fy);
    }
    return double(inside) / total;
}

// An unbiased estimate of the share of pixel (x, y) where the camera sees light s unoccluded, from
// a jittered grid of film points and their rays to the light.  `box` is the exact share of the
// pixel's footprint the image covers (the filter's share c for a box filter).  Where the probes find
// the light mostly seen and c is exact, c less the grid's share of blocked points, so only the occluder's edge
// is left to the grid; where mostly hidden, the grid's share of points that see it, which is never
// negative.
static inline float EstimateSeenCoverage(const RenderScene& scene, const CameraView& view, const ScreenLight& s, int x,
                                         int y, double box, ProbeCounts probes, int grid, uint64_t seed) {
    constexpr int kBatch = 64;
    PCG32 rng(seed);
    const int total = grid * grid;
    int reached = 0, blocked = 0;
    for (int first = 0; first < total; first += kBatch) {
        const int count = std::min(kBatch, total - first);
        float fx[kBatch], fy[kBatch];
        for (int k = 0; k < count; ++k) FilmGridPoint(view.camera.filter, x, y, first + k, grid, rng, fx[k], fy[k]);
        RTCRay rays[kBatch];
        const int n = CameraRaysToScreenLight(scene, view, s, fx, fy, count, rays);
        reached += n;
        blocked += CountBlocked(rays, n);
    }
    // (Only a box filter's c is exact: another filter's is an estimate of its own, and the grid's share of
    // points that reach the light, from the same points as the blocked ones, is the better one then.)
    const bool exact_c = view.camera.filter.type == PixelFilterType::Box;
    if (exact_c && 2 * probes.blocked <= probes.reached) return float(box - double(blocked) / total);
    return float(reached - blocked) / total;
}

// The lights of `candidates` that partly cover pixel (x, y), with their coverage.  At most one of
// them, the first found hidden in part, gets the estimate of its seen share (a camera sample has
// one PrimaryHit::light_seen_by_estimate); others hidden in part keep the sampled estimate.
// `seed` draws the estimates' grids (one per pixel and pass of `samples` camera samples).
static inline void PartialCoverages(const RenderScene& scene, const CameraView& view,
                                    const std::vector<int>& candidates, int x, int y, int samples, uint64_t seed,
                                    std::vector<PartialCoverage>& out) {
    out.clear();
    bool estimated = false;
    const PixelFilter& filter = view.camera.filter;
    const FilmBox b = PixelFootprint(filter, x, y);
    for (int i : candidates) {
        const ScreenLight& s = view.screen_lights[i];
        if (s.x1 <= b.x0 || s.x0 >= b.x1 || s.y1 <= b.y0 || s.y0 >= b.y1) continue;
        // The exact share of the footprint decides where g is constant (0 or 1); c is the filter's share,
        // estimated only where it is used (EstimateSeenCoverage takes the box share, which is c for a box filter).
        const double box = filter.IsUnitBox() ? PixelCoverage(s, x, y) : BoxCoverage(s, b.x0, b.y0, b.x1, b.y1);
        if (!(box > 0)) continue;
        auto filtered_coverage = [&] {
            return FilteredCoverage(s, filter, x, y, box, CoverageGrid(samples, kFilteredCoveragePointsPerSample),
                                    MixBits(seed ^ (uint64_t(i + 1) * 0x9e3779b97f4a7c15ull)));
        };
        const ProbeCounts probes = ProbeLightInPixel(scene, view, s, x, y);
        if (probes.blocked == 0) {
            if (box < 1) out.push_back({&s, float(filtered_coverage()), false});  // wholly covered: g is constant
        } else if (!estimated) {
            out.push_back({&s,
                           EstimateSeenCoverage(scene, view, s, x, y, box, probes,
                                                CoverageGrid(samples, kSeenCoverageRaysPerSample), seed),
                           true});
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
        offset += p.light->radiance * (p.coverage - (!p.occluded && InsideScreenLight(*p.light, fx, fy) ? 1.0f : 0.0f));
    return offset;
}

}  // namespace sphrect::render
