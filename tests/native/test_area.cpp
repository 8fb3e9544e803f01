#include <gtest/gtest.h>

#include "core/technique.h"

using namespace sphrect;

TEST(Area, PointsLieOnTheLight) {
    RectLight<float> light{{-0.5f, -0.5f, 1.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, true};
    LightSampler<Technique::Area, float> s({0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, light);
    ASSERT_TRUE(s.Valid());
    LightSample<float> ls = s.Sample({0.25f, 0.75f});
    EXPECT_NEAR(ls.point.x, -0.25f, 1e-6f);
    EXPECT_NEAR(ls.point.y, 0.25f, 1e-6f);
    EXPECT_NEAR(ls.point.z, 1.f, 1e-6f);
    // pdf = d^2 / (A cos): here cos = 1/d, so pdf = d^3.
    const float d = std::sqrt(0.25f * 0.25f * 2 + 1);
    EXPECT_NEAR(ls.pdf, d * d * d, 1e-5f);
}
