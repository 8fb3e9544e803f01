// The Bsdf: a material's lobes and their weights as the integrator evaluates them, and the Make*Bsdf
// constructors that build one per Blender shader (Lambert, the 'glossy' model, Principled, Glass, Glossy /
// Anisotropic, Translucent, Transparent, Holdout).
#pragma once

#include <algorithm>
#include <cmath>

#include "principled_lobes.h"
#include "singular.h"
#include "render/sampling_util.h"

namespace sphrect::render {

// A microfacet reflection lobe as Cycles 3.4's closures evaluate it: colour x D G1(wo) G1(wi) / (4 cos cos)
// (separable Smith G, no micro-Fresnel), times the macro dielectric Fresnel F(wo.n, fresnel_ior) when
// fresnel_ior > 0 (Glass BSDF's reflection at zero bounces); fresnel_ior 0: no Fresnel (Glossy BSDF).
struct MicrofacetLobe {
    Spectrum color;
    float alpha = 1;  // roughness^2
    float fresnel_ior = 0;
    bool beckmann = false;  // Cycles' Beckmann D and rational G1 instead of GGX (sampled by GGX normals)
    float probability = 0;  // chance of sampling this lobe
    // Anisotropic GGX (Anisotropic BSDF): alpha along the tangent, alpha_y across it (= alpha: isotropic); the
    // tangent turned about the normal by `rotation` turns, at the hit (cos, sin of its angle in the shading frame:
    // SetHitTangent).
    float alpha_y = 1;
    float rotation = 0;
    float tangent_cos = 1, tangent_sin = 0;
    bool anisotropic() const { return alpha_y != alpha; }
    // Cycles' multiple-scattering GGX (Glossy / Anisotropic BSDF of distribution Multiscatter GGX above the
    // singular roughness; multiscatter_ggx.h): `color` also tints each bounce.
    bool multiscatter = false;
    Spectrum bounce_color;
};
// Lobes one material holds: enough for a Mix / Add of glossy and glass shaders at distinct roughnesses.
constexpr int kMaxMicrofacetLobes = 4;

// A material's scattering as the integrator evaluates it: its lobes and their weights (made from a Material,
// material.h, by the Make*Bsdf functions below).
struct Bsdf {
    Spectrum diffuse;                // reflectance of the Lambert lobe (albedo): f = diffuse / pi; Principled:
                                     // the Burley lobe's weight x base colour
    Spectrum f0;                     // specular reflectance at normal incidence (0: no specular lobe);
                                     // Principled: Cycles' cspec0 (tinted dielectric F0 mixed with metal)
    float alpha = 1;                 // GGX roughness parameter
    float specular_probability = 0;  // chance of sampling the specular lobe in SampleBsdf
    bool glossy = false;             // anything beyond Lambert: needs the kGlossy kernel
    Spectrum emission;               // radiance emitted from both sides (emissive meshes); 0: none
    bool textured = false;           // images drive its inputs: a hit evaluates its Material (material.h)
    bool normal_mapped = false;      // RenderScene::normal_maps holds its map

    // Principled BSDF (Cycles 3.4).  Sheen and clearcoat cost only a flag test when absent.
    bool principled = false;
    bool has_specular = false;
    bool has_sheen = false;
    bool has_clearcoat = false;
    float burley_roughness = 0;  // the retro-reflection's roughness (Blender's, unsquared)
    // Diffuse BSDF of Roughness sigma > 0: Cycles 3.4's Oren-Nayar closure (bsdf_oren_nayar.h), f cos = |n.l| (a + b
    // t), its colour `oren_nayar`, a = 1 / (pi + (3 pi - 4) / 6 sigma), b = sigma a (OrenNayarFactor).  A diffuse lobe.
    bool has_oren_nayar = false;
    Spectrum oren_nayar;
    float oren_nayar_a = 0, oren_nayar_b = 0;
    float specular_ior = 1;           // the Fresnel blend's IOR, from Specular
    float specular_f0 = 0;            // its normal-incidence reflectance (0.08 specular)
    Spectrum sheen;                   // sheen weight x sheen colour (f = sheen (1 - wi.h)^5)
    float clearcoat = 0;              // 0.25 x Clearcoat, Cycles' weight of the clearcoat lobe
    float clearcoat_alpha = 1;        // GTR1 alpha = clearcoat roughness^2
    float clearcoat_probability = 0;  // chance of sampling the clearcoat lobe (the rest: cosine)
    // Principled Anisotropic: the specular's alpha across its tangent (alpha along it), the tangent's rotation in
    // turns (Anisotropic Rotation) and, at the hit, its angle in the shading frame (SetHitTangent).
    float specular_alpha_y = 1;
    float specular_rotation = 0;
    float specular_tangent_cos = 1, specular_tangent_sin = 0;
    // Some lobe is anisotropic: a hit needs the mesh's tangent (surface_hit.h, Cycles' radial default).
    bool anisotropic = false;
    // The specular is Cycles' multiple-scattering GGX (multiscatter_ggx.h): Multiscatter GGX above roughness 0.075.
    bool multiscatter = false;

    // Microfacet reflection lobes of their own (Glossy BSDF, a Glass BSDF's reflection), each
    // sampled with its own probability; Mix / Add Shader sums them (MixIntoBsdf).
    int num_lobes = 0;
    MicrofacetLobe lobes[kMaxMicrofacetLobes];
    // Mixes only: a Lambert lobe beside the Burley one (a Diffuse BSDF mixed with other shaders), and the
    // weight of the Principled specular (its Fresnel blend rises to white, so it cannot be folded into f0).
    Spectrum lambert;
    float specular_weight = 1;
    // Translucent BSDF (Cycles' CLOSURE_BSDF_TRANSLUCENT_ID): f = translucent / pi for wi on the side opposite wo,
    // sampled by the cosine about -n with this probability.  Its light arrives through the surface, so shading
    // takes samples on both sides (shade_surface.h).
    Spectrum translucent;
    float translucent_probability = 0;
    bool has_translucent = false;
    // A hit's Bsdf may have the translucent lobe: a Translucent BSDF is in the material, whatever its textures make of
    // it (has_translucent is the untextured values').  Without it a textured hit's light-tree receiver is known
    // before shading (TreeReceiverKnownEarly).
    bool may_be_translucent = false;
    // At a normal-mapped hit: the normal before the map, in the shading frame of the mapped one, which scales the
    // diffuse lobes by BumpShadowingTerm (Cycles does for closures labelled diffuse whose normal differs).
    bool bump_shadowing = false;
    Vec3f unmapped_normal;
    // Some lobe has a dielectric Fresnel (fresnel_ior > 0: glass): a hit on a back face uses 1 / ior, as Cycles'
    // glass closures do for SD_BACKFACING (BsdfAtHit).
    bool has_dielectric = false;
    // Holdout (Cycles' CLOSURE_HOLDOUT_ID): the share of the surface that is a hole in the image, black and of alpha
    // 0 where the camera sees it (the film's alpha is 1 - holdout there); its light reflection is the rest's.
    float holdout = 0;
    // Transparent BSDF (CLOSURE_BSDF_TRANSPARENT_ID), and Principled Alpha < 1 (Cycles expands it into a Mix Shader
    // with a white Transparent BSDF): the colour that camera and shadow rays keep passing straight through the surface
    // (integrator/transparency.h).  opaque_weight: the summed mix weights of the other shaders, which a camera ray
    // stopping at the surface shades (0 for a Transparent BSDF alone).
    Spectrum transparency;
    bool has_transparency = false;
    float opaque_weight = 1;
    // Singular lobes (singular.h): no light sample sees them; shading traces their mirror and refracted rays
    // (shade_surface.h, QueueSingularRays).  num_singular 0: nothing to do.
    int num_singular = 0;
    SingularLobe singular[kMaxSingularLobes];
};

// Adds lobe l to m's singular lobes, summed into an equal one; false when m holds kMaxSingularLobes others.
inline bool AddSingularLobe(Bsdf& m, const SingularLobe& l) {
    if (IsBlack(l.reflect) && IsBlack(l.refract)) return true;
    for (int i = 0; i < m.num_singular; ++i)
        if (SameSingularLobe(m.singular[i], l)) {
            m.singular[i].reflect += l.reflect;
            m.singular[i].refract += l.refract;
            return true;
        }
    if (m.num_singular == kMaxSingularLobes) return false;
    m.singular[m.num_singular++] = l;
    return true;
}

// The Principled BSDF node's inputs that are modelled (Blender 3.4's defaults).  Subsurface and
// transmission are not: the exporter warns about them.
struct PrincipledInputs {
    Spectrum base_color{0.8f, 0.8f, 0.8f};
    float metallic = 0;
    float specular = 0.5f;
    float specular_tint = 0;
    float roughness = 0.5f;
    float sheen = 0;
    float sheen_tint = 0.5f;
    float clearcoat = 0;
    float clearcoat_roughness = 0.03f;
    float anisotropic = 0;           // Cycles: alpha_x = r^2 / aspect, alpha_y = r^2 aspect, aspect = sqrt(1 - 0.9 a)
    float anisotropic_rotation = 0;  // turns about the normal
    bool multiscatter = false;       // the node's distribution Multiscatter GGX (else GGX)
    float diffuse_roughness = 0;     // the Diffuse BSDF's Roughness: 0 Lambert, else Oren-Nayar (MakeDiffuseBsdf)
    // Transmission t: its glass part, of weight t (1 - metallic), shows at zero bounces as a Glass BSDF's reflection
    // (IOR `ior`, the Fresnel of the view); the diffuse and sheen take (1 - metallic)(1 - t), the specular 1 - that
    // glass weight (svm_node_closure_bsdf).
    float transmission = 0;
    float ior = 1.45f;
};

// Lobe choice roughly by albedo (the sheen's is at most ~0.1 of its weight, the clearcoat's
// Fresnel starts at 0.04, a glass lobe's Fresnel at F0 or 0.04), each present lobe at least 10% of the samples;
// the cosine (Lambert, Burley, sheen) takes the rest.  Sets specular_, clearcoat_ and each lobe's probability.
inline void ChooseLobeProbabilities(Bsdf& m) {
    float w_cos = Luminance(m.lambert) + Luminance(m.diffuse) + 0.1f * Luminance(m.sheen) + Luminance(m.oren_nayar);
    float w_trans = m.has_translucent ? std::max(Luminance(m.translucent), 1e-6f) : 0.0f;
    float w_spec = m.has_specular ? std::max(Luminance(m.f0), 0.04f) * m.specular_weight : 0.0f;
    float w_coat = m.has_clearcoat ? std::max(0.1f * m.clearcoat, 1e-3f) : 0.0f;
    float w_lobe[kMaxMicrofacetLobes];
    int lobes = (w_cos > 0) + (w_spec > 0) + (w_coat > 0) + (w_trans > 0);
    for (int i = 0; i < m.num_lobes; ++i) {
        const MicrofacetLobe& l = m.lobes[i];
        const float fresnel = l.fresnel_ior > 0 ? std::max(DielectricFresnel(1, l.fresnel_ior), 0.04f) : 1.0f;
        w_lobe[i] = std::max(Luminance(l.color) * fresnel, 1e-6f);
        ++lobes;
    }
    if (lobes == 0) {
        w_cos = 1;  // black: sample the cosine, evaluate 0
    } else {
        float total = w_cos + w_spec + w_coat + w_trans;
        for (int i = 0; i < m.num_lobes; ++i) total += w_lobe[i];
        const float floor = 0.1f * total;
        if (w_trans > 0) w_trans = std::max(w_trans, floor);
        if (w_cos > 0) w_cos = std::max(w_cos, floor);
        if (w_spec > 0) w_spec = std::max(w_spec, floor);
        if (w_coat > 0) w_coat = std::max(w_coat, floor);
        for (int i = 0; i < m.num_lobes; ++i) w_lobe[i] = std::max(w_lobe[i], floor);
    }
    float sum = w_cos + w_spec + w_coat + w_trans;
    for (int i = 0; i < m.num_lobes; ++i) sum += w_lobe[i];
    m.specular_probability = w_spec / sum;
    m.translucent_probability = w_trans / sum;
    m.clearcoat_probability = w_coat / sum;
    for (int i = 0; i < m.num_lobes; ++i) m.lobes[i].probability = w_lobe[i] / sum;
}

// Blender material parameters -> Bsdf.  Roughness is clamped to 0.03 (alpha ~ 1e-3): a
// perfect mirror is a delta lobe that direct lighting from area lights cannot sample by lights.
// A Diffuse BSDF: Lambert at Roughness 0 (exactly 0, as svm_node_closure_bsdf tests it), else Cycles 3.4's
// Oren-Nayar (bsdf_oren_nayar_setup: sigma = saturate(roughness)), a lobe of the Principled evaluation (kGlossy
// kernel).
inline Bsdf MakeDiffuseBsdf(const Spectrum& base, float roughness = 0) {
    Bsdf m;
    if (roughness == 0) {
        m.diffuse = base;
        return m;
    }
    const float sigma = std::clamp(roughness, 0.0f, 1.0f);
    m.glossy = m.principled = true;
    m.has_oren_nayar = true;
    m.oren_nayar = base;
    m.oren_nayar_a = 1 / (kPi + ((3 * kPi - 4) / 6) * sigma);
    m.oren_nayar_b = sigma * m.oren_nayar_a;
    ChooseLobeProbabilities(m);
    return m;
}

inline Bsdf MakeLambertGgxBsdf(const Spectrum& base, float roughness, float metallic, float specular) {
    Bsdf m;
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

// A microfacet lobe of colour `color` and Blender roughness `roughness` (alpha = roughness^2); false (no
// lobe) when Cycles would not make one: black, or sharp -- Cycles' microfacet closures return 0 for
// alpha_x alpha_y <= 1e-7 (a delta lobe, which light samples cannot find: the caller's SingularLobe).
inline bool MakeMicrofacetLobe(const Spectrum& color, float roughness, float fresnel_ior, bool beckmann,
                               MicrofacetLobe& lobe) {
    const float r = std::clamp(roughness, 0.0f, 1.0f);
    lobe.alpha = lobe.alpha_y = r * r;
    lobe.color = color;
    lobe.fresnel_ior = fresnel_ior;
    lobe.beckmann = beckmann;
    return lobe.alpha * lobe.alpha > 1e-7f && !IsBlack(color);
}

// Cycles 3.4's closures of the Principled node (svm_node_closure_bsdf, CLOSURE_BSDF_PRINCIPLED_ID,
// its default GGX distribution = single-scatter GGX; no transmission): a Burley diffuse of weight
// (1 - metallic) base colour, sheen of weight (1 - metallic) sheen (mix(1, tint, sheen_tint), tint =
// base colour / its luminance), a GGX specular with Cycles' Fresnel blend of cspec0 = mix(0.08 specular
// mix(1, tint', specular_tint), base colour, metallic) (tint' normalised by 0.3 r + 0.6 g + 0.1 b) towards
// white by the dielectric Fresnel of IOR 2 / (1 - sqrt(0.08 specular)) - 1, and a clearcoat: GTR1 of
// alpha = clearcoat_roughness^2 with G at alpha 0.25, Fresnel of IOR 1.5, weight 0.25 clearcoat.
// Roughnesses are clamped to 0.03 as in MakeLambertGgxBsdf, but a sharp specular, clearcoat or glass (Cycles'
// singular closures, IsSingularRoughness) is a SingularLobe.
inline Bsdf MakePrincipledBsdf(const PrincipledInputs& in) {
    constexpr float kCutoff = 1e-5f;  // Cycles' CLOSURE_WEIGHT_CUTOFF: lobes below it are not made
    Bsdf m;
    m.glossy = m.principled = true;
    const Spectrum base = in.base_color;
    const float metallic = std::clamp(in.metallic, 0.0f, 1.0f);
    const float specular = std::clamp(in.specular, 0.0f, 1.0f);
    const float roughness = std::clamp(in.roughness, 0.0f, 1.0f);
    const float transmission = std::clamp(in.transmission, 0.0f, 1.0f);
    const float diffuse_weight = (1 - metallic) * (1 - transmission);
    const float glass_weight = transmission * (1 - metallic);
    m.specular_weight = 1 - glass_weight;
    if (glass_weight > kCutoff) {  // Cycles' refl_roughness: unclamped; a sharp one is singular
        const Spectrum white(glass_weight, glass_weight, glass_weight);
        MicrofacetLobe& l = m.lobes[m.num_lobes];
        if (MakeMicrofacetLobe(white, roughness, std::max(in.ior, 1e-5f), false, l)) {
            ++m.num_lobes;
        } else if (IsSingularRoughness(roughness)) {  // the refraction: base colour x glass weight x (1 - F)
            AddSingularLobe(m, {white, base * glass_weight, std::max(in.ior, 1e-5f), SingularFresnel::kDielectric, {}});
        }
        m.has_dielectric = m.num_lobes > 0 || m.num_singular > 0;
    }
    if (diffuse_weight > kCutoff && std::abs(base.x + base.y + base.z) / 3 > kCutoff) {
        m.diffuse = base * diffuse_weight;
        m.burley_roughness = roughness;
    }
    const float sheen = std::max(in.sheen, 0.0f);
    if (diffuse_weight > kCutoff && sheen > kCutoff) {
        const float lum = Luminance(base);  // Cycles: linear_rgb_to_gray, Rec.709 in Blender's default config
        const Spectrum tint = lum > 0 ? base / lum : Spectrum(1, 1, 1);
        const float st = in.sheen_tint;
        m.sheen = (Spectrum(1 - st, 1 - st, 1 - st) + tint * st) * (sheen * diffuse_weight);
        m.has_sheen = !IsBlack(m.sheen);
    }
    const bool sharp_specular = IsSingularRoughness(roughness);  // (anisotropy keeps alpha_x alpha_y = r^4)
    if (m.specular_weight > kCutoff && (specular > kCutoff || metallic > kCutoff)) {
        m.has_specular = !sharp_specular;
        const float r = std::max(roughness, 0.03f);
        m.alpha = m.specular_alpha_y = r * r;
        if (in.anisotropic != 0) {  // svm_node_closure_bsdf (Principled): aspect = sqrt(1 - 0.9 anisotropic)
            const float aspect = SafeSqrt(1 - 0.9f * std::min(in.anisotropic, 1.0f));
            m.alpha = std::min(r * r / aspect, 1.0f);  // bsdf_microfacet_ggx_setup: saturate
            m.specular_alpha_y = std::min(r * r * aspect, 1.0f);
            m.specular_rotation = in.anisotropic_rotation;
            m.anisotropic = m.alpha != m.specular_alpha_y;
        }
        m.multiscatter = in.multiscatter && roughness > 0.075f;  // Cycles: single-scatter GGX at or below
        m.specular_ior = 2 / (1 - std::sqrt(0.08f * specular)) - 1;
        m.specular_f0 = DielectricFresnel(1, m.specular_ior);
        const float lum = 0.3f * base.x + 0.6f * base.y + 0.1f * base.z;  // Cycles' approximation here
        const Spectrum tint = lum > 0 ? base / lum : Spectrum(1, 1, 1);
        const float t = in.specular_tint;
        const Spectrum tinted = (Spectrum(1 - t, 1 - t, 1 - t) + tint * t) * (0.08f * specular);
        const Spectrum c = tinted * (1 - metallic) + base * metallic;
        m.f0 = {std::clamp(c.x, 0.0f, 1.0f), std::clamp(c.y, 0.0f, 1.0f), std::clamp(c.z, 0.0f, 1.0f)};
        if (sharp_specular) {  // bsdf_microfacet_ggx's singular branch: weight x reflection_color
            const float w = m.specular_weight;
            AddSingularLobe(m, {Spectrum(w, w, w), {}, m.specular_ior, SingularFresnel::kBlend, m.f0});
            m.multiscatter = false;
        }
    }
    if (in.clearcoat > kCutoff) {
        m.clearcoat = 0.25f * in.clearcoat;
        if (IsSingularRoughness(in.clearcoat_roughness)) {  // Cycles' clearcoat: IOR 1.5, cspec0 0.04
            const float w = m.clearcoat;
            AddSingularLobe(m, {Spectrum(w, w, w), {}, 1.5f, SingularFresnel::kBlend, Spectrum(0.04f, 0.04f, 0.04f)});
            m.clearcoat = 0;
        } else {
            m.has_clearcoat = true;
            const float r = std::clamp(in.clearcoat_roughness, 0.03f, 1.0f);
            m.clearcoat_alpha = r * r;
        }
    }
    ChooseLobeProbabilities(m);
    return m;
}

// Cycles 3.4's Translucent BSDF: Lambertian transmission, f = colour / pi towards the other side of the surface
// (bsdf_translucent_eval), what a zero-bounce render shows of a thin surface lit from behind.
inline Bsdf MakeTranslucentBsdf(const Spectrum& color) {
    Bsdf m;
    m.glossy = m.principled = true;
    m.translucent = color;
    m.has_translucent = !IsBlack(color);
    ChooseLobeProbabilities(m);
    return m;
}

// Blender's Holdout shader: black, and the camera sees a hole (alpha 0) where it is.
inline Bsdf MakeHoldoutBsdf() {
    Bsdf m;
    m.holdout = 1;
    return m;
}

// Blender's Transparent BSDF: nothing reflected; camera and shadow rays go on through it, filtered by `color`.
inline Bsdf MakeTransparentBsdf(const Spectrum& color) {
    Bsdf m;
    m.transparency = color;
    m.has_transparency = !IsBlack(color);
    m.opaque_weight = 0;
    return m;
}

// The material a Mix / Add Shader starts from, before MixIntoBsdf adds its parts: black, opaque only where a
// part is.
inline Bsdf MakeEmptyMixBsdf() {
    Bsdf m = MakeDiffuseBsdf({});
    m.opaque_weight = 0;
    return m;
}

// A material of microfacet lobes only (Glass, Glossy BSDF): one lobe or none (black).
// A sharp one: a singular lobe (a glass's reflection and refraction, each closure's colour x its Fresnel).
inline Bsdf MakeSingleLobeBsdf(const Spectrum& color, float roughness, float fresnel_ior, bool beckmann) {
    Bsdf m;
    m.glossy = m.principled = true;
    if (MakeMicrofacetLobe(color, roughness, fresnel_ior, beckmann, m.lobes[0])) {
        m.num_lobes = 1;
    } else if (IsSingularRoughness(roughness)) {
        const bool glass = fresnel_ior > 0;
        AddSingularLobe(m, {color,
                            glass ? color : Spectrum(),
                            glass ? fresnel_ior : 1.0f,
                            glass ? SingularFresnel::kDielectric : SingularFresnel::kNone,
                            {}});
    }
    m.has_dielectric = (m.num_lobes > 0 || m.num_singular > 0) && fresnel_ior > 0;
    ChooseLobeProbabilities(m);
    return m;
}

// Cycles 3.4's Glass BSDF (svm_node_closure_bsdf, CLOSURE_BSDF_MICROFACET_{GGX,BECKMANN}_GLASS_ID) as a
// direct-light-only render sees it: the reflection closure colour x F(wo.n, ior)
// (fresnel_dielectric_cos of the view), GGX of alpha = roughness^2 with separable Smith G and no
// micro-Fresnel; the refraction closure (colour x (1 - F)) needs a second bounce or a light behind an
// open surface, neither modelled here (black).  A sharp glass is a SingularLobe, whose reflected and refracted
// rays shading traces (shade_surface.h).  ior is the
// front side's: a back face takes 1 / ior at the hit (BsdfAtHit), as in Cycles.
// beckmann: Cycles' Beckmann distribution (the node's default), evaluated with its D and rational G1, sampled
// by GGX visible normals of the same alpha (the pdf is that of the sampling: unbiased).
inline Bsdf MakeGlassBsdf(const Spectrum& color, float roughness, float ior, bool beckmann = false) {
    return MakeSingleLobeBsdf(color, roughness, std::max(ior, 1e-5f), beckmann);  // Cycles' fmaxf(ior, 1e-5)
}

// Cycles 3.4's Glossy BSDF (CLOSURE_BSDF_MICROFACET_{GGX,BECKMANN}_ID): colour x the microfacet reflection
// with no Fresnel at all (the node's Color is its reflectance at every angle).
// anisotropy, rotation: Blender's Anisotropic BSDF (svm_node_closure_bsdf with a tangent): alpha = roughness^2
// stretched along the tangent by 1 / (1 - a) across and (1 - a) along it for a >= 0 (a clamped to +-0.99; negative
// swaps them), the tangent turned by `rotation` turns.  GGX only (Beckmann stays isotropic: the exporter warns).
// multiscatter: the distribution Multiscatter GGX (GGX's lobe shape from its random walk: MicrofacetLobe).
inline Bsdf MakeGlossyBsdf(const Spectrum& color, float roughness, bool beckmann = false, float anisotropy = 0,
                           float rotation = 0, bool multiscatter = false) {
    Bsdf m = MakeSingleLobeBsdf(color, roughness, 0, beckmann);
    if (m.num_lobes == 0 || beckmann) return m;
    MicrofacetLobe& l = m.lobes[0];
    if (multiscatter) {  // bsdf_microfacet_multi_ggx_common_setup: the colour saturated, alpha >= 1e-4
        l.multiscatter = true;
        l.bounce_color = {std::clamp(color.x, 0.0f, 1.0f), std::clamp(color.y, 0.0f, 1.0f),
                          std::clamp(color.z, 0.0f, 1.0f)};
    }
    if (anisotropy == 0) return m;
    const float a = std::clamp(anisotropy, -0.99f, 0.99f), r2 = l.alpha;
    l.alpha = std::min(a < 0 ? r2 / (1 + a) : r2 * (1 - a), 1.0f);
    l.alpha_y = std::min(a < 0 ? r2 * (1 + a) : r2 / (1 - a), 1.0f);
    l.rotation = rotation;
    m.anisotropic = l.anisotropic();
    return m;
}

// A hit's tangent (unit, in the shading frame: z = 0) given to the material's anisotropic lobes, each turned by
// its rotation about the normal (Cycles' rotate_around_axis(T, N, rotation 2 pi)).
inline void SetHitTangent(Bsdf& m, const Vec3f& tangent) {
    const float base = std::atan2(tangent.y, tangent.x);
    auto turned = [&](float rotation, float& c, float& s) {
        const float angle = base + 2 * kPi * rotation;
        c = std::cos(angle);
        s = std::sin(angle);
    };
    if (m.has_specular && m.alpha != m.specular_alpha_y)
        turned(m.specular_rotation, m.specular_tangent_cos, m.specular_tangent_sin);
    for (int i = 0; i < m.num_lobes; ++i)
        if (m.lobes[i].anisotropic()) turned(m.lobes[i].rotation, m.lobes[i].tangent_cos, m.lobes[i].tangent_sin);
}

}  // namespace sphrect::render
