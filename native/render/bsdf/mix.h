// Mix / Add Shader: a Bsdf that holds the weighted sum of other Bsdfs' lobes.
#pragma once

#include <stdexcept>
#include <string>

#include "make_bsdf.h"

namespace sphrect::render {

// Whether a mix holds two microfacet lobes as one (their colours summed): the same shape, Fresnel and distribution
// (a multiple-scattering one also the same colour, which tints each bounce).
inline bool SameMicrofacetLobe(const MicrofacetLobe& a, const MicrofacetLobe& b) {
    return a.alpha == b.alpha && a.alpha_y == b.alpha_y && a.rotation == b.rotation && a.fresnel_ior == b.fresnel_ior &&
           a.beckmann == b.beckmann && a.multiscatter == b.multiscatter &&
           (!b.multiscatter || (a.bounce_color.x == b.bounce_color.x && a.bounce_color.y == b.bounce_color.y &&
                                a.bounce_color.z == b.bounce_color.z));
}

// What MixIntoBsdf does with a part the mix cannot hold: throw std::invalid_argument (building a scene), or, at
// a textured hit (whose Material was checked with kThrow on its untextured values, so this is the rare case of
// textures making lobes that merged there distinct), keep what fits: the part's Principled lobes dropped, an
// extra microfacet lobe added to the last one.  Never throws.
enum class MixOverflow { kThrow, kLenient };

// Mix / Add Shader (svm_node_mix_closure: each side's closures scaled by its weight, (1 - fac) and fac;
// Add: 1 and 1): `part`'s lobes scaled by `weight` and added to `mix`.  A mix holds Lambert lobes (summed),
// at most one Principled BSDF's lobes (Burley, sheen, specular, clearcoat) and kMaxMicrofacetLobes microfacet
// lobes (equal ones merged); what does not fit, and the former 'glossy' model, are kPolicy's.
// Emission is the caller's (RenderScene::MakeMaterialBsdf).
template <MixOverflow kPolicy = MixOverflow::kThrow>
inline void MixIntoBsdf(Bsdf& mix, const Bsdf& part, float weight) {
    constexpr bool kThrows = kPolicy == MixOverflow::kThrow;
    if constexpr (kThrows) {
        if (!(weight >= 0) || !std::isfinite(weight)) throw std::invalid_argument("a mix layer's weight must be >= 0");
        if (part.glossy && !part.principled)
            throw std::invalid_argument("the 'glossy' model cannot be mixed (use 'principled')");
    }
    mix.holdout += part.holdout * weight;
    mix.opaque_weight += part.opaque_weight * weight;
    if (part.has_transparency) {
        mix.transparency += part.transparency * weight;
        mix.has_transparency = !IsBlack(mix.transparency);
    }
    if (!part.principled) {  // Lambert
        if (!IsBlack(part.diffuse)) mix.glossy = mix.principled = true;
        mix.lambert += part.diffuse * weight;
        ChooseLobeProbabilities(mix);
        return;
    }
    mix.glossy = mix.principled = true;
    mix.lambert += part.lambert * weight;
    if (part.has_oren_nayar) {  // two of different roughness: their parameters weighted by their colours' luminance
        const float w_mix = Luminance(mix.oren_nayar), w_part = Luminance(part.oren_nayar) * weight;
        const float t = w_mix + w_part > 0 ? w_part / (w_mix + w_part) : 1.0f;
        mix.oren_nayar_a += (part.oren_nayar_a - mix.oren_nayar_a) * (mix.has_oren_nayar ? t : 1.0f);
        mix.oren_nayar_b += (part.oren_nayar_b - mix.oren_nayar_b) * (mix.has_oren_nayar ? t : 1.0f);
        mix.oren_nayar += part.oren_nayar * weight;
        mix.has_oren_nayar = true;
    }
    mix.has_dielectric = mix.has_dielectric || part.has_dielectric;
    mix.anisotropic = mix.anisotropic || part.anisotropic;
    if (part.has_translucent) {
        mix.translucent += part.translucent * weight;
        mix.has_translucent = true;
    }
    const bool part_has_principled =
        !IsBlack(part.diffuse) || part.has_sheen || part.has_specular || part.has_clearcoat;
    const bool mix_has_principled = !IsBlack(mix.diffuse) || mix.has_sheen || mix.has_specular || mix.has_clearcoat;
    if (part_has_principled && mix_has_principled && kThrows)
        throw std::invalid_argument("a mix holds at most one Principled BSDF");
    if (part_has_principled && !mix_has_principled) {
        mix.diffuse = part.diffuse * weight;
        mix.burley_roughness = part.burley_roughness;
        mix.has_sheen = part.has_sheen;
        mix.sheen = part.sheen * weight;
        mix.has_specular = part.has_specular;
        mix.alpha = part.alpha;
        mix.specular_alpha_y = part.specular_alpha_y;
        mix.specular_rotation = part.specular_rotation;
        mix.multiscatter = part.multiscatter;
        mix.specular_ior = part.specular_ior;
        mix.specular_f0 = part.specular_f0;
        mix.f0 = part.f0;
        mix.specular_weight = part.specular_weight * weight;
        mix.has_clearcoat = part.has_clearcoat;
        mix.clearcoat = part.clearcoat * weight;
        mix.clearcoat_alpha = part.clearcoat_alpha;
    }
    for (int i = 0; i < part.num_lobes; ++i) {
        MicrofacetLobe lobe = part.lobes[i];
        lobe.color = lobe.color * weight;
        int j = 0;
        while (j < mix.num_lobes && !SameMicrofacetLobe(mix.lobes[j], lobe)) ++j;
        if (j < mix.num_lobes) {
            mix.lobes[j].color += lobe.color;
        } else if (mix.num_lobes < kMaxMicrofacetLobes) {
            mix.lobes[mix.num_lobes++] = lobe;
        } else if constexpr (kThrows) {
            throw std::invalid_argument("a mix holds at most " + std::to_string(kMaxMicrofacetLobes) +
                                        " distinct glossy / glass lobes");
        } else {
            mix.lobes[kMaxMicrofacetLobes - 1].color += lobe.color;
        }
    }
    for (int i = 0; i < part.num_singular; ++i) {
        SingularLobe lobe = part.singular[i];
        lobe.reflect = lobe.reflect * weight;
        lobe.refract = lobe.refract * weight;
        if (AddSingularLobe(mix, lobe)) continue;
        if constexpr (kThrows)
            throw std::invalid_argument("a mix holds at most " + std::to_string(kMaxSingularLobes) +
                                        " distinct sharp glossy / glass lobes");
    }
    ChooseLobeProbabilities(mix);
}

}  // namespace sphrect::render
