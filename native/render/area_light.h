// Area lights: rectangles and ellipses (discs), sampled and intersected analytically, and the
// triangles of emissive meshes.  Rectangles are sampled with the chosen technique
// (core/technique.h, through integrator/light_sampling_at.h); ellipses with the chosen ellipse
// technique (core/ellipse_technique.h, through integrator/ellipse_sampling_at.h): uniformly by
// area (here), converted to solid angle, or by the spherical ellipse map; triangles by solid
// angle with Arvo's spherical triangle map (core/spherical_triangle.h), or by area under the
// `area` technique.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/ellipse_light.h"
#include "core/light_sample.h"
#include "core/rect_light.h"
#include "core/solid_angle.h"
#include "core/triangle_emitter.h"
#include "light_bounds.h"
#include "ray_visibility.h"
#include "sampling_util.h"

namespace sphrect::render {

enum class AreaShape { Rectangle, Ellipse, Triangle };

struct AreaLight {
    AreaShape shape = AreaShape::Rectangle;
    // Rectangle: the light (frame.light: corner, edges ex, ey) with what the samplers' setups
    // need of it, computed once per light.  Ellipses: invalid, or with spread their bounding rectangle.
    RectLightFrame<float> frame;
    // Ellipse: what the spherical ellipse's setups need of it (invalid for the other shapes).
    EllipseLightFrame<float> ellipse_frame;
    Vec3f center;        // centre
    Vec3f ax, ay;        // Ellipse: semi-axes
    Vec3f v0, e1, e2;    // Triangle: vertex v0 and edges v1 - v0, v2 - v0
    Vec3f n;             // unit normal, cross(ex, ey) direction: the emitting side
    Vec3f inv_x, inv_y;  // ex / |ex|^2, ey / |ey|^2 (resp. the ellipse's semi-axes): plane coordinates
    Spectrum radiance;
    float area = 0;
    bool two_sided = false;
    bool visible = true;  // seen by camera rays
    LightVisibility vis;  // what it lights, its shadows, MIS (ray_visibility.h)
    // Part of an emissive mesh (a triangle, or a rectangle made of two): Embree geometry, so
    // camera and BSDF rays find it through their hit, not through IntersectAreaLight.
    bool on_mesh = false;
    // Spread (rectangles and ellipses, SetAreaSpread): Cycles 3.4's tan_spread and normalize_spread;
    // spread_cot 0 (a spread of 180 degrees) is a light without spread.
    float spread_cot = 0;
    float spread_normalization = 1;
    // Textured emission (an emissive mesh's, or the light's own): index into RenderScene::textured_emitters, -1 for
    // none.  `radiance` is then its mean over the light, which light selection uses (textured_emission.h).
    int texture = -1;
    bool HasSpread() const { return spread_cot > 0; }
};

// Cycles 3.4 clamps the spread to at least 1 degree (scene/light.cpp).
constexpr float kMinAreaSpread = kPi / 180;

// The spread (radians, [0, pi]) of an area light as Cycles 3.4 sets it up (scene/light.cpp), in float as it
// does: a = (pi - max(spread, 1 degree)) / 2, the complement of the half spread h; spread_cot = tan(a) =
// 1 / tan(h); the normalisation 2 / (2 + (2 a - pi) tan(a)) = 1 / (1 - h / tan(h)) keeps the light's power (the
// integral of cos * attenuation over the hemisphere).  Cycles' float expression cancels at small spreads: it
// gives 1.245 times the exact factor at 1 degree, 1.025 at 2, 1.0016 at 5; it is kept, for parity.  A spread of
// 180 degrees gives spread_cot 0: no spread, the light as without it.
inline void SetAreaSpread(AreaLight& l, float spread) {
    const float a = 0.5f * (kPi - std::max(spread, kMinAreaSpread));
    l.spread_cot = std::tan(a);
    l.spread_normalization = l.spread_cot > 0 ? 2.0f / (2.0f + (2.0f * a - kPi) * l.spread_cot) : 1.0f;
    // An ellipse with spread is sampled on its bounding rectangle's clip (EllipseSamplingAt).
    if (l.HasSpread() && l.shape == AreaShape::Ellipse)
        l.frame = MakeRectLightFrame(RectLight<float>{l.center - l.ax - l.ay, l.ax * 2.0f, l.ay * 2.0f, l.two_sided});
}

// Cycles 3.4's spread attenuation (kernel/light/common.h, light_spread_attenuation: a soft box's grid,
// the fraction of the light its slats let through at angle alpha to the normal), for light leaving
// towards `toward`: max((1 - tan(alpha) / tan(h)) normalization, 0).  tan(alpha) from |n x w| / |n . w|,
// exact near the normal where sqrt(1 - cos^2) is not.
inline float SpreadAttenuation(const AreaLight& l, const Vec3f& toward) {
    const float c = std::abs(Dot(l.n, toward));
    if (!(c > 0)) return 0;
    const float tan_alpha = Length(Cross(l.n, toward)) / c;
    return std::max((1 - l.spread_cot * tan_alpha) * l.spread_normalization, 0.0f);
}

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
    l.ellipse_frame = MakeEllipseLightFrame(EllipseLight<float>{center, ax, ay, two_sided});
    SetAxesAndEmission(l, ax, ay, radiance, two_sided, visible);
    return l;
}

// A triangle of an emissive mesh.  Mesh emission is two-sided, as in Cycles 3.4, whose
// emissive closure weighs emission by |Ng . wi| > 0 (kernel/closure/emissive.h, emissive_pdf).
inline AreaLight MakeTriangleAreaLight(const Vec3f& v0, const Vec3f& v1, const Vec3f& v2, const Spectrum& radiance) {
    AreaLight l;
    l.shape = AreaShape::Triangle;
    l.v0 = v0;
    l.e1 = v1 - v0;
    l.e2 = v2 - v0;
    l.center = v0 + (l.e1 + l.e2) * (1.0f / 3);
    const Vec3f c = Cross(l.e1, l.e2);
    l.area = 0.5f * Length(c);
    l.n = Normalize(c);
    SetAxesAndEmission(l, l.e1, l.e2, radiance, /*two_sided=*/true, /*visible=*/true);
    l.on_mesh = true;
    return l;
}

// Radiance leaving the light at a point towards `toward` (any vector pointing away from the light).
// With spread, attenuated (SpreadAttenuation) for every ray: light samples, BSDF and camera rays.
inline Spectrum EmittedRadiance(const AreaLight& l, const Vec3f& toward) {
    if (!(l.two_sided || Dot(l.n, toward) > 0)) return Spectrum();
    return l.HasSpread() ? l.radiance * SpreadAttenuation(l, toward) : l.radiance;
}

// The share of its radiance a rectangle or ellipse light sends towards `toward`: 0 behind a one-sided light, its
// spread's attenuation (EmittedRadiance's factor, for a light whose radiance varies over it: textured_emission.h).
inline float EmissionTowards(const AreaLight& l, const Vec3f& toward) {
    if (!(l.two_sided || Dot(l.n, toward) > 0)) return 0;
    return l.HasSpread() ? SpreadAttenuation(l, toward) : 1.0f;
}
// Whether the point p of the ellipse light's plane lies on the ellipse.
inline bool OnEllipse(const AreaLight& l, const Vec3f& p) {
    const Vec3f q = p - l.center;
    const float a = Dot(q, l.inv_x), b = Dot(q, l.inv_y);
    return a * a + b * b <= 1;
}

// The part of rectangle light l (with spread, of an ellipse's bounding rectangle) from which `origin` receives light
// within the spread (Cycles 3.4: kernel/light/common.h, light_spread_clamp_area_light): the light clipped to the
// square, in its plane, centred on the origin's foot, of half side r = distance to the plane * tan(h) -- the box of the
// disc outside which the attenuation is 0.  A sub-rectangle, sampled by every technique as a light of its own; an
// invalid frame when empty (the origin receives nothing).  In double, from the light's double frame.
inline RectLightFrame<float> SpreadClippedFrame(const AreaLight& l, const Vec3f& origin) {
    const RectLightFrame<float>& f = l.frame;
    const Vec3d d = Vec3d(origin) - f.corner;
    const double fu = Dot(d, f.exh), fv = Dot(d, f.eyh), r = std::abs(Dot(d, f.n)) / double(l.spread_cot);
    const double u0 = std::max(fu - r, 0.0), u1 = std::min(fu + r, f.wx);
    const double v0 = std::max(fv - r, 0.0), v1 = std::min(fv + r, f.wy);
    if (!(u0 < u1 && v0 < v1)) {
        RectLightFrame<float> empty = f;
        empty.valid = false;
        return empty;
    }
    return SubRectLightFrame(f, u0, v0, u1, v1);
}

// Distance along the ray (o, d) to the light, or kInf when it misses within (0, tmax).
inline float IntersectAreaLight(const AreaLight& l, const Vec3f& o, const Vec3f& d, float tmax) {
    const float denom = Dot(l.n, d);
    if (denom == 0) return kInf;
    const Vec3f origin = l.shape == AreaShape::Rectangle  ? l.frame.light.corner
                         : l.shape == AreaShape::Triangle ? l.v0
                                                          : l.center;
    const float t = Dot(l.n, origin - o) / denom;
    if (!(t > 0 && t < tmax)) return kInf;
    const Vec3f q = o + d * t - origin;
    if (l.shape == AreaShape::Triangle) {
        // Barycentrics (b1, b2) of q = b1 e1 + b2 e2 from the 2x2 Gram system.
        const float g11 = Dot(l.e1, l.e1), g12 = Dot(l.e1, l.e2), g22 = Dot(l.e2, l.e2);
        const float r1 = Dot(q, l.e1), r2 = Dot(q, l.e2), det = g11 * g22 - g12 * g12;
        const float b1 = (g22 * r1 - g12 * r2) / det, b2 = (g11 * r2 - g12 * r1) / det;
        return (b1 >= 0 && b2 >= 0 && b1 + b2 <= 1) ? t : kInf;
    }
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

// Ellipse (and any planar light sampled by area): 0 behind a one-sided light.
inline float EllipseAreaPDF(const AreaLight& l, const Vec3f& origin, const Vec3f& p) {
    if (!l.two_sided && Dot(l.n, origin - l.center) <= 0) return 0;  // behind a one-sided light
    return AreaToSolidAnglePDF(l, origin, p);
}

// The light sample at `point`, drawn uniformly by area on the planar light l, seen from origin.
inline LightSample<float> AreaSampleSeenFrom(const AreaLight& l, const Vec3f& origin, const Vec3f& point) {
    LightSample<float> s;
    s.point = point;
    const Vec3f w = s.point - origin;
    s.dist = Length(w);
    if (!(s.dist > 0)) return s;
    s.dir = w / s.dist;
    s.pdf = EllipseAreaPDF(l, origin, s.point);
    return s;
}

// Ellipse: concentric disc mapped by the semi-axes (uniform in area).
inline LightSample<float> SampleEllipseArea(const AreaLight& l, const Vec3f& origin, Point2<float> u) {
    const Point2<float> d = SampleUniformDiskConcentric(u);
    return AreaSampleSeenFrom(l, origin, l.center + l.ax * d.u + l.ay * d.v);
}

// Triangle, uniform by area: barycentrics (1 - su, su (1 - v), su v), su = sqrt(u)
// (pbrt-v4's SampleUniformTriangle in its simplest form), converted to solid angle.
inline LightSample<float> SampleTriangleArea(const AreaLight& l, const Vec3f& origin, Point2<float> u) {
    const float su = std::sqrt(u.u);
    return AreaSampleSeenFrom(l, origin, l.v0 + l.e1 * (su * (1 - u.v)) + l.e2 * (su * u.v));
}

// A triangle light seen from one point, sampled by solid angle: core/triangle_emitter.h on its vertex and edges.
inline TriangleSolidAngleSetup MakeTriangleSolidAngleSetup(const AreaLight& l, const Vec3f& origin) {
    return sphrect::MakeTriangleSolidAngleSetup(l.v0, l.e1, l.e2, origin);
}

// Solid-angle pdf of the point p on the triangle: 1 / Omega (the map is uniform in solid angle).
inline float TriangleSolidAnglePDF(const TriangleSolidAngleSetup& r, const AreaLight& /*l*/, const Vec3f& /*origin*/,
                                   const Vec3f& /*p*/) {
    return r.valid ? r.pdf : 0.0f;
}

inline LightSample<float> SampleTriangleSolidAngle(const TriangleSolidAngleSetup& r, const AreaLight& /*l*/,
                                                   const Vec3f& origin, Point2<float> u) {
    return sphrect::SampleTriangleSolidAngle(r, origin, u);
}

// Emitted flux up to the common factor pi: luminance(L) * area * sides.
inline double AreaLightPower(const AreaLight& l) {
    return double(Luminance(l.radiance)) * l.area * (l.two_sided ? 2 : 1);
}

// The light tree's bounds of an emissive triangle of luminance `luminance` (a planar light: cone around its normal).
inline LightBounds TriangleLightBounds(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2, float luminance,
                                       bool two_sided) {
    LightBounds b;
    b.lo = {std::min({p0.x, p1.x, p2.x}), std::min({p0.y, p1.y, p2.y}), std::min({p0.z, p1.z, p2.z})};
    b.hi = {std::max({p0.x, p1.x, p2.x}), std::max({p0.y, p1.y, p2.y}), std::max({p0.z, p1.z, p2.z})};
    const Vec3f c = Cross(p1 - p0, p2 - p0);
    const float twice_area = Length(c);
    b.power = twice_area > 0 ? double(luminance) * 0.5 * twice_area : 0.0;  // a degenerate triangle emits nothing
    b.axis = twice_area > 0 ? c / twice_area : Vec3f(0, 0, 1);
    b.cos_theta_o = 1;
    b.cos_theta_e = 0;
    b.two_sided = two_sided;
    return b;
}

// The light tree's bounds of an area light: its box, a cone around its normal, L*A.
inline LightBounds AreaLightBounds(const AreaLight& l) {
    if (l.shape == AreaShape::Triangle)
        return TriangleLightBounds(l.v0, l.v0 + l.e1, l.v0 + l.e2, Luminance(l.radiance), l.two_sided);
    LightBounds b;
    // Box of a rectangle: its corners; of an ellipse c + ax cos t + ay sin t: c +- sqrt(ax_i^2 + ay_i^2).
    if (l.shape == AreaShape::Rectangle) {
        const RectLight<float>& r = l.frame.light;
        const Vec3f corners[4] = {r.corner, r.corner + r.ex, r.corner + r.ey, r.corner + r.ex + r.ey};
        b.lo = b.hi = corners[0];
        for (const Vec3f& c : corners) {
            b.lo = {std::min(b.lo.x, c.x), std::min(b.lo.y, c.y), std::min(b.lo.z, c.z)};
            b.hi = {std::max(b.hi.x, c.x), std::max(b.hi.y, c.y), std::max(b.hi.z, c.z)};
        }
    } else {
        const Vec3f half = {std::hypot(l.ax.x, l.ay.x), std::hypot(l.ax.y, l.ay.y), std::hypot(l.ax.z, l.ay.z)};
        b.lo = l.center - half;
        b.hi = l.center + half;
    }
    b.power = double(Luminance(l.radiance)) * l.area;  // intensity along the normal, per side (double: no overflow)
    b.axis = l.n;
    b.cos_theta_o = 1;
    b.cos_theta_e = 0;  // cosine falloff to pi/2
    b.two_sided = l.two_sided;
    return b;
}

}  // namespace sphrect::render
