// Technique `rectangle_cosine` (rectangle_cosine.h) on its own; with the other techniques it
// is checked by the hard-case suite, the form factors and the chi-square tests.
#include <gtest/gtest.h>

#include "core/hard_cases.h"
#include "core/technique.h"

using namespace sphrect;

// rectangle_cosine with no usable normal falls back to uniform weights = `rectangle`.
TEST(RectangleCosine, WithoutNormalIsRectangle) {
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, true};
    const Vec3f o(0.2f, 0.1f, 0.7f);
    const LightSampler<Technique::RectangleCosine, float> c(o, Vec3f(0, 0, 0), L);
    const LightSampler<Technique::Rectangle, float> r(o, Vec3f(0, 0, 1), L);
    ASSERT_TRUE(c.Valid());
    for (float u : HardCaseUV())
        for (float v : HardCaseUV()) {
            const LightSample<float> a = c.Sample({u, v}), b = r.Sample({u, v});
            EXPECT_EQ(a.point.x, b.point.x);
            EXPECT_EQ(a.point.y, b.point.y);
            EXPECT_FLOAT_EQ(a.pdf, b.pdf);
        }
}
