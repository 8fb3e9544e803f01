// The attributes Cycles 3.4 computes from a Blender mesh when a shader reads them (blender/mesh.cpp:
// attr_create_pointiness, attr_create_random_per_island), per vertex of the mesh as Blender gives it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/sampling_util.h"

namespace sphrect::render::svm {

// Geometry > Pointiness: per vertex, the angle between its normal and the mean direction of its edges, over pi
// (0.5 on flat ground, above on convex corners), blurred once over its neighbours; vertices at one position count
// as one (their normals summed), as Cycles merges a mesh's split vertices.  `edges` holds vertex pairs.
std::vector<float> Pointiness(const std::vector<Vec3f>& positions, const std::vector<Vec3f>& normals,
                              const std::vector<uint32_t>& edges);

// Geometry > Random Per Island: per vertex, a number in [0, 1] shared by its island (the vertices joined by
// `edges`), hashed from the island's representative as Cycles' disjoint set picks it.
std::vector<float> RandomPerIsland(size_t num_vertices, const std::vector<uint32_t>& edges);

// Object Info > Random of an object that is not an instance: Cycles hashes its name.
float ObjectNameRandom(const std::string& name);
// Object Info > Random from a depsgraph instance's random_id (Cycles' uint_to_float_incl).
float ObjectIdRandom(uint32_t random_id);

}  // namespace sphrect::render::svm
