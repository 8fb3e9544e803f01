// Arvo's spherical-triangle map (spherical_triangle.h), the building block of `triangles`.
#include <gtest/gtest.h>

#include <random>

#include "core/spherical_triangle.h"

using namespace sphrect;

TEST(SphericalTriangle, SamplesStayInsideAndCoverUniformly) {
    // An octant triangle: area pi / 2; the fraction of samples with x > y must be 1/2 by symmetry.
    const SphericalTriangle t = MakeSphericalTriangle({1, 0, 0}, {0, 1, 0}, {0, 0, 1});
    EXPECT_NEAR(t.area, M_PI / 2, 1e-14);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> U(0, 1);
    int above = 0, n = 100000;
    for (int i = 0; i < n; ++i) {
        const Vec3d w = SampleSphericalTriangle(t, U(rng), U(rng));
        ASSERT_NEAR(Length(w), 1, 1e-12);
        ASSERT_GE(w.x, -1e-12);
        ASSERT_GE(w.y, -1e-12);
        ASSERT_GE(w.z, -1e-12);
        above += w.x > w.y;
    }
    // Binomial(1e5, 1/2): 4 standard deviations = 632.
    EXPECT_NEAR(above, n / 2, 632);
}
