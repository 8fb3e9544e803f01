// Area lights: rectangles and ellipses (discs), sampled and intersected analytically.
// Rectangles are sampled with the chosen technique (core/technique.h, through
// integrator/light_sampling_at.h); ellipses uniformly by area, converted to solid angle.
#pragma once

#include <cmath>

#include "core/light_sample.h"
#include "core/rect_light.h"
#include "sampling_util.h"

namespace sphrect::render {

enum class AreaShape { Rectangle, Ellipse };

struct AreaLight {
    AreaShape shape = AreaShape::Rectangle;
    // Rectangle: the light (frame.light: corner, edges ex, ey) with what the samplers' setups
    // need of it, computed once per light.  Ellipses leave it invalid.
    RectLightFrame<float> frame;
    Vec3f center;           // centre
    Vec3f ax, ay;           // Ellipse: semi-axes
    Vec3f n;                // unit normal, cross(ex, ey) direction: the emitting side
    Vec3f inv_x, inv_y;     // ex / |ex|^2, ey / |ey|^2 (resp. the ellipse's semi-axes): plane coordinates
    Spectrum radiance;
    float area = 0;
    bool two_sided = false;
    bool visible = true;    // seen by camera rays
};

// What both shapes set alike: the plane coordinates along their axes a, b (a rectangle's edges,
// an ellipse's semi-axes) and the emission.
inline void SetAxesAndEmission(AreaLight& l, const Vec3f& a, const Vec3f& b, const Spectrum& radiance, bool two_sided,
                               bool visible) {
    l.inv_x = a / Dot(a, a);
    l.inv_y = b / Dot(b, b);
    l.radiance = radiance;
    l.two_sided = two_sided;
    l.visible = visible;
}

inline AreaLight MakeRectAreaLight(const Vec3f& corner, const Vec3f& ex, const Vec3f& ey, const Spectrum& radiance,
                                   bool two_sided, bool visible) {
    AreaLight l;
    l.shape = AreaShape::Rectangle;
    l.frame = MakeRectLightFrame(RectLight<float>{corner, ex, ey, two_sided});
    l.center = corner + ex * 0.5f + ey * 0.5f;
    const Vec3f c = Cross(ex, ey);
    l.area = Length(c);
    l.n = c / l.area;
    SetAxesAndEmission(l, ex, ey, radiance, two_sided, visible);
    return l;
}

inline AreaLight MakeEllipseAreaLight(const Vec3f& center, const Vec3f& ax, const Vec3f& ay, const Spectrum& radiance,
                                      bool two_sided, bool visible) {
    AreaLight l;
    l.shape = AreaShape::Ellipse;
    l.center = center;
    l.ax = ax;
    l.ay = ay;
    const Vec3f c = Cross(ax, ay);
    l.area = kPi * Length(c);
    l.n = Normalize(c);
    SetAxesAndEmission(l, ax, ay, radiance, two_sided, visible);
    return l;
}

// Radiance leaving the light at a point towards `toward` (any vector pointing away from the light).
inline Spectrum EmittedRadiance(const AreaLight& l, const Vec3f& toward) {
    return (l.two_sided || Dot(l.n, toward) > 0) ? l.radiance : Spectrum();
}

// Distance along the ray (o, d) to the light, or kInf when it misses within (0, tmax).
inline float IntersectAreaLight(const AreaLight& l, const Vec3f& o, const Vec3f& d, float tmax) {
    const float denom = Dot(l.n, d);
    if (denom == 0) return kInf;
    const Vec3f origin = l.shape == AreaShape::Rectangle ? l.frame.light.corner : l.center;
    const float t = Dot(l.n, origin - o) / denom;
    if (!(t > 0 && t < tmax)) return kInf;
    const Vec3f q = o + d * t - origin;
    const float a = Dot(q, l.inv_x), b = Dot(q, l.inv_y);
    if (l.shape == AreaShape::Rectangle) return (a >= 0 && a <= 1 && b >= 0 && b <= 1) ? t : kInf;
    return a * a + b * b <= 1 ? t : kInf;
}

// Solid-angle pdf at `origin` of uniform area sampling, d^2 / (A |cos theta_l|); 0 if not finite.
inline float AreaToSolidAnglePDF(const AreaLight& l, const Vec3f& origin, const Vec3f& p) {
    const Vec3f d = p - origin;
    const float d2 = Dot(d, d);
    const float cosl = std::abs(Dot(l.n, d)) / std::sqrt(d2);
    const float pdf = d2 / (l.area * cosl);
    return std::isfinite(pdf) && pdf > 0 ? pdf : 0.0f;
}

inline float EllipseAreaPDF(const AreaLight& l, const Vec3f& origin, const Vec3f& p) {
    if (!l.two_sided && Dot(l.n, origin - l.center) <= 0) return 0;  // behind a one-sided light
    return AreaToSolidAnglePDF(l, origin, p);
}

// Ellipse: concentric disc mapped by the semi-axes (uniform in area).
inline LightSample<float> SampleEllipseArea(const AreaLight& l, const Vec3f& origin, Point2<float> u) {
    LightSample<float> s;
    const Point2<float> d = SampleUniformDiskConcentric(u);
    s.point = l.center + l.ax * d.u + l.ay * d.v;
    const Vec3f w = s.point - origin;
    s.dist = Length(w);
    if (!(s.dist > 0)) return s;
    s.dir = w / s.dist;
    s.pdf = EllipseAreaPDF(l, origin, s.point);
    return s;
}

// Emitted flux up to the common factor pi: luminance(L) * area * sides.
inline double AreaLightPower(const AreaLight& l) {
    return double(Luminance(l.radiance)) * l.area * (l.two_sided ? 2 : 1);
}

}  // namespace sphrect::render
