// How a light sample chooses its emitter: the names the renderer offers and their list.
//   power  area lights by power (LightSelector), point and spot lights each once per camera sample;
//   tree   every area, point and spot light through the light tree (LightTree: power, distance
//          and orientation at the shading point), one emitter per light sample;
//   ris    at surface hits, RenderOptions::ris_candidates candidates drawn as `tree` draws its sample, one kept by
//          resampled importance sampling on its unshadowed contribution (integrator/resampled_light_choice.h);
//          scattering points in media choose as `tree`.
// Suns are evaluated once per camera sample with each.
#pragma once

#include <array>

namespace sphrect::render {

enum class LightSelection { Power, Tree, Ris };

constexpr std::array<LightSelection, 3> kAllLightSelections = {LightSelection::Power, LightSelection::Tree,
                                                               LightSelection::Ris};

constexpr const char* LightSelectionName(LightSelection s) {
    switch (s) {
        case LightSelection::Power: return "power";
        case LightSelection::Tree: return "tree";
        case LightSelection::Ris: return "ris";
    }
    return "?";
}

// Whether the light tree proposes the emitters (`ris` resamples the tree's proposals).
constexpr bool ChoosesByLightTree(LightSelection s) { return s != LightSelection::Power; }

}  // namespace sphrect::render
