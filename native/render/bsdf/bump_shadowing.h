// The shadow-terminator term of diffuse lobes at normal-mapped hits.
#pragma once

#include "render/sampling_util.h"

namespace sphrect::render {

// Cycles' bump_shadowing_term (Chiang et al., "Taming the Shadow Terminator", 2019): the smooth falloff of
// diffuse light where a perturbed normal n (here +z) faces a light that the unperturbed normal n0 sees at
// grazing angles; g = (n0.wi) / ((n.wi) (n0.n)), the term 1 outside g in [0, 1).
inline float BumpShadowingTerm(const Vec3f& n0, const Vec3f& wi) {
    const float denominator = wi.z * n0.z;
    if (denominator == 0) return 1;
    const float g = Dot(n0, wi) / denominator;
    if (!(g >= 0 && g < 1)) return 1;
    return g + g * g - g * g * g;
}

}  // namespace sphrect::render
