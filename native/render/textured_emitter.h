// An area light whose emission an image drives: an emissive mesh's (Material::textures[kEmission]) or a rectangle or
// ellipse light's own (a Blender light's node tree).  What it reads -- the lookup and the multiplier of its colour --,
// where a point of it finds its texture coordinates, and, for a rectangle, the power of its blocks, by which light
// samples choose where on it to go (core/rectangle_blocks.h).  Evaluated by textured_emission.h.
#pragma once

#include <cstdint>
#include <vector>

#include "core/rectangle_blocks.h"
#include "sampling_util.h"
#include "texture.h"

namespace sphrect::render {

struct TexturedEmitter {
    // The radiance at a point is multiplier x the lookup's colour there (clamped to >= 0): a mesh's material's
    // emission and emission texture, or a light's radiance and its texture.
    TextureLookup lookup;
    Spectrum multiplier;
    // A rectangle or ellipse light's own texture: its coordinates are the point's along the light's edges, (a, b, 0)
    // in [0, 1]^2 from its corner (an ellipse's bounding rectangle's), which the lookup's transform maps to the
    // node tree's (the exporter's).  Otherwise a mesh's triangles, interpolating the mesh's coordinates.
    bool on_light_plane = false;
    int material = 0;  // a mesh's: its Material (camera rays read the emission through it)
    // A mesh whose material's emission a node program drives (Material::programs[kEmission]; `lookup` unused): the
    // radiance is multiplier x the program's colour at the point (textured_emission.h).
    bool programmed = false;
    uint32_t mesh = 0;
    uint32_t triangles[2] = {0, 0};  // the light's triangles of that mesh (a rectangle: two)
    int num_triangles = 1;
    // Rectangles: nx x ny blocks (at most kMaxRectangleBlocksPerSide per side) and each one's mean luminance, with a
    // floor (scene_textured_emitters.cpp); none (nx = 0) for a light with spread, sampled on its clipped part.
    int nx = 0, ny = 0;
    std::vector<float> block_radiance;
    bool HasBlocks() const { return nx > 0; }
    RectangleBlocks Blocks() const { return {nx, ny, block_radiance.data()}; }
};

}  // namespace sphrect::render
