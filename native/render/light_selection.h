// How a light sample chooses its emitter: the names the renderer offers and their list.
//   power  area lights by power (LightSelector), point and spot lights each once per camera sample;
//   tree   every area, point and spot light through the light tree (LightTree: power, distance
//          and orientation at the shading point), one emitter per light sample.
// Suns are evaluated once per camera sample with either.
#pragma once

#include <array>

namespace sphrect::render {

enum class LightSelection { Power, Tree };

constexpr std::array<LightSelection, 2> kAllLightSelections = {LightSelection::Power, LightSelection::Tree};

constexpr const char* LightSelectionName(LightSelection s) {
    switch (s) {
        case LightSelection::Power: return "power";
        case LightSelection::Tree: return "tree";
    }
    return "?";
}

}  // namespace sphrect::render
