// The lobes of Blender's Principled BSDF (v1) as Cycles 3.4 evaluates them (kernel/closure/
// bsdf_principled_diffuse.h, bsdf_principled_sheen.h, bsdf_microfacet.h, svm/closure.h), as pure
// functions of the shading-frame directions (normal +z, wo and wi above it).  Each returns the
// BRDF value f (Cycles' closures return f cos(wi); the integrator here multiplies by cos itself).
// principled.h evaluates a Bsdf's lobes with them.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/sampling_util.h"

namespace sphrect::render {

// (1 - cos)^5, clamped as Cycles' schlick_fresnel.
inline float SchlickWeight(float cos_theta) {
    const float m = std::clamp(1 - cos_theta, 0.0f, 1.0f);
    return (m * m) * (m * m) * m;
}

// Unpolarised Fresnel reflectance of a dielectric of relative IOR eta (fresnel_dielectric_cos:
// no refracted direction needed; 1 on total internal reflection).
inline float DielectricFresnel(float cos_i, float eta) {
    const float c = std::abs(cos_i);
    float g = eta * eta - 1 + c * c;
    if (!(g > 0)) return 1;
    g = std::sqrt(g);
    const float a = (g - c) / (g + c);
    const float b = (c * (g + c) - 1) / (c * (g - c) + 1);
    return 0.5f * a * a * (1 + b * b);
}

// Cycles' interpolate_fresnel_color: cspec0 blended towards white by the rise of the dielectric Fresnel of relative
// IOR eta at cos_lh (the light's cosine to the microfacet normal) above its normal-incidence value f0 = F(1, eta).
inline Spectrum InterpolatedFresnel(float cos_lh, float eta, float f0, const Spectrum& cspec0) {
    const float rise = (DielectricFresnel(cos_lh, eta) - f0) / (1 - f0);
    return cspec0 * (1 - rise) + Spectrum(rise, rise, rise);
}

// Cycles 3.4's Oren-Nayar (bsdf_oren_nayar_get_intensity, its f cos divided by the cosine): a + b t, t = (wi.wo -
// cos_i cos_o) / max(cos_i, cos_o) where positive (the azimuthal term of Fujii's simplification), else unscaled.
inline float OrenNayarFactor(float a, float b, const Vec3f& wo, const Vec3f& wi) {
    const float nl = std::max(wi.z, 0.0f), nv = std::max(wo.z, 0.0f);
    float t = Dot(wi, wo) - nl * nv;
    if (t > 0) t /= std::max(nl, nv) + std::numeric_limits<float>::min();
    return a + b * t;
}

// Burley's diffuse (Disney 2012) split as Cycles 3.4 does (Burley 2015, 2.3): a Lambert-like part
// (1 - FV/2)(1 - FL/2) and a retro-reflection RR (FL + FV + FL FV (RR - 1)), RR = roughness
// (1 + wi.wo) = 2 roughness (wi.h)^2.  Returns f / colour (multiply by the diffuse weight x base colour).
inline float BurleyDiffuse(const Vec3f& wo, const Vec3f& wi, float roughness) {
    const float fv = SchlickWeight(wo.z), fl = SchlickWeight(wi.z);
    const float lambert = (1 - 0.5f * fv) * (1 - 0.5f * fl);
    const float rr = roughness * (Dot(wi, wo) + 1);
    return kInvPi * (lambert + rr * (fl + fv + fl * fv * (rr - 1)));
}

// Cycles' principled sheen: f = (1 - wi.h)^5 (no 1/pi: Cycles' closure value is that times cos).
inline float PrincipledSheen(const Vec3f& wo, const Vec3f& wi) { return SchlickWeight(Dot(wi, Normalize(wo + wi))); }

// GGX's D for a unit microfacet normal h with roughness ax along x and ay along y (Walter et al. 2007's anisotropic
// form, cos^-4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^-2 / (pi ax ay), multiplied out):
// 1 / (pi ax ay ((hx / ax)^2 + (hy / ay)^2 + hz^2)^2).
inline float GgxAnisotropicD(const Vec3f& h, float ax, float ay) {
    const float sx = h.x / ax, sy = h.y / ay;
    const float d = sx * sx + sy * sy + h.z * h.z;
    return 1 / (kPi * ax * ay * d * d);
}

// Separable Smith masking for GGX, as Cycles 3.4's microfacet closures (G = G1(wo) G1(wi), not the
// height-correlated form): G1 = 2 / (1 + sqrt(1 + alpha^2 tan^2)).
inline float SmithG1Ggx(float cos_theta, float alpha) {
    const float c2 = cos_theta * cos_theta;
    if (!(c2 > 0)) return 0;
    return 2 / (1 + SafeSqrt(1 + alpha * alpha * (1 - c2) / c2));
}

// Burley's GTR1 ("Berry") distribution of the clearcoat, normalised so that D cos(theta_h)
// integrates to 1; D_GTR1 of Cycles (1/pi at alpha >= 1).  sin2 = 1 - cos^2 is passed in, taken
// from h's x, y: near the peak of alpha ~ 1e-3 that keeps the precision 1 + (a2 - 1) cos^2 loses.
inline float Gtr1D(float cos2, float sin2, float alpha) {
    if (alpha >= 1) return kInvPi;
    const float a2 = alpha * alpha;
    return (a2 - 1) / (kPi * std::log(a2) * (a2 * cos2 + sin2));
}

// A half vector with density D_GTR1(h) cos(theta_h) (Burley 2012, B.2: cos^2 = (1 - a2^(1-u)) / (1 - a2)).
inline Vec3f SampleGtr1Normal(float alpha, Point2<float> u) {
    const float a2 = alpha * alpha;
    const float cos2 = alpha >= 1 ? u.u : (1 - std::pow(a2, 1 - u.u)) / (1 - a2);
    const float cos_theta = SafeSqrt(cos2), sin_theta = SafeSqrt(1 - cos2), phi = 2 * kPi * u.v;
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

}  // namespace sphrect::render
