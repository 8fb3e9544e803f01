// Blender's Object Properties > Visibility > Ray Visibility as Cycles 3.4 honours it (its PATH_RAY_* visibility
// flags, scene/object.cpp and scene/light.cpp): which rays see a mesh -- Embree's geometry mask, matched against each
// ray's mask, any common bit -- and what a light lights: the closures of a BSDF by class (a light sample evaluates
// only the closures it is visible to, kernel/integrator/surface_shader.h's _surface_shader_exclude), the rays that
// find it (kernel/integrator/shade_light.h: a BSDF ray of a class the light hides from does not), the medium; and a
// light's Cast Shadow and Multiple Importance.
#pragma once

#include <cstdint>

namespace sphrect::render {

// A ray's kind, and the kinds of rays a mesh is visible to (bits).  A BSDF ray is of its lobe's class: diffuse
// (Lambert, Burley, sheen), glossy (microfacet reflection), diffuse | transmission (translucent), as Cycles' labels
// make it; a phase ray volume_scatter.
enum RayKind : uint8_t {
    kRayCamera = 1,
    kRayShadow = 2,
    kRayDiffuse = 4,
    kRayGlossy = 8,
    kRayTransmission = 16,
    kRayVolumeScatter = 32,
};
constexpr uint8_t kRayAll = 63;
// The closure classes a light can hide from (SHADER_EXCLUDE_DIFFUSE, _GLOSSY, _TRANSMIT).
constexpr uint8_t kRayBsdfClasses = kRayDiffuse | kRayGlossy | kRayTransmission;
// The names of the bits, lowest first: the scene files' and Blender's (visible_<name>).
inline constexpr const char* kRayKindNames[] = {"camera", "shadow",       "diffuse",
                                                "glossy", "transmission", "volume_scatter"};

// What a light lights and how (Cycles 3.4's light shader flags).  Its camera visibility is the light's `visible`.
struct LightVisibility {
    uint8_t rays = kRayAll;   // the ray kinds and closure classes it lights (diffuse, glossy, transmission, scatter)
    bool cast_shadow = true;  // false: its light samples trace no shadow ray (SHADER_CAST_SHADOW)
    bool use_mis = true;      // false: BSDF and phase rays do not find it, its samples weigh 1 (SHADER_USE_MIS)
    bool IsDefault() const { return rays == kRayAll && cast_shadow && use_mis; }
    // Whether a BSDF or phase ray of kind `ray` finds the light: kernel/integrator/shade_light.h skips it if it hides
    // from any of the ray's kinds (a translucent ray is diffuse and transmission).
    bool FoundBy(uint8_t ray) const { return use_mis && (ray & ~rays) == 0; }
    // The mask of its light samples' shadow rays: 0 (nothing blocks them) without Cast Shadow.
    unsigned ShadowMask() const { return cast_shadow ? unsigned(kRayShadow) : 0u; }
};

}  // namespace sphrect::render
