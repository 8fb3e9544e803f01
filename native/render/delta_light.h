// Point, spot and sun lights, evaluated once per shading or scattering point with a shadow ray.
// Without a radius (point, spot) or an angle (sun) they are delta lights (no MIS possible).  With
// one they are soft, as Cycles 3.4 evaluates them (kernel/light/light.h, scene/light.cpp):
//  - a point or spot light of radius r is a disc of radius r centred on the light and facing the
//    shading point, of uniform radiance I / (pi r^2) (I the intensity; a spot's times its falloff
//    towards the point), seen by BSDF rays and, unless hidden, by the camera;
//  - a sun of angular diameter 2 alpha is the cone of directions within alpha of it, of radiance
//    E / (pi tan^2(alpha) cos^3(theta)) at angle theta from its direction (Cycles samples a disc of
//    radius tan(alpha) one unit away; E its irradiance at normal incidence).
// Both are the cone they subtend (the facing disc subtends exactly a cone), sampled uniformly by
// solid angle (core/cone.h), with the pdf the MIS weights of BSDF rays need.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/cone.h"
#include "light_bounds.h"
#include "ray_visibility.h"
#include "sampling_util.h"

namespace sphrect::render {

enum class DeltaKind { Point, Spot, Sun };

struct DeltaLight {
    DeltaKind kind = DeltaKind::Point;
    Vec3f position;                              // Point, Spot
    Vec3f axis;                                  // Spot: unit cone axis;  Sun: unit direction towards the sun
    Spectrum power;                              // Point/Spot: intensity I (W/sr); Sun: irradiance E (W/m^2)
    float cos_half_angle = -1, spot_smooth = 0;  // Spot
    float radius = 0;                            // Point, Spot: the disc's radius; 0: a delta light
    float sun_one_minus_cos = 0;                 // Sun: 1 - cos(angle / 2); 0: a delta light
    bool visible = true;                         // soft: seen by camera rays (Blender's Visibility > Camera)
    LightVisibility vis;                         // what it lights, its shadows, MIS (ray_visibility.h)
};

inline bool IsSoft(const DeltaLight& l) { return l.kind == DeltaKind::Sun ? l.sun_one_minus_cos > 0 : l.radius > 0; }

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
    Spectrum li;     // incident radiance times the delta's solid angle (irradiance at normal incidence); soft: Le / pdf
    float pdf = 0;   // soft: the direction's solid-angle pdf; 0 for a delta light
};

// The cone a soft light subtends at p: its frame (z towards the light) and 1 - cos of its half-angle;
// dist: to the disc's centre (kInf for the sun).  Invalid (one_minus_cos 0) at a point light's centre.
struct SoftLightCone {
    Frame frame;
    float one_minus_cos = 0, dist = 0;
};

inline SoftLightCone SoftConeAt(const DeltaLight& l, const Vec3f& p) {
    if (l.kind == DeltaKind::Sun) return {Frame::FromZ(l.axis), l.sun_one_minus_cos, kInf};
    const Vec3f d = l.position - p;
    const float dist = Length(d);
    if (!(dist > 0)) return {};
    return {Frame::FromZ(d / dist), OneMinusCosOfDisc(l.radius, dist), dist};
}

// Radiance a soft light sends along -w, w unit and inside the cone at angle theta from its
// axis (cos_theta), and the distance along w to the light (the facing disc's plane).
inline Spectrum SoftLightRadiance(const DeltaLight& l, const SoftLightCone& cone, const Vec3f& w, float cos_theta) {
    if (l.kind == DeltaKind::Sun) {
        const float x = cone.one_minus_cos, c = 1 - x;  // tan^2 = (1 - c^2) / c^2 = x (2 - x) / c^2
        return l.power * (c * c / (kPi * x * (2 - x) * cos_theta * cos_theta * cos_theta));
    }
    Spectrum le = l.power * (1 / (kPi * l.radius * l.radius));
    if (l.kind == DeltaKind::Spot) le = le * SpotAttenuation(l, -w);
    return le;
}

// A direction towards soft light l from p, uniform in the cone it subtends (u the pattern's point): Le / pdf.
inline DeltaIllumination SampleSoftLight(const DeltaLight& l, const Vec3f& p, Point2<float> u) {
    DeltaIllumination r;
    const SoftLightCone cone = SoftConeAt(l, p);
    if (!(cone.one_minus_cos > 0)) return r;
    const Vec3f local = SampleUniformCone(u, cone.one_minus_cos);
    if (!(local.z > 0)) return r;
    r.wi = cone.frame.FromLocal(local);
    r.dist = cone.dist / local.z;
    r.pdf = UniformConePDF(cone.one_minus_cos);
    r.li = SoftLightRadiance(l, cone, r.wi, local.z) * (1 / r.pdf);
    if (!std::isfinite(r.pdf) || !IsFinite(r.li)) return {};
    return r;
}

// Where the ray (o, d), d unit, reaches soft light l (t; kInf for the sun), with the radiance it
// brings and the cone's pdf of d; hit false where it misses.
struct SoftLightCrossing {
    bool hit = false;
    float t = 0;
    Spectrum le;
    float pdf = 0;
};

inline SoftLightCrossing CrossSoftLight(const DeltaLight& l, const Vec3f& o, const Vec3f& d) {
    const SoftLightCone cone = SoftConeAt(l, o);
    if (!(cone.one_minus_cos > 0) || !(OneMinusCosBetween(d, cone.frame.n) <= cone.one_minus_cos)) return {};
    const float cos_theta = Dot(d, cone.frame.n);
    if (!(cos_theta > 0)) return {};
    const Spectrum le = SoftLightRadiance(l, cone, d, cos_theta);
    if (IsBlack(le) || !IsFinite(le)) return {};
    return {true, cone.dist / cos_theta, le, UniformConePDF(cone.one_minus_cos)};
}

// What a point, spot or sun light sends to p: a delta light's direction, or a soft light's sampled
// one (SampleSoftLight, with the point u).
inline DeltaIllumination IlluminateFromDelta(const DeltaLight& l, const Vec3f& p, Point2<float> u) {
    if (IsSoft(l)) return SampleSoftLight(l, p, u);
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
    b.lo = l.position - Vec3f(l.radius, l.radius, l.radius);  // a soft light's disc lies within its radius
    b.hi = l.position + Vec3f(l.radius, l.radius, l.radius);
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
