// The screen shapes of the control variate (render/screen_lights.h): the image of a light is the
// set of film points whose camera ray crosses it (checked against IntersectAreaLight on random
// film points), and a pixel's coverage is the exact area of its overlap (checked against dense
// counting, and summed over the film against the image's closed-form area); the disk-polygon and
// box-polygon areas (render/overlap_area.h) against known values.
// Settings: 200,000 random film points per light; coverage within 2e-4 of counting on a 2^17-point lattice,
// summing over the film to the image's area within 1e-9 (relative).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "render/overlap_area.h"
#include "render/screen_lights.h"

namespace sphrect::render {
namespace {

CameraModel TestCamera(bool orthographic) {
    CameraModel c;
    c.width = 40;
    c.height = 30;
    c.orthographic = orthographic;
    // Looking down -Z from (0.3, -0.2, 0), turned a little about y.
    const float a = 0.15f;
    const float m[3][4] = {{std::cos(a), 0, std::sin(a), 0.3f}, {0, 1, 0, -0.2f}, {-std::sin(a), 0, std::cos(a), 0}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) c.to_world[i][j] = m[i][j];
    c.half_width = orthographic ? 3.0f : 0.6f;
    c.half_height = c.half_width * 0.75f;
    c.offset_x = 0.05f;
    c.clip_start = 0.1f;
    return c;
}

std::vector<AreaLight> TestLights() {
    return {MakeRectAreaLight({-1.5f, -0.8f, -4}, {1.2f, 0.3f, 0}, {-0.3f, 1.2f, 0.45f}, {1, 1, 1}, false, true),
            MakeEllipseAreaLight({1.0f, 0.4f, -5}, {0.9f, 0.2f, 0.1f}, {-0.2f, 0.9f, 0}, {2, 2, 2}, true, true),
            // Beyond the film's left edge, partly.
            MakeRectAreaLight({-4.0f, 0.5f, -3.5f}, {2.0f, 0, 0}, {0, 0.6f, 0}, {3, 3, 3}, false, true)};
}

// Ray through film point (fx, fy) as GenerateCameraRay makes it.
bool RayCrosses(const CameraModel& c, const AreaLight& l, double fx, double fy) {
    const Ray r = GenerateCameraRay<false>(c, float(fx), float(fy), {});
    return IntersectAreaLight(l, r.o, r.d, r.tmax) < kInf;
}

class ScreenLightsTest : public ::testing::TestWithParam<bool> {};

TEST_P(ScreenLightsTest, ImageIsWhereCameraRaysCrossTheLight) {
    const CameraModel cam = TestCamera(GetParam());
    const auto lights = TestLights();
    const auto screen = BuildScreenLights(cam, lights, lights.size());
    ASSERT_EQ(screen.size(), 3u);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> ux(0, cam.width), uy(0, cam.height);
    for (const ScreenLight& s : screen) {
        int inside = 0, disagree = 0;
        for (int k = 0; k < 200000; ++k) {
            const double x = ux(rng), y = uy(rng);
            const bool in = InsideScreenLight(s, float(x), float(y));
            inside += in;
            disagree += in != RayCrosses(cam, lights[s.light], float(x), float(y));
        }
        EXPECT_GT(inside, 1000) << s.light;
        // Only points within float rounding of the rim may disagree.
        EXPECT_LE(disagree, 3) << s.light;
    }
}

TEST_P(ScreenLightsTest, CoverageIsTheOverlapArea) {
    const CameraModel cam = TestCamera(GetParam());
    const auto lights = TestLights();
    const auto screen = BuildScreenLights(cam, lights, lights.size());
    constexpr int kPoints = 1 << 17;  // counting error ~ log(kPoints) / kPoints
    const double kGolden = 0.5 * (std::sqrt(5.0) - 1);
    for (const ScreenLight& s : screen) {
        double total = 0, worst = 0;
        int partial = 0;
        for (int py = 0; py < cam.height; ++py)
            for (int px = 0; px < cam.width; ++px) {
                const double c = PixelCoverage(s, px, py);
                ASSERT_GE(c, 0);
                ASSERT_LE(c, 1);
                total += c;
                if (c == 0 || c == 1) continue;
                ++partial;
                if (partial % 3) continue;  // count a sample of the edge pixels
                // A Fibonacci lattice of kPoints points (no row lines up with an axis-aligned edge).
                int n = 0;
                for (int i = 0; i < kPoints; ++i) {
                    const double u = (i + 0.5) / kPoints, v = std::fmod(i * kGolden, 1.0);
                    n += InsideScreenLight(s, px + u, py + v);
                }
                worst = std::max(worst, std::abs(c - double(n) / kPoints));
            }
        EXPECT_GE(partial, 8) << s.light;
        EXPECT_LT(worst, 2e-4) << s.light;
        // The whole image's area (the part on the film, for the light beyond its edge).
        if (s.light == 2) continue;
        double area;
        if (s.ellipse) {
            area = M_PI / std::sqrt(s.m00 * s.m11 - s.m01 * s.m01);
        } else {
            area = 0;
            for (int k = 0; k < 4; ++k) area += 0.5 * (s.qx[k] * s.qy[(k + 1) & 3] - s.qx[(k + 1) & 3] * s.qy[k]);
        }
        EXPECT_NEAR(total, area, 1e-9 * area) << s.light;
    }
}

INSTANTIATE_TEST_SUITE_P(Cameras, ScreenLightsTest, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Orthographic" : "Perspective"; });

TEST(ScreenLights, LeavesOutWhatTheControlVariateCannotUse) {
    CameraModel cam = TestCamera(false);
    auto lights = TestLights();
    lights[0].visible = false;       // not seen by the camera
    lights[1].radiance = {0, 0, 0};  // black
    lights[2] = MakeRectAreaLight({-1, -1, -4}, {2, 0, 0}, {0, -2, 0}, {1, 1, 1}, false, true);  // back side
    EXPECT_TRUE(BuildScreenLights(cam, lights, lights.size()).empty());
    lights = TestLights();
    lights.push_back(MakeRectAreaLight({-1, -1, 0.5f}, {2, 0, 0}, {0, 0, -2}, {1, 1, 1}, true, true));   // behind
    lights.push_back(MakeRectAreaLight({-1, -1, -0.05f}, {2, 0, 0}, {0, 2, 0}, {1, 1, 1}, true, true));  // clipped
    EXPECT_EQ(BuildScreenLights(cam, lights, lights.size()).size(), 3u);
    cam.aperture_radius = 0.1f;  // depth of field
    EXPECT_TRUE(BuildScreenLights(cam, TestLights(), 3).empty());
}

TEST(ScreenLightGeometry, UnitDiskInsidePolygons) {
    const double bx[4] = {-2, 2, 2, -2}, by[4] = {-2, -2, 2, 2};
    EXPECT_NEAR(UnitDiskPolygonArea(bx, by, 4), M_PI, 1e-14);  // the whole disk
    const double qx[4] = {0, 2, 2, 0}, qy[4] = {0, 0, 2, 2};
    EXPECT_NEAR(UnitDiskPolygonArea(qx, qy, 4), M_PI / 4, 1e-14);   // a quadrant
    const double hx[4] = {-2, 2, 2, -2}, hy[4] = {0.5, 0.5, 2, 2};  // the cap above y = 1/2
    EXPECT_NEAR(UnitDiskPolygonArea(hx, hy, 4), std::acos(0.5) - 0.5 * std::sqrt(0.75), 1e-14);
    const double ix[4] = {-0.1, 0.2, 0.2, -0.1}, iy[4] = {-0.1, -0.1, 0.3, 0.3};  // inside
    EXPECT_NEAR(UnitDiskPolygonArea(ix, iy, 4), 0.3 * 0.4, 1e-15);
    const double ox[4] = {1.5, 2, 2, 1.5}, oy[4] = {-1, -1, 1, 1};  // outside
    EXPECT_NEAR(UnitDiskPolygonArea(ox, oy, 4), 0, 1e-15);
}

TEST(ScreenLightGeometry, ConvexPolygonInBox) {
    const double tx[3] = {0, 4, 0}, ty[3] = {0, 0, 4};  // triangle of area 8
    EXPECT_NEAR(ConvexPolygonBoxArea(tx, ty, 3, -1, -1, 5, 5), 8, 1e-14);
    EXPECT_NEAR(ConvexPolygonBoxArea(tx, ty, 3, 0, 0, 1, 1), 1, 1e-14);
    EXPECT_NEAR(ConvexPolygonBoxArea(tx, ty, 3, 1.5, 1.5, 2.5, 2.5), 0.5, 1e-14);  // cut by the diagonal
    EXPECT_NEAR(ConvexPolygonBoxArea(tx, ty, 3, 5, 5, 6, 6), 0, 1e-14);
    const double rx[3] = {0, 0, 4}, ry[3] = {0, 4, 0};  // clockwise
    EXPECT_NEAR(ConvexPolygonBoxArea(rx, ry, 3, 1.5, 1.5, 2.5, 2.5), 0.5, 1e-14);
}

}  // namespace
}  // namespace sphrect::render
