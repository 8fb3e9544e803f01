// Surface scattering: Lambert; the "glossy" model (Lambert diffuse weighted by 1 - metallic, plus
// a GGX / Trowbridge-Reitz specular lobe with alpha = roughness^2, F0 = mix(0.08 * specular, base
// colour, metallic), Schlick Fresnel, height-correlated Smith masking-shadowing: scene files'
// kind 'glossy'); Blender's Principled BSDF as Cycles 3.4 evaluates it (MakePrincipledBsdf,
// lobes in principled_lobes.h); Glass and Glossy BSDF as microfacet lobes (MakeGlassBsdf,
// MakeGlossyBsdf); Mix / Add Shader as the weighted sum of those (MixIntoBsdf), all evaluated
// by EvalPrincipled.  All functions work in the shading frame where the normal is +z and
// wo is on the +z side (the caller flips the normal to the viewer's side).
//
// One file per concern in bsdf/: make_bsdf.h (the Bsdf and its constructors), mix.h (Mix / Add Shader),
// microfacet.h (GGX, anisotropic GGX, Beckmann), principled_lobes.h and multiscatter_ggx.h (Cycles' lobes),
// principled.h (evaluation, pdf and sampling of the lobes), bump_shadowing.h; this file dispatches on them.
#pragma once

#include <algorithm>
#include <cmath>

#include "bsdf/bump_shadowing.h"
#include "bsdf/make_bsdf.h"
#include "bsdf/microfacet.h"
#include "bsdf/mix.h"
#include "bsdf/principled.h"
#include "core/rng.h"
#include "ray_visibility.h"
#include "sampling_util.h"

namespace sphrect::render {

// --- The BSDF, specialised on whether a glossy lobe can exist ----------------------------------

// wi below the surface (wi.z < 0) only reaches the translucent lobe.
template <bool kGlossy>
inline Spectrum EvalBsdf(const Bsdf& m, const Vec3f& wo, const Vec3f& wi, bool sampled = false) {
    if constexpr (kGlossy) {
        if (m.has_translucent && wi.z < 0 && wo.z > 0) {
            // Transmission: Cycles' term about the flipped normals, i.e. the mirrored direction here.
            const float bump = m.bump_shadowing ? BumpShadowingTerm(m.unmapped_normal, -wi) : 1.0f;
            return m.translucent * (kInvPi * bump);
        }
    }
    if (wi.z <= 0 || wo.z <= 0) return {};
    if constexpr (kGlossy) {
        if (m.principled) return EvalPrincipled(m, wo, wi, sampled);
    }
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
inline float BsdfPDF(const Bsdf& m, const Vec3f& wo, const Vec3f& wi) {
    if constexpr (kGlossy) {
        if (m.has_translucent && wi.z < 0 && wo.z > 0) return PrincipledPDF(m, wo, wi);
    }
    if (wi.z <= 0 || wo.z <= 0) return 0;
    if constexpr (kGlossy) {
        if (m.principled) return PrincipledPDF(m, wo, wi);
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
inline BsdfSample SampleBsdf(const Bsdf& m, const Vec3f& wo, Point2<float> u) {
    BsdfSample s;
    if (wo.z <= 0) return s;
    if constexpr (kGlossy) {
        if (m.glossy) {
            // One uniform number picks the lobe and is rescaled to [0,1) for the lobe's own warp.
            const float ps = m.specular_probability;
            if (m.principled) {
                s.wi = SamplePrincipledDirection(m, wo, u);
            } else if (u.u < ps) {
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
            s.f = EvalBsdf<true>(m, wo, s.wi, true);
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

// --- A light that lights some closure classes only (ray_visibility.h) ----------------------------

// The lobes of m that a light visible to `classes` (kRayDiffuse, kRayGlossy) lights, for EvalBsdf: Cycles evaluates
// only those closures for its samples (_surface_shader_exclude).  Transmission is no lobe here (refraction is not
// simulated): it changes nothing.
[[gnu::cold, gnu::noinline]] inline Bsdf LobesLitBy(const Bsdf& m, uint8_t classes) {
    Bsdf out = m;
    if (!(classes & kRayDiffuse)) {  // Lambert, Burley, sheen, translucent: CLOSURE_IS_BSDF_DIFFUSE
        out.diffuse = out.lambert = out.sheen = out.translucent = out.oren_nayar = {};
        out.has_sheen = out.has_oren_nayar = false;
    }
    if (!(classes & kRayGlossy)) {  // the microfacet reflections: CLOSURE_IS_BSDF_GLOSSY
        out.has_specular = out.has_clearcoat = false;
        out.num_lobes = 0;
        if (!out.principled) out.glossy = false;  // the 'glossy' model's GGX lobe
    }
    return out;
}

// The pdf of the lobes of m that a light visible to `classes` lights, by their own probabilities (not renormalised):
// Cycles' pdf for such a light's MIS weight (_surface_shader_bsdf_eval_mis skips the others' pdfs).
template <bool kGlossy>
inline float BsdfPDFOfClasses(const Bsdf& m, const Vec3f& wo, const Vec3f& wi, uint8_t classes) {
    const bool diffuse = classes & kRayDiffuse, reflection = classes & kRayGlossy;
    if constexpr (kGlossy) {
        if ((m.has_translucent && wi.z < 0 && wo.z > 0) || (m.principled && wi.z > 0 && wo.z > 0))
            return PrincipledPDFOfClasses(m, wo, wi, classes);
    }
    if (wi.z <= 0 || wo.z <= 0) return 0;
    const float cosine = diffuse ? CosineHemispherePDF(wi.z) : 0.0f;
    if constexpr (kGlossy) {
        if (m.glossy) {
            const float ps = m.specular_probability;
            return (reflection ? ps * GgxReflectionPDF(wo, wi, m.alpha) : 0.0f) + (1 - ps) * cosine;
        }
    }
    return cosine;
}

// The ray kind (ray_visibility.h) of SampleBsdf's sample from u: the class of the lobe u.u picks, by SampleBsdf's and
// SamplePrincipledDirection's thresholds (the same sums in the same order).  Apart from them, so that sampling
// costs nothing more where no mesh or light hides from a kind.
template <bool kGlossy>
inline uint8_t SampledRayKind(const Bsdf& m, Point2<float> u) {
    if constexpr (kGlossy) {
        if (m.glossy) {
            if (!m.principled) return u.u < m.specular_probability ? kRayGlossy : kRayDiffuse;
            float start = m.specular_probability + m.clearcoat_probability;
            for (int i = 0; i < m.num_lobes; ++i) start += m.lobes[i].probability;
            if (u.u < start) return kRayGlossy;
            return u.u < start + m.translucent_probability ? kRayDiffuse | kRayTransmission : kRayDiffuse;
        }
    }
    return kRayDiffuse;
}

}  // namespace sphrect::render
