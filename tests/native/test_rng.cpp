// The random-number generator (rng.h): PCG32's floats, bounded integers, MixBits.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"

using namespace sphrect;

TEST(Rng, PCG32FloatsAreUniformAndBelowOne) {
    PCG32 rng(123);
    double sum = 0;
    const int N = 100000;
    for (int i = 0; i < N; ++i) {
        const float f = rng.NextFloat();
        ASSERT_TRUE(f >= 0.f && f < 1.f);
        sum += f;
    }
    // Mean of N uniforms: sd = sqrt(1/12/N) ~ 0.00091; 5 sd bound (false failure ~ 6e-7).
    EXPECT_NEAR(sum / N, 0.5, 5 * std::sqrt(1.0 / 12 / N));
    EXPECT_EQ(BitsToUnitFloat(0xffffffffu), kOneMinusEpsilonF);
    for (uint32_t b : {1u, 7u, 1000u}) {
        for (int i = 0; i < 1000; ++i) ASSERT_LT(rng.NextBounded(b), b);
    }
    EXPECT_NE(MixBits(0), MixBits(1));
}
