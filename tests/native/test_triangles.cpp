// Technique `triangles` (triangles.h): its two switches, the area fallback of both
// triangles and the mixed spherical / planar setup, are unbiased and return the pdf of
// their point.
#include <gtest/gtest.h>

#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

// `triangles`: its switch is on the smaller triangle's solid angle; a shading point
// above the centre at the distance where it crosses.
TEST(Triangles, FallbackSwitchIsUnbiasedOnBothSides) {
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, false};
    auto fallback = [&](double d) { return !MakeTrianglesSetup(Vec3f(0.1f, 0.2f, float(d)), L).area_fallback; };
    const auto [d_lo, d_hi] = FindSwitch(10, 1e5, fallback);
    const Vec3f o_lo(0.1f, 0.2f, float(d_lo)), o_hi(0.1f, 0.2f, float(d_hi));
    ASSERT_FALSE(MakeTrianglesSetup(o_lo, L).area_fallback);
    ASSERT_TRUE(MakeTrianglesSetup(o_hi, L).area_fallback);
    ExpectUnbiasedAcross<Technique::Triangles>("switch", o_lo, o_hi, Vec3f(0, 0, -1), L);
}

// `triangles` with one triangle sampled spherically and the other (below the solid-
// angle threshold) by area: unbiased, and the pdf is the pdf of the point.
TEST(Triangles, MixedSphericalAndPlanarIsUnbiased) {
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, false};
    const Vec3f o(0.8f, -0.8f, 2.5e-7f), n = Normalize(Vec3f(-1, 1, 0));
    const TrianglesSetup<float> t = MakeTrianglesSetup(o, L);
    ASSERT_TRUE(t.valid);
    ASSERT_NE(t.planar[0], t.planar[1]);
    EXPECT_GT(std::min(t.p1, 1 - t.p1), 0.1);
    ExpectUnbiasedAcross<Technique::Triangles>("mixed", o, o, n, L);
    const LightSampler<Technique::Triangles, float> s(o, n, L);
    for (float u : HardCaseUV())
        for (float v : HardCaseUV()) {
            const LightSample<float> ls = s.Sample({u, v});
            EXPECT_NEAR(s.Pdf(ls.point), ls.pdf, 1e-4f * ls.pdf);
        }
}
