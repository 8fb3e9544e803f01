// Delta lights: point, spot and sun, evaluated once per shading or scattering point with a
// shadow ray (no MIS possible).
#pragma once

#include <algorithm>
#include <cmath>

#include "light_bounds.h"
#include "sampling_util.h"

namespace sphrect::render {

enum class DeltaKind { Point, Spot, Sun };

struct DeltaLight {
    DeltaKind kind = DeltaKind::Point;
    Vec3f position;                              // Point, Spot
    Vec3f axis;                                  // Spot: unit cone axis;  Sun: unit direction towards the sun
    Spectrum power;                              // Point/Spot: intensity I (W/sr); Sun: irradiance E (W/m^2)
    float cos_half_angle = -1, spot_smooth = 0;  // Spot
};

inline float SmoothStep(float e0, float e1, float x) {
    const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
    return t * t * (3 - 2 * t);
}

// Cycles 3.4's spot falloff: cos(angle to the axis), faded by smoothstep over the outer
// (1 - cos(size / 2)) * blend of the cone's cosine range, zero outside the cone.
inline float SpotAttenuation(const DeltaLight& l, const Vec3f& dir_from_light) {
    const float c = Dot(dir_from_light, l.axis);
    if (c <= l.cos_half_angle) return 0;
    const float t = c - l.cos_half_angle;
    float a = c;
    if (l.spot_smooth > 0 && t < l.spot_smooth) a *= SmoothStep(0, l.spot_smooth, t);
    return a;
}

struct DeltaIllumination {
    Vec3f wi;        // unit, towards the light
    float dist = 0;  // kInf for the sun
    Spectrum li;     // incident radiance times the delta's solid angle (irradiance at normal incidence)
};

inline DeltaIllumination IlluminateFromDelta(const DeltaLight& l, const Vec3f& p) {
    DeltaIllumination r;
    if (l.kind == DeltaKind::Sun) {
        r.wi = l.axis;
        r.dist = kInf;
        r.li = l.power;
        return r;
    }
    const Vec3f d = l.position - p;
    const float d2 = Dot(d, d);
    r.dist = std::sqrt(d2);
    if (!(r.dist > 0)) return r;
    r.wi = d / r.dist;
    float att = 1 / d2;
    if (l.kind == DeltaKind::Spot) att *= SpotAttenuation(l, -r.wi);
    r.li = l.power * att;
    return r;
}

// The light tree's bounds of a point or spot light; a sun has no finite bounds and is not a tree emitter
// (returns false).
inline bool DeltaLightBounds(const DeltaLight& l, LightBounds* out) {
    if (l.kind == DeltaKind::Sun) return false;
    LightBounds b;
    b.lo = b.hi = l.position;
    b.power = Luminance(l.power);
    if (l.kind == DeltaKind::Spot) {
        b.axis = l.axis;
        b.cos_theta_o = std::clamp(l.cos_half_angle, -1.0f, 1.0f);  // SpotAttenuation: zero outside
        b.cos_theta_e = 1;
    } else {
        b.cos_theta_o = -1;  // the whole sphere
        b.cos_theta_e = 0;
    }
    *out = b;
    return true;
}

}  // namespace sphrect::render
