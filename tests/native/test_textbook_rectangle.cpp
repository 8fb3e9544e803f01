// The textbook formulation (textbook_rectangle.h) against the robust map: the same points
// where the paper's float formulas are accurate, and the failure the robust path exists for.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/textbook_rectangle.h"
#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

// In ordinary configurations (foot of o inside both slabs: no axis swap or mirror)
// the robust map is the paper's map: same points as the textbook formulation.
TEST(TextbookRectangle, MatchesPaperFormulationInOrdinaryCases) {
    const RectLight<float> L{{-0.5f, -0.7f, 0.2f}, {1.f, 0, 0}, {0, 1.4f, 0}, true};
    for (const Vec3f& o : {Vec3f(0.2f, 0.1f, 1.f), Vec3f(-0.3f, 0.5f, 0.4f), Vec3f(0.f, 0.f, 2.f)}) {
        const RectangleSetup<float> sr = MakeRectangleSetup(o, L);
        const TextbookRectangle tb = MakeTextbookRectangle(o, L);
        ASSERT_FALSE(sr.swap);
        EXPECT_NEAR(sr.solid_angle, tb.S, 1e-5f * tb.S);
        for (float u = 0.05f; u < 1; u += 0.1f)
            for (float v = 0.05f; v < 1; v += 0.1f) {
                const Vec3f a = SampleRectangle(sr, {u, v}).point;
                const Vec3f b = SampleTextbookRectangle(tb, u, v).point;
                EXPECT_NEAR(a.x, b.x, 1e-4f);
                EXPECT_NEAR(a.y, b.y, 1e-4f);
                EXPECT_NEAR(a.z, b.z, 1e-4f);
            }
    }
}

// The baseline's failure the robust path exists for (issue 2's numbers): a unit
// square seen from far away, textbook float Omega vs the robust one.
TEST(TextbookRectangle, TextbookFloatSolidAngleFailsFarAway) {
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, true};
    for (float d : {100.f, 1000.f, 10000.f}) {
        const Vec3f o(0, 0, d);
        const double ref = ReferenceSolidAngle(o, L);
        const double robust = MakeRectangleSetup(o, L).solid_angle;
        const double textbook = MakeTextbookRectangle(o, L).S;
        std::printf("d = %g: textbook rel. error %.3g, robust %.3g\n", d, std::abs(textbook - ref) / ref,
                    std::abs(robust - ref) / ref);
        EXPECT_LE(std::abs(robust - ref) / ref, 1e-6);
        EXPECT_GT(std::abs(textbook - ref) / ref, 1e-3);
    }
}
