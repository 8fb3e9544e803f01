// The mesh attributes Cycles computes at sync time (render/svm/standard_attributes.h) on meshes whose values are
// known: Pointiness 0.5 on flat ground and above it on a convex corner, unchanged when a vertex is split into
// co-located copies; Random Per Island shared within an island.  (Against Cycles 3.4: tests/blender/
// test_attribute_nodes.py.)
#include <gtest/gtest.h>

#include <cmath>

#include "render/svm/standard_attributes.h"

using namespace sphrect;
using namespace sphrect::render::svm;

namespace {

// A 3x3-vertex grid in the z = 0 plane (unit spacing), vertex 4 in the middle lifted by `lift`.
std::vector<Vec3f> GridPositions(float lift) {
    std::vector<Vec3f> p;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) p.push_back({float(x), float(y), x == 1 && y == 1 ? lift : 0.0f});
    return p;
}
const std::vector<uint32_t> kGridEdges = {0, 1, 1, 2, 3, 4, 4, 5, 6, 7, 7, 8, 0, 3, 3, 6, 1, 4, 4, 7, 2, 5, 5, 8};

}  // namespace

TEST(StandardAttributes, PointinessIsOneHalfOnFlatGroundAndMoreOnAPeak) {
    const std::vector<Vec3f> up(9, Vec3f(0, 0, 1));
    // Flat: every vertex's edges' mean lies in the plane, a right angle to the normal.
    for (float v : Pointiness(GridPositions(0), up, kGridEdges)) EXPECT_NEAR(v, 0.5f, 1e-6f);
    // A peak: its edges lean down (raw 0.65), its side neighbours' up (concave, raw 0.45), the corners flat (0.5);
    // each value then the mean over the vertex and its neighbours.
    const std::vector<float> peak = Pointiness(GridPositions(0.5f), up, kGridEdges);
    const float raw_peak = std::acos(-1.0f / std::sqrt(5.0f)) / 3.14159265f;
    const float raw_side = std::acos(0.5f / std::sqrt(1.25f) / 3.0f) / 3.14159265f;
    EXPECT_NEAR(peak[4], (raw_peak + 4 * raw_side) / 5, 1e-5f);
    EXPECT_NEAR(peak[1], (raw_side + 2 * 0.5f + raw_peak) / 4, 1e-5f);
    EXPECT_GT(raw_peak, 0.5f);
    EXPECT_LT(raw_side, 0.5f);
}

TEST(StandardAttributes, CoLocatedCopiesCountAsOneVertex) {
    // The middle vertex split in two (a copy at index 9 taking the edges to 5, 7): its normals summed, one value.
    std::vector<Vec3f> p = GridPositions(0.5f);
    const std::vector<Vec3f> up(9, Vec3f(0, 0, 1));
    const std::vector<float> welded = Pointiness(p, up, kGridEdges);
    p.push_back(p[4]);
    std::vector<Vec3f> normals = up;
    normals.push_back(Vec3f(0, 0, 1));
    std::vector<uint32_t> edges = kGridEdges;
    for (size_t i = 0; i < edges.size(); i += 2)
        if ((edges[i] == 4 && (edges[i + 1] == 5 || edges[i + 1] == 7))) edges[i] = 9;
    const std::vector<float> split = Pointiness(p, normals, edges);
    EXPECT_FLOAT_EQ(split[4], split[9]);
    for (int v = 0; v < 9; ++v) EXPECT_NEAR(split[v], welded[v], 1e-6f) << v;
}

TEST(StandardAttributes, RandomPerIslandIsSharedWithinAnIsland) {
    // Islands {0, 1, 2} and {3, 4}; vertex 5 alone.
    const std::vector<float> r = RandomPerIsland(6, {0, 1, 2, 1, 3, 4});
    EXPECT_EQ(r[0], r[1]);
    EXPECT_EQ(r[1], r[2]);
    EXPECT_EQ(r[3], r[4]);
    EXPECT_NE(r[0], r[3]);
    EXPECT_NE(r[3], r[5]);
    for (float x : r) EXPECT_TRUE(x >= 0 && x <= 1);
}

TEST(StandardAttributes, ObjectRandomIsTheScaledId) {
    EXPECT_EQ(ObjectIdRandom(0), 0.0f);
    EXPECT_EQ(ObjectIdRandom(0xFFFFFFFFu), 1.0f);
    EXPECT_NE(ObjectNameRandom("Cube"), ObjectNameRandom("Cube.001"));
}
