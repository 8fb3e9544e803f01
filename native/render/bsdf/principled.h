// Evaluation, pdf and sampling of a Bsdf's lobes in the shading frame (normal +z, wo above it): Blender's
// Principled BSDF as Cycles 3.4 evaluates it, and the microfacet lobes of Glass, Glossy and mixes beside it.
#pragma once

#include <algorithm>
#include <cmath>

#include "bump_shadowing.h"
#include "core/rng.h"
#include "make_bsdf.h"
#include "microfacet.h"
#include "multiscatter_ggx.h"
#include "principled_lobes.h"
#include "render/ray_visibility.h"

namespace sphrect::render {

// --- Principled (Cycles 3.4) --------------------------------------------------------------------

// The Principled specular's Fresnel (Cycles' interpolate_fresnel_color of its cspec0 and IOR).
inline Spectrum PrincipledSpecularFresnel(const Bsdf& m, float cos_ih) {
    return InterpolatedFresnel(cos_ih, m.specular_ior, m.specular_f0, m.f0);
}

constexpr float kClearcoatShadowingAlpha = 0.25f;  // Cycles' fixed alpha of the clearcoat's G
constexpr float kClearcoatIor = 1.5f;

inline float ClearcoatD(const Vec3f& h, float alpha) { return Gtr1D(h.z * h.z, h.x * h.x + h.y * h.y, alpha); }

// pdf of wi = reflect(wo, h) with h drawn with density D_GTR1 cos(theta_h).
inline float ClearcoatReflectionPDF(const Vec3f& wo, const Vec3f& wi, float alpha) {
    if (wi.z <= 0) return 0;
    const Vec3f h = Normalize(wo + wi);
    return ClearcoatD(h, alpha) * h.z / (4 * Dot(wo, h));
}

// One microfacet lobe's f (wo.z, wi.z > 0, h their half vector; sampled: wi is the BSDF's own sample).
inline Spectrum EvalMicrofacetLobe(const MicrofacetLobe& l, const Vec3f& wo, const Vec3f& wi, const Vec3f& h,
                                   bool sampled) {
    if (l.multiscatter) {
        const float c = l.tangent_cos, s = l.tangent_sin;
        const bool iso = !l.anisotropic();
        return l.color * MultiscatterGgxEval(iso ? wo : IntoTangentFrame(wo, c, s),
                                             iso ? wi : IntoTangentFrame(wi, c, s), l.alpha, l.alpha_y, 0, {}, sampled,
                                             l.bounce_color);
    }
    float dg;
    if (l.beckmann) {
        dg = BeckmannD(h, l.alpha) * BeckmannG1(wo.z, l.alpha) * BeckmannG1(wi.z, l.alpha);
    } else if (l.anisotropic()) {
        dg = GgxAnisotropicDG(wo, wi, h, l.alpha, l.alpha_y, l.tangent_cos, l.tangent_sin);
    } else {
        dg = GgxD(h, l.alpha) * SmithG1Ggx(wo.z, l.alpha) * SmithG1Ggx(wi.z, l.alpha);
    }
    const float fresnel = l.fresnel_ior > 0 ? DielectricFresnel(wo.z, l.fresnel_ior) : 1.0f;
    return l.color * (fresnel * dg / (4 * wo.z * wi.z));
}

// wo.z, wi.z > 0.
// sampled: wi is the BSDF's own sample (its multiple-scattering walk then starts from the view, as Cycles' sampling
// walk does: multiscatter_ggx.h).
inline Spectrum EvalPrincipled(const Bsdf& m, const Vec3f& wo, const Vec3f& wi, bool sampled = false) {
    Spectrum f = m.diffuse * BurleyDiffuse(wo, wi, m.burley_roughness) + m.lambert * kInvPi;
    if (m.has_oren_nayar) f += m.oren_nayar * OrenNayarFactor(m.oren_nayar_a, m.oren_nayar_b, wo, wi);
    const Vec3f h = Normalize(wo + wi);
    const float cos_ih = Dot(wi, h), inv_4cos = 1 / (4 * wo.z * wi.z);
    if (m.has_sheen) f += m.sheen * SchlickWeight(cos_ih);
    if (m.bump_shadowing) f = f * BumpShadowingTerm(m.unmapped_normal, wi);  // the diffuse lobes so far
    if (m.has_specular && m.multiscatter) {
        const bool iso = m.alpha == m.specular_alpha_y;
        const float c = m.specular_tangent_cos, s = m.specular_tangent_sin;
        f += MultiscatterGgxEval(iso ? wo : IntoTangentFrame(wo, c, s), iso ? wi : IntoTangentFrame(wi, c, s), m.alpha,
                                 m.specular_alpha_y, m.specular_ior, m.f0, sampled) *
             m.specular_weight;
    } else if (m.has_specular) {
        const float dg = m.alpha == m.specular_alpha_y
                             ? GgxD(h, m.alpha) * SmithG1Ggx(wo.z, m.alpha) * SmithG1Ggx(wi.z, m.alpha)
                             : GgxAnisotropicDG(wo, wi, h, m.alpha, m.specular_alpha_y, m.specular_tangent_cos,
                                                m.specular_tangent_sin);
        f += PrincipledSpecularFresnel(m, cos_ih) * (m.specular_weight * dg * inv_4cos);
    }
    for (int i = 0; i < m.num_lobes; ++i) f += EvalMicrofacetLobe(m.lobes[i], wo, wi, h, sampled);
    if (m.has_clearcoat) {
        const float g = SmithG1Ggx(wo.z, kClearcoatShadowingAlpha) * SmithG1Ggx(wi.z, kClearcoatShadowingAlpha);
        const float fresnel = DielectricFresnel(cos_ih, kClearcoatIor);
        const float v = m.clearcoat * fresnel * ClearcoatD(h, m.clearcoat_alpha) * g * inv_4cos;
        f += Spectrum(v, v, v);
    }
    return f;
}

// wo.z > 0; wi.z > 0, or < 0 for the translucent lobe.
inline float PrincipledPDF(const Bsdf& m, const Vec3f& wo, const Vec3f& wi) {
    if (wi.z < 0) return m.translucent_probability * CosineHemispherePDF(-wi.z);
    const float ps = m.specular_probability, pc = m.clearcoat_probability;
    float p_cos = 1 - ps - pc - m.translucent_probability;
    float pdf = 0;
    if (ps > 0)
        pdf += ps * (m.alpha == m.specular_alpha_y ? GgxReflectionPDF(wo, wi, m.alpha)
                                                   : GgxAnisotropicPDF(wo, wi, m.alpha, m.specular_alpha_y,
                                                                       m.specular_tangent_cos, m.specular_tangent_sin));
    if (pc > 0) pdf += pc * ClearcoatReflectionPDF(wo, wi, m.clearcoat_alpha);
    for (int i = 0; i < m.num_lobes; ++i) {
        const MicrofacetLobe& l = m.lobes[i];
        p_cos -= l.probability;
        pdf += l.probability * (l.anisotropic()
                                    ? GgxAnisotropicPDF(wo, wi, l.alpha, l.alpha_y, l.tangent_cos, l.tangent_sin)
                                    : GgxReflectionPDF(wo, wi, l.alpha));
    }
    return pdf + std::max(p_cos, 0.0f) * CosineHemispherePDF(wi.z);
}

// PrincipledPDF of the lobes of some closure classes (ray_visibility.h; kRayDiffuse: the cosine and translucent lobes,
// kRayGlossy: the microfacet reflections), each at its own probability: Cycles' pdf of the closures a light lights
// (_surface_shader_bsdf_eval_mis).  The same sums in the same order as PrincipledPDF, which stays the hot path's
// (test_bsdf_lobes.cpp checks that all classes give its value bit for bit).
inline float PrincipledPDFOfClasses(const Bsdf& m, const Vec3f& wo, const Vec3f& wi, uint8_t classes) {
    const bool diffuse = classes & kRayDiffuse, reflection = classes & kRayGlossy;
    if (wi.z < 0) return diffuse ? m.translucent_probability * CosineHemispherePDF(-wi.z) : 0.0f;
    const float ps = m.specular_probability, pc = m.clearcoat_probability;
    float p_cos = 1 - ps - pc - m.translucent_probability;
    float pdf = 0;
    if (reflection && ps > 0)
        pdf += ps * (m.alpha == m.specular_alpha_y ? GgxReflectionPDF(wo, wi, m.alpha)
                                                   : GgxAnisotropicPDF(wo, wi, m.alpha, m.specular_alpha_y,
                                                                       m.specular_tangent_cos, m.specular_tangent_sin));
    if (reflection && pc > 0) pdf += pc * ClearcoatReflectionPDF(wo, wi, m.clearcoat_alpha);
    for (int i = 0; i < m.num_lobes; ++i) {
        const MicrofacetLobe& l = m.lobes[i];
        p_cos -= l.probability;
        if (reflection)
            pdf += l.probability * (l.anisotropic()
                                        ? GgxAnisotropicPDF(wo, wi, l.alpha, l.alpha_y, l.tangent_cos, l.tangent_sin)
                                        : GgxReflectionPDF(wo, wi, l.alpha));
    }
    return diffuse ? pdf + std::max(p_cos, 0.0f) * CosineHemispherePDF(wi.z) : pdf;
}

// wo mirrored about the microfacet normal h, or the zero direction (no sample: its pdf is 0) when that falls
// below the surface: a reflection lobe's density there is not part of the pdf, where only the translucent
// lobe samples.
inline Vec3f ReflectAbove(const Vec3f& wo, const Vec3f& h) {
    const Vec3f wi = h * (2 * Dot(wo, h)) - wo;
    return wi.z > 0 ? wi : Vec3f();
}

// One uniform number picks the lobe (GGX visible normals of the specular, GTR1 normals, each microfacet
// lobe's GGX visible normals, else the cosine for diffuse and sheen) and is rescaled to [0,1) for the
// lobe's own warp.
inline Vec3f SamplePrincipledDirection(const Bsdf& m, const Vec3f& wo, Point2<float> u) {
    const float ps = m.specular_probability, pc = m.clearcoat_probability;
    if (u.u < ps) {
        u.u = std::min(u.u / ps, kOneMinusEpsilonF);
        const Vec3f h = m.alpha == m.specular_alpha_y
                            ? SampleGgxVisibleNormal(wo, m.alpha, u)
                            : SampleGgxAnisotropicNormal(wo, m.alpha, m.specular_alpha_y, m.specular_tangent_cos,
                                                         m.specular_tangent_sin, u);
        return ReflectAbove(wo, h);
    }
    if (u.u < ps + pc) {
        u.u = std::min((u.u - ps) / pc, kOneMinusEpsilonF);
        const Vec3f h = SampleGtr1Normal(m.clearcoat_alpha, u);
        return ReflectAbove(wo, h);
    }
    float start = ps + pc;
    for (int i = 0; i < m.num_lobes; ++i) {
        const float p = m.lobes[i].probability;
        if (u.u < start + p) {
            u.u = std::min((u.u - start) / p, kOneMinusEpsilonF);
            const MicrofacetLobe& l = m.lobes[i];
            const Vec3f h = l.anisotropic()
                                ? SampleGgxAnisotropicNormal(wo, l.alpha, l.alpha_y, l.tangent_cos, l.tangent_sin, u)
                                : SampleGgxVisibleNormal(wo, l.alpha, u);
            return ReflectAbove(wo, h);
        }
        start += p;
    }
    if (const float pt = m.translucent_probability; u.u < start + pt) {
        u.u = std::min((u.u - start) / pt, kOneMinusEpsilonF);
        const Vec3f w = SampleCosineHemisphere(u);
        return {w.x, w.y, -w.z};
    }
    start += m.translucent_probability;
    u.u = std::min((u.u - start) / std::max(1 - start, 1e-7f), kOneMinusEpsilonF);
    return SampleCosineHemisphere(u);
}

}  // namespace sphrect::render
