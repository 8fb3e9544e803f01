#include "area_light_finder.h"

#include <stdexcept>

#include "embree_rays.h"

namespace sphrect::render {
namespace {

// One BVH query: Embree's context first (the callbacks receive a pointer to it), then the ray as
// the linear test sees it and the buffer the callback fills.
struct CrossingQuery {
    RTCIntersectContext rtc;
    const std::vector<AreaLight>* lights;
    Vec3f o, d;
    float tmin, tmax;
    LightsSought sought;
    LightCrossing* found;
    int count;  // > kMaxCrossings: overflowed
};

void Extend(RTCBounds& b, const Vec3f& p) {
    b.lower_x = std::min(b.lower_x, p.x), b.lower_y = std::min(b.lower_y, p.y), b.lower_z = std::min(b.lower_z, p.z);
    b.upper_x = std::max(b.upper_x, p.x), b.upper_y = std::max(b.upper_y, p.y), b.upper_z = std::max(b.upper_z, p.z);
}

// The light's box, padded so that the traversal's float slab tests never cull a crossing the
// exact test finds (an axis-aligned light's box is flat: without padding a ray could slip past it).
void EmbreeBoundsOfLight(const RTCBoundsFunctionArguments* args) {
    const auto& lights = *static_cast<const std::vector<AreaLight>*>(args->geometryUserPtr);
    const AreaLight& l = lights[args->primID];
    RTCBounds b{kInf, kInf, kInf, 0, -kInf, -kInf, -kInf, 0};
    if (l.shape == AreaShape::Ellipse) {
        // Half-extent along axis k of {c + cos(a) ax + sin(a) ay}: sqrt(ax_k^2 + ay_k^2).
        const Vec3f h(std::sqrt(l.ax.x * l.ax.x + l.ay.x * l.ay.x), std::sqrt(l.ax.y * l.ax.y + l.ay.y * l.ay.y),
                      std::sqrt(l.ax.z * l.ax.z + l.ay.z * l.ay.z));
        Extend(b, l.center - h);
        Extend(b, l.center + h);
    } else if (l.shape == AreaShape::Rectangle) {
        const RectLight<float>& r = l.frame.light;
        for (const Vec3f& p : {r.corner, r.corner + r.ex, r.corner + r.ey, r.corner + r.ex + r.ey}) Extend(b, p);
    } else {
        for (const Vec3f& p : {l.v0, l.v0 + l.e1, l.v0 + l.e2}) Extend(b, p);
    }
    const float extent = std::max({b.upper_x - b.lower_x, b.upper_y - b.lower_y, b.upper_z - b.lower_z});
    const float magnitude = std::max({std::abs(b.lower_x), std::abs(b.lower_y), std::abs(b.lower_z),
                                      std::abs(b.upper_x), std::abs(b.upper_y), std::abs(b.upper_z)});
    const float pad = 1e-5f * (1 + extent + magnitude);
    b.lower_x -= pad, b.lower_y -= pad, b.lower_z -= pad;
    b.upper_x += pad, b.upper_y += pad, b.upper_z += pad;
    *args->bounds_o = b;
}

// Records the crossing, reports no hit: the ray's tfar stays, so every light on it is visited.
void RecordCrossing(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    auto& q = *reinterpret_cast<CrossingQuery*>(args->context);
    float t;
    if (!CrossesLight((*q.lights)[args->primID], q.sought, q.o, q.d, q.tmin, q.tmax, t)) return;
    if (q.count < AreaLightFinder::kMaxCrossings) q.found[q.count] = {int(args->primID), t};
    ++q.count;
}

void NeverOccludes(const RTCOccludedFunctionNArguments*) {}

}  // namespace

void AreaLightFinder::Release() {
    if (rtc_scene_) rtcReleaseScene(rtc_scene_);
    rtc_scene_ = nullptr;
}

void AreaLightFinder::Build(RTCDevice device, const std::vector<AreaLight>& lights, size_t n) {
    Release();
    lights_ = &lights;
    n_ = n;
    if (n <= kLinearLightSearchMax) return;
    rtc_scene_ = rtcNewScene(device);
    rtcSetSceneBuildQuality(rtc_scene_, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, unsigned(n));
    void* user = const_cast<std::vector<AreaLight>*>(&lights);
    rtcSetGeometryUserData(g, user);
    rtcSetGeometryBoundsFunction(g, EmbreeBoundsOfLight, user);
    rtcSetGeometryIntersectFunction(g, RecordCrossing);
    rtcSetGeometryOccludedFunction(g, NeverOccludes);
    rtcCommitGeometry(g);
    rtcAttachGeometry(rtc_scene_, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(rtc_scene_);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE)
        throw std::runtime_error("Embree: building the area lights' BVH failed");
}

int AreaLightFinder::QueryBVH(const Vec3f& o, const Vec3f& d, float tmin, float tmax, LightsSought sought,
                              LightCrossing* found) const {
    CrossingQuery q{{}, lights_, o, d, tmin, tmax, sought, found, 0};
    rtcInitIntersectContext(&q.rtc);
    // tnear 0: the callback applies tmin itself, exactly as the linear test does.
    RTCRayHit rh = MakeRTCRayHit(o, d, 0, tmax);
    rtcIntersect1(rtc_scene_, &q.rtc, &rh);
    return q.count <= kMaxCrossings ? q.count : -1;
}

}  // namespace sphrect::render
