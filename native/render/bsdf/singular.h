// Singular (delta) lobes: a sharp mirror, a sharp glass's reflection and refraction.  Cycles 3.4 evaluates them as 0
// for every light sample (bsdf_reflection.h, bsdf_refraction.h, bsdf_microfacet.h below alpha_x alpha_y 1e-7), but
// still traces their one direction at max_bounces 0 (path_state_next only marks the ray to end after its next hit)
// and adds the emission it finds there with MIS skipped: weight closure x eval / pdf = the closure's weight.
#pragma once

#include <algorithm>
#include <cmath>

#include "principled_lobes.h"
#include "render/sampling_util.h"

namespace sphrect::render {

// Whether a microfacet closure of Blender roughness `roughness` (alpha_x alpha_y = roughness^4) is a delta lobe in
// Cycles 3.4 (the microfacet closures' alpha_x * alpha_y <= 1e-7 test).
inline bool IsSingularRoughness(float roughness) {
    const float r = std::clamp(roughness, 0.0f, 1.0f);
    return r * r * r * r <= 1e-7f;
}

// How a singular lobe's reflection weight depends on the view (Cycles' closure weight x reflection_color):
// kNone: its colour alone (Glossy BSDF); kDielectric: x F(wo.n, ior), the refraction x max(1e-4, 1 - F) (Glass BSDF,
// a Principled glass); kBlend: x cspec0 blended towards white by the rise of F(wo.n, ior) above F(1, ior)
// (interpolate_fresnel_color: the Principled specular, its clearcoat).
enum class SingularFresnel : uint8_t { kNone, kDielectric, kBlend };

struct SingularLobe {
    Spectrum reflect;  // the reflection closure's weight (mix weights included)
    Spectrum refract;  // kDielectric: the refraction closure's weight before its Fresnel (0: none)
    float ior = 1;     // relative IOR; a glass seen from its back face takes 1 / ior (HitSpecificBsdf)
    SingularFresnel fresnel = SingularFresnel::kNone;
    Spectrum cspec0;  // kBlend: the colour at normal incidence
};
// Lobes one material holds: a Mix of a few sharp glossy / glass shaders, or a Principled's specular, clearcoat and
// glass.
constexpr int kMaxSingularLobes = 4;

// Whether two lobes of a mix are one (their weights summed).
inline bool SameSingularLobe(const SingularLobe& a, const SingularLobe& b) {
    return a.fresnel == b.fresnel && (a.fresnel == SingularFresnel::kNone || a.ior == b.ior) &&
           a.cspec0.x == b.cspec0.x && a.cspec0.y == b.cspec0.y && a.cspec0.z == b.cspec0.z;
}

// A singular lobe's rays for the view wo (shading frame, wo.z > 0): the mirror direction with its weight, and for a
// glass the refracted direction (none past the critical angle: total internal reflection, where F = 1).
struct SingularScatter {
    Vec3f reflect_dir;
    Spectrum reflect_weight;
    bool refracts = false;
    Vec3f refract_dir;
    Spectrum refract_weight;
};

// The refracted direction of wo (wo.z > 0) into a medium of relative IOR eta (Cycles' fresnel_dielectric seen from
// outside); false at total internal reflection.
inline bool RefractSingular(const Vec3f& wo, float eta, Vec3f& wi) {
    const float inv = 1 / eta;
    const float arg = 1 - inv * inv * (1 - wo.z * wo.z);
    if (arg < 0) return false;
    const float cos_t = std::max(std::sqrt(arg), 1e-7f);
    wi = Vec3f(-inv * wo.x, -inv * wo.y, -cos_t);
    return true;
}

inline SingularScatter ScatterSingular(const SingularLobe& l, const Vec3f& wo) {
    SingularScatter s;
    s.reflect_dir = Vec3f(-wo.x, -wo.y, wo.z);
    switch (l.fresnel) {
        case SingularFresnel::kNone: s.reflect_weight = l.reflect; break;
        case SingularFresnel::kBlend:
            s.reflect_weight = l.reflect * InterpolatedFresnel(wo.z, l.ior, DielectricFresnel(1, l.ior), l.cspec0);
            break;
        case SingularFresnel::kDielectric: {
            const float f = DielectricFresnel(wo.z, l.ior);
            s.reflect_weight = l.reflect * f;
            if (!IsBlack(l.refract) && RefractSingular(wo, l.ior, s.refract_dir)) {
                s.refracts = true;
                s.refract_weight = l.refract * std::max(1e-4f, 1 - f);
            }
            break;
        }
    }
    return s;
}

}  // namespace sphrect::render
