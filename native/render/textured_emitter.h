// An area light of an emissive mesh whose emission an image drives (Material::textures[kEmission]): which triangles
// it is made of, to find the texture coordinates of a point on it, and, for a rectangle, the power of its blocks,
// by which light samples choose where on it to go (core/rectangle_blocks.h).  Evaluated by textured_emission.h.
#pragma once

#include <cstdint>
#include <vector>

#include "core/rectangle_blocks.h"
#include "sampling_util.h"

namespace sphrect::render {

struct TexturedEmitter {
    int material = 0;  // its Material: the lookup is textures[kEmission], the multiplier `emission`
    uint32_t mesh = 0;
    uint32_t triangles[2] = {0, 0};  // the light's triangles of that mesh (a rectangle: two)
    int num_triangles = 1;
    // Rectangles: nx x ny blocks (at most kMaxRectangleBlocksPerSide per side) and each one's mean luminance, with a
    // floor (scene_textured_emitters.cpp).
    int nx = 0, ny = 0;
    std::vector<float> block_radiance;
    RectangleBlocks Blocks() const { return {nx, ny, block_radiance.data()}; }
};

}  // namespace sphrect::render
