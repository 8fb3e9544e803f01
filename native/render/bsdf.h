// Surface scattering: Lambert, and the common part of Blender's Principled BSDF
// (Lambert diffuse weighted by 1 - metallic, plus a GGX / Trowbridge-Reitz specular lobe
// with alpha = roughness^2, F0 = mix(0.08 * specular, base colour, metallic), Schlick Fresnel,
// height-correlated Smith masking-shadowing).  All functions work in the shading frame where
// the normal is +z and wo is on the +z side (the caller flips the normal to the viewer's side).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/rng.h"
#include "sampling_util.h"

namespace sphrect::render {

struct Material {
    Spectrum diffuse;      // reflectance of the Lambert lobe (albedo): f = diffuse / pi
    Spectrum f0;           // specular reflectance at normal incidence (0: no specular lobe)
    float alpha = 1;       // GGX roughness parameter
    float specular_probability = 0;  // chance of sampling the specular lobe in SampleBsdf
    bool glossy = false;
    Spectrum emission;     // radiance emitted from both sides (emissive meshes); 0: none
};

// Blender material parameters -> Material.  Roughness is clamped to 0.03 (alpha ~ 1e-3): a
// perfect mirror is a delta lobe that direct lighting from area lights cannot sample by lights.
inline Material MakeDiffuseMaterial(const Spectrum& base) {
    Material m;
    m.diffuse = base;
    return m;
}

inline Material MakeGlossyMaterial(const Spectrum& base, float roughness, float metallic, float specular) {
    Material m;
    m.glossy = true;
    metallic = std::clamp(metallic, 0.0f, 1.0f);
    const float r = std::clamp(roughness, 0.03f, 1.0f);
    m.alpha = r * r;
    m.diffuse = base * (1 - metallic);
    const float f0_dielectric = 0.08f * std::max(specular, 0.0f);
    m.f0 = Spectrum(f0_dielectric, f0_dielectric, f0_dielectric) * (1 - metallic) + base * metallic;
    // Pick lobes roughly by their albedo so neither is starved.
    const float wd = Luminance(m.diffuse), ws = std::max(Luminance(m.f0), 0.04f);
    m.specular_probability = wd > 0 ? std::clamp(ws / (wd + ws), 0.1f, 0.9f) : 1.0f;
    return m;
}

// --- GGX / Trowbridge-Reitz (Walter et al. 2007; Heitz 2014, 2018) ---------------------------

inline float GgxD(const Vec3f& h, float alpha) {
    const float c2 = h.z * h.z, a2 = alpha * alpha;
    const float d = c2 * (a2 - 1) + 1;
    return a2 / (kPi * d * d);
}

// Smith Lambda for GGX: (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2.
inline float GgxLambda(const Vec3f& w, float alpha) {
    const float c2 = w.z * w.z;
    if (c2 <= 0) return kInf;
    const float tan2 = std::max(0.0f, 1 - c2) / c2;
    return 0.5f * (-1 + std::sqrt(1 + alpha * alpha * tan2));
}

inline float GgxG1(const Vec3f& w, float alpha) { return 1 / (1 + GgxLambda(w, alpha)); }
inline float GgxG2(const Vec3f& wo, const Vec3f& wi, float alpha) {
    return 1 / (1 + GgxLambda(wo, alpha) + GgxLambda(wi, alpha));
}

inline Spectrum SchlickFresnel(const Spectrum& f0, float cos_theta) {
    const float m = std::clamp(1 - cos_theta, 0.0f, 1.0f);
    const float m5 = (m * m) * (m * m) * m;
    return f0 + (Spectrum(1, 1, 1) - f0) * m5;
}

// Heitz 2018, "Sampling the GGX Distribution of Visible Normals": a microfacet normal with
// density D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z.
inline Vec3f SampleGgxVisibleNormal(const Vec3f& wo, float alpha, Point2<float> u) {
    const Vec3f vh = Normalize(Vec3f(alpha * wo.x, alpha * wo.y, wo.z));
    const float len2 = vh.x * vh.x + vh.y * vh.y;
    const Vec3f t1 = len2 > 0 ? Vec3f(-vh.y, vh.x, 0) / std::sqrt(len2) : Vec3f(1, 0, 0);
    const Vec3f t2 = Cross(vh, t1);
    const float r = std::sqrt(u.u), phi = 2 * kPi * u.v;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1 + vh.z);
    p2 = (1 - s) * SafeSqrt(1 - p1 * p1) + s * p2;
    const Vec3f nh = t1 * p1 + t2 * p2 + vh * SafeSqrt(1 - p1 * p1 - p2 * p2);
    return Normalize(Vec3f(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)));
}

// Solid-angle pdf of wi = reflect(wo, h) when h is drawn from the visible normals:
// D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z).
inline float GgxReflectionPDF(const Vec3f& wo, const Vec3f& wi, float alpha) {
    if (wi.z <= 0) return 0;
    const Vec3f h = Normalize(wo + wi);
    return GgxG1(wo, alpha) * GgxD(h, alpha) / (4 * wo.z);
}

// --- The BSDF, specialised on whether a glossy lobe can exist ----------------------------------

template <bool kGlossy>
inline Spectrum EvalBsdf(const Material& m, const Vec3f& wo, const Vec3f& wi) {
    if (wi.z <= 0 || wo.z <= 0) return {};
    Spectrum f = m.diffuse * kInvPi;
    if constexpr (kGlossy) {
        if (m.glossy) {
            const Vec3f h = Normalize(wo + wi);
            const float spec = GgxD(h, m.alpha) * GgxG2(wo, wi, m.alpha) / (4 * wo.z * wi.z);
            f += SchlickFresnel(m.f0, Dot(wi, h)) * spec;
        }
    }
    return f;
}

template <bool kGlossy>
inline float BsdfPDF(const Material& m, const Vec3f& wo, const Vec3f& wi) {
    if (wi.z <= 0 || wo.z <= 0) return 0;
    if constexpr (kGlossy) {
        if (m.glossy) {
            const float ps = m.specular_probability;
            return ps * GgxReflectionPDF(wo, wi, m.alpha) + (1 - ps) * CosineHemispherePDF(wi.z);
        }
    }
    return CosineHemispherePDF(wi.z);
}

struct BsdfSample {
    Vec3f wi;
    Spectrum f;
    float pdf = 0;  // 0: no sample
};

template <bool kGlossy>
inline BsdfSample SampleBsdf(const Material& m, const Vec3f& wo, Point2<float> u) {
    BsdfSample s;
    if (wo.z <= 0) return s;
    if constexpr (kGlossy) {
        if (m.glossy) {
            // One uniform number picks the lobe and is rescaled to [0,1) for the lobe's own warp.
            const float ps = m.specular_probability;
            if (u.u < ps) {
                u.u = std::min(u.u / ps, kOneMinusEpsilonF);
                const Vec3f h = SampleGgxVisibleNormal(wo, m.alpha, u);
                s.wi = h * (2 * Dot(wo, h)) - wo;
            } else {
                u.u = std::min((u.u - ps) / (1 - ps), kOneMinusEpsilonF);
                s.wi = SampleCosineHemisphere(u);
            }
            s.pdf = BsdfPDF<true>(m, wo, s.wi);
            if (!(s.pdf > 0)) {
                s.pdf = 0;
                return s;
            }
            s.f = EvalBsdf<true>(m, wo, s.wi);
            return s;
        }
    }
    s.wi = SampleCosineHemisphere(u);
    s.pdf = CosineHemispherePDF(s.wi.z);
    if (!(s.pdf > 0)) {
        s.pdf = 0;
        return s;
    }
    s.f = m.diffuse * kInvPi;
    return s;
}

}  // namespace sphrect::render
