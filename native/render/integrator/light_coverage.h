// The control variate of the lights the camera sees (render/screen_lights.h): a camera sample at
// film point x of a pixel that a light's image partly covers starts from
//     sum over those lights of L_j (coverage_j - [x inside image j]),
// so that, with what it then sees, its expectation is the pixel's and its variance is that of
// f - g.  Pixels wholly inside or outside an image need nothing (g is constant there), nor do pixels
// where something in front hides part of the light (SeenUnoccludedInPixel).  Off under
// depth of field (no screen lights then) and in a medium (the light is seen attenuated, so g would
// not cancel), and when RenderOptions::analytic_light_coverage is false.
#pragma once

#include <vector>

#include "render/camera.h"
#include "render/embree_rays.h"
#include "render/kernel.h"
#include "render/screen_lights.h"

namespace sphrect::render {

struct PartialCoverage {
    const ScreenLight* light;
    float coverage;  // in (0, 1]
};

static inline bool UsesLightCoverage(const RenderScene& scene, const RenderOptions& opt) {
    return opt.analytic_light_coverage && !scene.has_medium && !scene.screen_lights.empty();
}

// The screen lights whose image may overlap the tile (indices into scene.screen_lights).
static inline void ScreenLightsOverTile(const RenderScene& scene, const TileRect& tile, std::vector<int>& out) {
    out.clear();
    for (size_t i = 0; i < scene.screen_lights.size(); ++i) {
        const ScreenLight& s = scene.screen_lights[i];
        if (s.x1 > tile.x0 && s.x0 < tile.x1 && s.y1 > tile.y0 && s.y0 < tile.y1) out.push_back(int(i));
    }
}

// Whether the camera sees light s unoccluded through the probe points of pixel (x, y) inside its
// image (a 3 x 3 grid).  Where something in front hides part of the light, g does not cancel f: the
// offset would add the image edge's noise to the occluder's, so such a pixel keeps the sampled
// estimate.  The choice depends only on the scene and the pixel, so the image is unbiased either way.
static inline bool SeenUnoccludedInPixel(const RenderScene& scene, const ScreenLight& s, int x, int y) {
    constexpr float kProbes[3] = {0.05f, 0.5f, 0.95f};
    const AreaLight& light = scene.area_lights[s.light];
    RTCRay rays[9];
    int n = 0;
    for (float py : kProbes)
        for (float px : kProbes) {
            const float fx = x + px, fy = y + py;
            if (!InsideScreenLight(s, fx, fy)) continue;
            const Ray r = GenerateCameraRay<false>(scene.camera, fx, fy, {});
            const float t = IntersectAreaLight(light, r.o, r.d, r.tmax);
            if (t < kInf && t > r.tmin) rays[n++] = MakeRTCRay(r.o, r.d, r.tmin, ShadowRayLength(t));
        }
    OccludeShadowRays(scene.rtc_scene, rays, size_t(n), sizeof(RTCRay));
    for (int k = 0; k < n; ++k)
        if (rays[k].tfar < 0) return false;  // blocked (Embree sets tfar to -inf)
    return true;
}

// The lights of `candidates` that partly cover pixel (x, y), unoccluded, with their coverage.
static inline void PartialCoverages(const RenderScene& scene, const std::vector<int>& candidates, int x, int y,
                                    std::vector<PartialCoverage>& out) {
    out.clear();
    for (int i : candidates) {
        const ScreenLight& s = scene.screen_lights[i];
        if (s.x1 <= x || s.x0 >= x + 1 || s.y1 <= y || s.y0 >= y + 1) continue;
        const double c = PixelCoverage(s, x, y);
        if (c > 0 && c < 1 && SeenUnoccludedInPixel(scene, s, x, y)) out.push_back({&s, float(c)});
    }
}

// The starting value of a camera sample at film point (fx, fy) of a pixel with these partial coverages.
static inline Spectrum CoverageOffset(const std::vector<PartialCoverage>& partial, float fx, float fy) {
    Spectrum offset;
    for (const PartialCoverage& p : partial)
        offset += p.light->radiance * (p.coverage - (InsideScreenLight(*p.light, fx, fy) ? 1.0f : 0.0f));
    return offset;
}

}  // namespace sphrect::render
