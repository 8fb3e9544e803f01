// CameraFootprint (render/camera.h): Cycles 3.4's compact ray differential at a camera ray's hit, which Bump nodes
// read (the Cycles comparisons: tests/blender/test_bump.py).
#include <gtest/gtest.h>

#include <cmath>

#include "render/camera.h"

namespace sphrect::render {
namespace {

CameraModel Camera(bool orthographic) {
    CameraModel c;
    c.width = 200, c.height = 100;
    c.orthographic = orthographic;
    c.half_width = 0.5f, c.half_height = 0.25f;
    // Turned about +x by 90 degrees (looking down +y) and moved: the footprint does not depend on where it is.
    const float m[3][4] = {{1, 0, 0, 3}, {0, 0, -1, -2}, {0, 1, 0, 1}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) c.to_world[i][j] = m[i][j];
    return c;
}

TEST(CameraFootprint, OrthographicIsOnePixelWide) {
    const CameraModel c = Camera(true);
    EXPECT_FLOAT_EQ(CameraFootprint(c, Vec3f(0, 1, 0), 7.0f), 1.0f / 200);
}

TEST(CameraFootprint, PerspectiveGrowsWithDistanceByTheDirectionsChange) {
    const CameraModel c = Camera(false);
    // At the centre a pixel step s = 2 half_width / width turns the unit direction by about s (same in y).
    const float s = 1.0f / 200;
    EXPECT_NEAR(CameraFootprint(c, Vec3f(0, 1, 0), 1.0f), s, 1e-3f * s);
    EXPECT_NEAR(CameraFootprint(c, Vec3f(0, 1, 0), 4.0f), 4 * s, 4e-3f * s);
    // Off-axis by 45 degrees in x: the x step turns the direction by s cos^2 = s / 2, the y step by s cos = s / sqrt 2.
    const Vec3f d = Normalize(Vec3f(1, 1, 0));
    EXPECT_NEAR(CameraFootprint(c, d, 1.0f), 0.5f * (0.5f * s + s / std::sqrt(2.0f)), 2e-3f * s);
    EXPECT_EQ(CameraFootprint(c, Vec3f(0, -1, 0), 1.0f), 0.0f);  // behind the camera: none
}

}  // namespace
}  // namespace sphrect::render
