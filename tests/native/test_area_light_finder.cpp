// The BVH that finds the analytic area lights on a ray gives exactly the linear test's crossings,
// in the same order: on random scenes of rectangles and ellipses, axis-aligned (flat boxes) and
// tilted, tiny and large, for camera-visible and all lights, inside and beyond tmax; and on a
// stack of coincident lights beyond its buffer.
#include <gtest/gtest.h>

#include <embree3/rtcore.h>

#include <random>
#include <vector>

#include "render/area_light_finder.h"

namespace sphrect::render {
namespace {

std::vector<LightCrossing> Linear(const std::vector<AreaLight>& lights, const Vec3f& o, const Vec3f& d, float tmin,
                                  float tmax, LightsSought sought) {
    std::vector<LightCrossing> out;
    for (size_t i = 0; i < lights.size(); ++i) {
        float t;
        if (CrossesLight(lights[i], sought, o, d, tmin, tmax, t)) out.push_back({int(i), t});
    }
    return out;
}

std::vector<LightCrossing> Found(const AreaLightFinder& finder, const Vec3f& o, const Vec3f& d, float tmin, float tmax,
                                 LightsSought sought) {
    std::vector<LightCrossing> out;
    finder.ForEachCrossing(o, d, tmin, tmax, sought, [&](int i, float t) { out.push_back({i, t}); });
    return out;
}

class AreaLightFinderTest : public ::testing::Test {
  protected:
    void SetUp() override { device_ = rtcNewDevice(nullptr); }
    void TearDown() override { rtcReleaseDevice(device_); }
    RTCDevice device_ = nullptr;
};

// Random lights over a 10 m cube: half axis-aligned, half tilted, sizes 1 mm ... 2 m.
std::vector<AreaLight> RandomLights(size_t n, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<AreaLight> lights;
    for (size_t i = 0; i < n; ++i) {
        const Vec3f c(10 * u(rng) - 5, 10 * u(rng) - 5, 10 * u(rng) - 5);
        const float size = std::pow(10.0f, -3 + 3.3f * u(rng));
        Vec3f a(size, 0, 0), b(0, size * (0.2f + u(rng)), 0);
        if (i % 2) {
            const Vec3f axis = Normalize(Vec3f(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
            a = Normalize(Cross(axis, Vec3f(0.3f, 0.5f, 0.8f))) * size;
            b = Normalize(Cross(axis, a)) * (size * (0.2f + u(rng)));
        }
        const bool visible = i % 3 != 0, two_sided = i % 4 == 0;
        if (i % 5 == 0)
            lights.push_back(MakeEllipseAreaLight(c, a, b, {1, 1, 1}, two_sided, visible));
        else
            lights.push_back(MakeRectAreaLight(c - (a + b) * 0.5f, a, b, {1, 1, 1}, two_sided, visible));
    }
    return lights;
}

TEST_F(AreaLightFinderTest, BvhFindsWhatTheLinearTestFinds) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0, 1);
    const std::vector<AreaLight> lights = RandomLights(3000, rng);
    AreaLightFinder finder;
    finder.Build(device_, lights, lights.size());
    ASSERT_TRUE(finder.uses_bvh());
    size_t crossings = 0;
    for (int r = 0; r < 20000; ++r) {
        const Vec3f o(12 * u(rng) - 6, 12 * u(rng) - 6, 12 * u(rng) - 6);
        Vec3f d = Normalize(Vec3f(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f));
        if (r % 4 == 0) d = Normalize(Vec3f(d.x, d.y, 1e-4f * d.z));  // grazing the axis-aligned lights
        if (r % 8 == 1) {  // aimed at a light's centre or its corner: crossings certain, or on the edge
            const AreaLight& l = lights[rng() % lights.size()];
            const Vec3f target = l.shape == AreaShape::Rectangle && r % 16 == 1 ? l.frame.light.corner : l.center;
            d = Normalize(target - o);
        }
        const float tmin = r % 3 == 0 ? 0.5f : 0.0f, tmax = r % 2 ? kInf : 6.0f;
        for (LightsSought sought : {LightsSought::All, LightsSought::VisibleToCamera}) {
            const auto want = Linear(lights, o, d, tmin, tmax, sought), got = Found(finder, o, d, tmin, tmax, sought);
            ASSERT_EQ(want.size(), got.size()) << "ray " << r;
            for (size_t k = 0; k < want.size(); ++k) {
                EXPECT_EQ(want[k].light, got[k].light);
                EXPECT_EQ(want[k].t, got[k].t);  // the same test: bit for bit
            }
            crossings += want.size();
        }
    }
    EXPECT_GT(crossings, 4000u);  // the rays do meet lights (aimed ones at least)
}

TEST_F(AreaLightFinderTest, FewLightsAreTestedInTurnAndStacksBeyondTheBufferAreComplete) {
    std::vector<AreaLight> few;
    for (int i = 0; i < int(kLinearLightSearchMax); ++i)
        few.push_back(MakeRectAreaLight({-1, -1, float(i)}, {2, 0, 0}, {0, 2, 0}, {1, 1, 1}, false, true));
    AreaLightFinder linear;
    linear.Build(device_, few, few.size());
    EXPECT_FALSE(linear.uses_bvh());
    EXPECT_EQ(Found(linear, {0, 0, -1}, {0, 0, 1}, 0, kInf, LightsSought::All).size(), few.size());

    // 100 coincident squares: more crossings than a BVH query keeps, so the linear test answers.
    std::vector<AreaLight> stack;
    for (int i = 0; i < 100; ++i)
        stack.push_back(MakeRectAreaLight({-1, -1, 2}, {2, 0, 0}, {0, 2, 0}, {1, 1, 1}, false, i % 2 == 0));
    AreaLightFinder finder;
    finder.Build(device_, stack, stack.size());
    ASSERT_TRUE(finder.uses_bvh());
    const auto all = Found(finder, {0.3f, 0.2f, 0}, {0, 0, 1}, 0, kInf, LightsSought::All);
    ASSERT_EQ(all.size(), 100u);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(all[i].light, i);
    EXPECT_EQ(Found(finder, {0.3f, 0.2f, 0}, {0, 0, 1}, 0, kInf, LightsSought::VisibleToCamera).size(), 50u);
    EXPECT_TRUE(Found(finder, {0.3f, 0.2f, 0}, {0, 0, 1}, 0, 1.5f, LightsSought::All).empty());
    EXPECT_TRUE(Found(finder, {0.3f, 0.2f, 0}, {0, 0, 1}, 2.5f, kInf, LightsSought::All).empty());
}

}  // namespace
}  // namespace sphrect::render
