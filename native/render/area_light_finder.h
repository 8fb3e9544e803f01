// Finding the analytic area lights (rectangles, ellipses) a camera or BSDF ray crosses.
//
// Lights do not occlude: a ray collects every light it crosses, not only the first, so they are
// not part of the scene's Embree geometry.  Few lights are tested in turn (a test is cheap);
// above kLinearLightSearchMax they are one Embree user geometry in a scene of their own, whose
// BVH visits only the lights whose bounds the ray meets.  Its intersect callback records each
// crossing in the query's buffer and never reports a hit, so the traversal goes on to the end of
// the ray.  The crossings are then sorted by light index: both paths give the same list in the
// same order (the same float sums, so the same image), whichever is taken.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "area_light.h"

namespace sphrect::render {

// Up to this many analytic lights, a ray tests each in turn: below it the BVH costs more than it saves
// (bench_many_lights; docs/architecture.md, measured choices).
constexpr size_t kLinearLightSearchMax = 8;

struct LightCrossing {
    int light;  // index into the scene's area lights
    float t;    // distance along the ray
};

// Which lights a query collects: those seen by camera rays (AreaLight::visible), or all.
enum class LightsSought { VisibleToCamera, All };

// The lights [0, n) of `lights` crossed by (o, d) at tmin <= t < tmax, t > 0, by the same test
// (IntersectAreaLight) on both paths.
inline bool CrossesLight(const AreaLight& l, LightsSought sought, const Vec3f& o, const Vec3f& d, float tmin,
                         float tmax, float& t) {
    if (sought == LightsSought::VisibleToCamera && !l.visible) return false;
    t = IntersectAreaLight(l, o, d, tmax);
    return !std::isinf(t) && t >= tmin;
}

class AreaLightFinder {
  public:
    // Crossings kept per BVH query; a ray crossing more (stacked coincident lights) is answered
    // by the linear test instead, so nothing is dropped.
    static constexpr int kMaxCrossings = 32;

    AreaLightFinder() = default;
    ~AreaLightFinder() { Release(); }
    AreaLightFinder(const AreaLightFinder&) = delete;
    AreaLightFinder& operator=(const AreaLightFinder&) = delete;

    // Lights [0, n) of `lights` (which must outlive the finder and not move); a BVH over them
    // when n > kLinearLightSearchMax.
    void Build(RTCDevice device, const std::vector<AreaLight>& lights, size_t n);
    void Release();  // the BVH (before its Embree device goes)
    bool uses_bvh() const { return rtc_scene_ != nullptr; }
    size_t size() const { return n_; }

    // Calls f(light, t) for every crossing, in increasing light index.
    template <class F>
    void ForEachCrossing(const Vec3f& o, const Vec3f& d, float tmin, float tmax, LightsSought sought, F&& f) const {
        if (rtc_scene_) {
            LightCrossing found[kMaxCrossings];
            const int n = QueryBVH(o, d, tmin, tmax, sought, found);
            if (n >= 0) {
                std::sort(found, found + n,
                          [](const LightCrossing& a, const LightCrossing& b) { return a.light < b.light; });
                for (int k = 0; k < n; ++k) f(found[k].light, found[k].t);
                return;
            }
        }
        for (size_t i = 0; i < n_; ++i) {
            float t;
            if (CrossesLight((*lights_)[i], sought, o, d, tmin, tmax, t)) f(int(i), t);
        }
    }

  private:
    // The crossings into `found` (unsorted) and their count, or -1 when there are more than
    // kMaxCrossings.
    int QueryBVH(const Vec3f& o, const Vec3f& d, float tmin, float tmax, LightsSought sought,
                 LightCrossing* found) const;

    const std::vector<AreaLight>* lights_ = nullptr;
    size_t n_ = 0;
    RTCScene rtc_scene_ = nullptr;
};

}  // namespace sphrect::render
