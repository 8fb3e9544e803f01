// Area light spread (render/area_light.h): the sub-rectangle a shading point samples is Cycles 3.4's clip (the
// light cut to the square of half side d tan(h) around the point's foot), exact in double, empty when the square
// misses the light; the rectangle map on it gives the sub-rectangle's closed-form solid angle, also 1e-3 above a
// light of spread 1 degree; the attenuation is N at the normal and 0 from the half spread on.  Deterministic.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rectangle.h"
#include "render/area_light.h"

namespace sphrect::render {
namespace {

// A 2 x 1 one-sided light at height z facing down (-z), corner (-1, -0.5, z).
AreaLight TestLight(float z, float spread_degrees) {
    AreaLight l = MakeRectAreaLight({-1, -0.5f, z}, {0, 1, 0}, {2, 0, 0}, {1, 1, 1}, false, true);
    SetAreaSpread(l, spread_degrees * kPi / 180);
    return l;
}

TEST(AreaSpread, SpreadOf180DegreesIsNoSpread) {
    AreaLight l = TestLight(1, 180);
    EXPECT_FALSE(l.HasSpread());
    EXPECT_EQ(l.spread_normalization, 1.0f);
    EXPECT_TRUE(TestLight(1, 179.9f).HasSpread());
}

TEST(AreaSpread, ClipIsTheSquareAroundTheFootCutToTheLight) {
    const AreaLight l = TestLight(1, 30);
    const double r = 1.0 / l.spread_cot;  // height 1
    EXPECT_NEAR(r, std::tan(15 * M_PI / 180), 1e-6);
    // The light's edges: exh = +y (length 1), eyh = +x (length 2), corner (-1, -0.5).
    const RectLightFrame<float> inside = SpreadClippedFrame(l, {0.3f, 0.1f, 0});
    ASSERT_TRUE(inside.valid);
    EXPECT_NEAR(inside.wx, 2 * r, 1e-7);
    EXPECT_NEAR(inside.wy, 2 * r, 1e-7);
    EXPECT_NEAR(inside.corner.x, 0.3 - r, 1e-7);
    EXPECT_NEAR(inside.corner.y, 0.1 - r, 1e-7);
    EXPECT_NEAR(inside.corner.z, 1, 1e-7);
    const RectLightFrame<float> edge = SpreadClippedFrame(l, {0.95f, 0.4f, 0});  // cut at x = 1 and y = 0.5
    ASSERT_TRUE(edge.valid);
    EXPECT_NEAR(edge.wy, 1 - (0.95 - r), 1e-7);
    EXPECT_NEAR(edge.wx, 0.5 - (0.4 - r), 1e-7);
    EXPECT_FALSE(SpreadClippedFrame(l, {1.5f, 0, 0}).valid);     // the square misses the light
    EXPECT_FALSE(SpreadClippedFrame(l, {0.2f, 0.1f, 1}).valid);  // in the light's plane: nothing
}

TEST(AreaSpread, RectangleMapOnTheClipHasItsSolidAngleEvenAtOneDegreeNearTheLight) {
    for (float z : {1.0f, 1e-3f}) {
        const AreaLight l = TestLight(z, 1);
        const double h = z, r = h / l.spread_cot;
        const Vec3f o{0.1f, -0.2f, 0};
        const RectLightFrame<float> f = SpreadClippedFrame(l, o);
        ASSERT_TRUE(f.valid);
        EXPECT_NEAR(f.wx / (2 * r), 1, 1e-6);
        const RectangleSetup<float> s = MakeRectangleSetup(o, f);
        ASSERT_TRUE(s.valid);
        // A 2r x 2r square centred over the point: 4 asin(r^2 / (r^2 + h^2)).
        const double omega = 4 * std::asin(r * r / (r * r + h * h));
        EXPECT_NEAR(s.omega / omega, 1, 1e-5) << "z = " << z;
        // Samples land on the clip.
        for (float u : {0.01f, 0.5f, 0.99f}) {
            const LightSample<float> ls = SampleRectangle(s, {u, 1 - u});
            EXPECT_NEAR(ls.point.z, z, 1e-6f * (1 + z));
            EXPECT_LE(std::abs(ls.point.x - o.x), r * (1 + 1e-4) + 1e-7);
            EXPECT_LE(std::abs(ls.point.y - o.y), r * (1 + 1e-4) + 1e-7);
        }
    }
}

TEST(AreaSpread, AttenuationIsNormalisedAtTheNormalAndZeroFromTheHalfSpread) {
    const AreaLight l = TestLight(1, 60);
    EXPECT_FLOAT_EQ(SpreadAttenuation(l, {0, 0, -1}), l.spread_normalization);
    const float t = std::tan(30 * kPi / 180);
    EXPECT_NEAR(SpreadAttenuation(l, {0.5f * t, 0, -1}), 0.5f * l.spread_normalization, 1e-5f);
    EXPECT_NEAR(SpreadAttenuation(l, {t, 0, -1}), 0, 1e-5f);
    EXPECT_EQ(SpreadAttenuation(l, {2 * t, 0, -1}), 0);
    EXPECT_EQ(EmittedRadiance(l, {0, 0, 1}).x, 0);  // the back of a one-sided light
    EXPECT_FLOAT_EQ(EmittedRadiance(l, {0, 0, -1}).x, l.spread_normalization);
}

}  // namespace
}  // namespace sphrect::render
