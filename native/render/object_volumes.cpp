// Object volumes (object_volumes.h): their boundaries in Embree, and the walk of a ray through them.
#include "object_volumes.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "embree_rays.h"
#include "medium.h"
#include "scene_checks.h"

namespace sphrect::render {

namespace {

// The context of a walk: where the filter records the crossings it sees.
struct CrossingRecorder {
    RTCIntersectContext rtc;  // first: the filter casts Embree's context pointer back to this
    VolumeCrossing* out;      // kMaxVolumeCrossings of room
    int count = 0;
};

// Records a candidate hit and rejects it, so that one traversal visits every crossing.  A crossing on a shared edge
// may be reported by both triangles: harmless, entering and leaving are idempotent (ObjectVolumes::Crossings).
void RecordCrossing(const RTCFilterFunctionNArguments* args) {
    auto* rec = reinterpret_cast<CrossingRecorder*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        args->valid[i] = 0;
        if (rec->count == kMaxVolumeCrossings) continue;
        const Vec3f ng(RTCHitN_Ng_x(args->hit, args->N, i), RTCHitN_Ng_y(args->hit, args->N, i),
                       RTCHitN_Ng_z(args->hit, args->N, i));
        const Vec3f d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                      RTCRayN_dir_z(args->ray, args->N, i));
        // Embree's Ng: (v1 - v0) x (v2 - v0), outwards for outward winding.
        rec->out[rec->count++] = {RTCRayN_tfar(args->ray, args->N, i), RTCHitN_geomID(args->hit, args->N, i),
                                  Dot(ng, d) < 0};
    }
}

}  // namespace

Spectrum VolumeSegments::TransmittanceTo(float t) const {
    Spectrum tau;
    for (int i = 0; i < count && segment[i].t0 < t; ++i)
        tau += OpticalDepth(segment[i].coefficients.sigma_t, std::min(segment[i].t1, t) - segment[i].t0);
    return TransmittanceOfDepth(tau);
}

ObjectVolumes::~ObjectVolumes() {
    if (rtc_scene_) rtcReleaseScene(rtc_scene_);
}

void ObjectVolumes::Add(RTCDevice device, const std::string& name, const float* vertices, size_t nv,
                        const int32_t* triangles, size_t nt, const Spectrum& sigma_s, const Spectrum& sigma_a,
                        float g) {
    const std::string who = "volume '" + name + "'";
    if (coefficients_.size() == size_t(kMaxObjectVolumes))
        Fail(who + ": a scene holds at most " + std::to_string(kMaxObjectVolumes) + " volumes");
    CheckColor(who + " sigma_s", sigma_s);
    CheckColor(who + " sigma_a", sigma_a);
    if (!(g > -1 && g < 1)) Fail(who + ": anisotropy g must be in (-1, 1)");
    if (nt == 0) Fail(who + " has no triangles");
    CheckTriangleMesh(who, vertices, nv, triangles, nt);
    if (!rtc_scene_) {
        rtc_scene_ = rtcNewScene(device);
        rtcSetSceneFlags(rtc_scene_, RTC_SCENE_FLAG_ROBUST);
    }
    RTCGeometry geom = NewTriangleGeometry(device, who, vertices, nv, triangles, nt);
    rtcSetGeometryIntersectFilterFunction(geom, &RecordCrossing);
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(rtc_scene_, geom);
    rtcReleaseGeometry(geom);
    if (id != coefficients_.size()) throw std::logic_error("unexpected Embree geometry id");
    coefficients_.push_back({sigma_s, sigma_s + sigma_a, g});
    names_.push_back(name);
}

void ObjectVolumes::Commit(RTCDevice) {
    if (!rtc_scene_) return;
    rtcCommitScene(rtc_scene_);
    RTCBounds b;
    rtcGetSceneBounds(rtc_scene_, &b);
    // Widened a little: a ray grazing the box must still walk (the test below is in float).
    const Vec3f lo(b.lower_x, b.lower_y, b.lower_z), hi(b.upper_x, b.upper_y, b.upper_z);
    const Vec3f pad =
        (hi - lo) * 1e-4f + Vec3f(1e-6f, 1e-6f, 1e-6f) * (1 + std::max(MaxAbsComponent(lo), MaxAbsComponent(hi)));
    bounds_lo_ = lo - pad;
    bounds_hi_ = hi + pad;
}

bool ObjectVolumes::MissesBounds(const Vec3f& o, const Vec3f& d) const {
    float t0 = 0, t1 = kInf;
    const float oc[3] = {o.x, o.y, o.z}, dc[3] = {d.x, d.y, d.z};
    const float lo[3] = {bounds_lo_.x, bounds_lo_.y, bounds_lo_.z}, hi[3] = {bounds_hi_.x, bounds_hi_.y, bounds_hi_.z};
    for (int a = 0; a < 3; ++a) {
        if (dc[a] == 0) {
            if (oc[a] < lo[a] || oc[a] > hi[a]) return true;
            continue;
        }
        const float inv = 1 / dc[a];
        float ta = (lo[a] - oc[a]) * inv, tb = (hi[a] - oc[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return true;
    }
    return false;
}

int ObjectVolumes::Crossings(const Vec3f& o, const Vec3f& d, VolumeCrossing* out, uint64_t& inside) const {
    CrossingRecorder rec;
    rtcInitIntersectContext(&rec.rtc);
    rec.out = out;
    RTCRayHit rh = MakeRTCRayHit(o, d, 0, kInf);
    rtcIntersect1(rtc_scene_, &rec.rtc, &rh);
    const int n = rec.count;
    std::sort(out, out + n, [](const VolumeCrossing& a, const VolumeCrossing& b) { return a.t < b.t; });
    // A volume whose first crossing leaves it holds the origin.
    uint64_t met = 0;
    inside = 0;
    for (int i = 0; i < n; ++i) {
        const uint64_t bit = uint64_t(1) << out[i].volume;
        if (met & bit) continue;
        met |= bit;
        if (!out[i].entering) inside |= bit;
    }
    return n;
}

VolumeCoefficients ObjectVolumes::Sum(uint64_t set) const {
    VolumeCoefficients sum;
    float g_weight = 0;
    for (uint64_t s = set; s; s &= s - 1) {
        const VolumeCoefficients& c = coefficients_[size_t(__builtin_ctzll(s))];
        sum.sigma_s += c.sigma_s;
        sum.sigma_t += c.sigma_t;
        const float w = Average(c.sigma_s);
        sum.g += w * c.g;
        g_weight += w;
    }
    sum.g = g_weight > 0 ? sum.g / g_weight : 0;
    return sum;
}

Spectrum ObjectVolumes::Transmittance(const Vec3f& o, const Vec3f& d, float tmax) const {
    if (!rtc_scene_ || MissesBounds(o, d)) return {1, 1, 1};
    VolumeCrossing crossings[kMaxVolumeCrossings];
    uint64_t inside;
    const int n = Crossings(o, d, crossings, inside);
    // Optical depth: each volume's time inside, times its sigma_t.
    Spectrum tau;
    float t_prev = 0;
    uint64_t set = inside;
    auto add = [&](float t_next) {
        const float len = std::min(t_next, tmax) - t_prev;
        if (!(len > 0)) return;
        for (uint64_t s = set; s; s &= s - 1)
            tau += OpticalDepth(coefficients_[size_t(__builtin_ctzll(s))].sigma_t, len);
    };
    for (int i = 0; i < n && crossings[i].t < tmax; ++i) {
        add(crossings[i].t);
        t_prev = std::max(t_prev, crossings[i].t);
        const uint64_t bit = uint64_t(1) << crossings[i].volume;
        set = crossings[i].entering ? set | bit : set & ~bit;
    }
    add(tmax);
    return TransmittanceOfDepth(tau);
}

void ObjectVolumes::Segments(const Vec3f& o, const Vec3f& d, VolumeSegments& out, float t_begin) const {
    out.count = 0;
    out.truncated = false;
    const Vec3f start = t_begin > 0 ? o + d * t_begin : o;
    if (!rtc_scene_ || MissesBounds(start, d)) {
        out.segment[out.count++] = {0, kInf, {}};
        return;
    }
    VolumeCrossing crossings[kMaxVolumeCrossings];
    uint64_t set;
    const int n = Crossings(start, d, crossings, set);
    if (t_begin > 0) {
        for (int i = 0; i < n; ++i) crossings[i].t += t_begin;
        out.segment[out.count++] = {0, t_begin, {}};
    }
    float t_prev = std::max(t_begin, 0.0f);
    for (int i = 0; i < n; ++i) {
        const uint64_t bit = uint64_t(1) << crossings[i].volume;
        const uint64_t next = crossings[i].entering ? set | bit : set & ~bit;
        if (next == set) continue;  // a shared edge's second report
        if (out.count == kMaxVolumeSegments - 1) {
            out.truncated = true;
            break;
        }
        if (crossings[i].t > t_prev) {
            out.segment[out.count++] = {t_prev, crossings[i].t, Sum(set)};
            t_prev = crossings[i].t;
        }
        set = next;
    }
    out.segment[out.count++] = {t_prev, kInf, Sum(set)};
}

}  // namespace sphrect::render
