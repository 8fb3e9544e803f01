// Blender's Object Properties > Visibility > Ray Visibility as Cycles 3.4 honours it (its PATH_RAY_* visibility
// flags, scene/object.cpp and scene/light.cpp): which rays see a mesh -- Embree's geometry mask, matched against each
// ray's mask, any common bit -- and what a light lights: the closures of a BSDF by class (a light sample evaluates
// only the closures it is visible to, kernel/integrator/surface_shader.h's _surface_shader_exclude), the rays that
// find it (kernel/integrator/shade_light.h: a BSDF ray of a class the light hides from does not), the medium; and a
// light's Cast Shadow and Multiple Importance.
#pragma once

#include <cstdint>

#include "svm/program.h"

namespace sphrect::render {

// A ray's kind, and the kinds of rays a mesh is visible to (bits).  A BSDF ray is of its lobe's class: diffuse
// (Lambert, Burley, sheen), glossy (microfacet reflection), diffuse | transmission (translucent), as Cycles' labels
// make it; a phase ray volume_scatter.
constexpr uint8_t kRayCamera = 1, kRayShadow = 2, kRayDiffuse = 4, kRayGlossy = 8, kRayTransmission = 16,
                  kRayVolumeScatter = 32;
constexpr uint8_t kRayAll = 63;
// The closure classes a light can hide from (SHADER_EXCLUDE_DIFFUSE, _GLOSSY, _TRANSMIT).
constexpr uint8_t kRayBsdfClasses = kRayDiffuse | kRayGlossy | kRayTransmission;
// The names of the bits, lowest first: the scene files' and Blender's (visible_<name>).
inline constexpr const char* kRayKindNames[] = {"camera", "shadow",       "diffuse",
                                                "glossy", "transmission", "volume_scatter"};

// The Light Path node's flags (svm::RayFlag) of a BSDF or phase ray of kind `ray`, as Cycles' path_state_next sets
// them from the sampled lobe's label: a reflection or a transmission (translucent), diffuse or glossy; a phase ray's
// volume scatter.  (A singular lobe's kRayIsSingular is not told apart from a glossy one here: ScatteredRayFlagsOf.)
constexpr uint8_t ScatteredRayFlags(uint8_t ray) {
    if (ray & kRayVolumeScatter) return svm::kRayIsVolumeScatter;
    const uint8_t lobe = (ray & kRayDiffuse) ? svm::kRayIsDiffuse : svm::kRayIsGlossy;
    return uint8_t(lobe | ((ray & kRayTransmission) ? svm::kRayIsTransmission : svm::kRayIsReflection));
}

// What a light lights and how (Cycles 3.4's light shader flags), in one byte so that a light of the default
// visibility costs shading one comparison.  Its camera visibility is the light's `visible`.
class LightVisibility {
  public:
    static constexpr uint8_t kCastShadow = 64, kUseMis = 128;
    LightVisibility() = default;
    // rays: the ray kinds and closure classes it lights (diffuse, glossy, transmission, volume scatter); cast_shadow
    // false: its light samples trace no shadow ray (SHADER_CAST_SHADOW); use_mis false: BSDF and phase rays do not
    // find it and its samples weigh 1 (SHADER_USE_MIS).
    LightVisibility(uint8_t rays, bool cast_shadow, bool use_mis)
        : bits_(uint8_t((rays & kRayAll) | (cast_shadow ? kCastShadow : 0) | (use_mis ? kUseMis : 0))) {}
    uint8_t rays() const { return bits_ & kRayAll; }
    bool cast_shadow() const { return bits_ & kCastShadow; }
    bool use_mis() const { return bits_ & kUseMis; }
    bool IsDefault() const { return bits_ == 0xff; }
    // Whether a BSDF or phase ray of kind `ray` finds the light: kernel/integrator/shade_light.h skips it if it hides
    // from any of the ray's kinds (a translucent ray is diffuse and transmission).
    bool FoundBy(uint8_t ray) const { return use_mis() && (ray & ~rays()) == 0; }
    // The mask of its light samples' shadow rays: 0 (nothing blocks them) without Cast Shadow.
    unsigned ShadowMask() const { return cast_shadow() ? kRayShadow : 0u; }

  private:
    uint8_t bits_ = 0xff;
};

}  // namespace sphrect::render
