// The bilinear warp (bilinear.h) and the spherical triangle (spherical_triangle.h)
// building blocks.
#include <gtest/gtest.h>

#include <random>

#include "core/bilinear.h"
#include "core/spherical_triangle.h"

using namespace sphrect;

TEST(Bilinear, SampleInvertRoundTripAndPdfIsTheJacobian) {
    const BilinearWeights ws[] = {{1, 2, 3, 4}, {0, 1, 1, 1}, {0, 0, 1, 1}, {0.5, 0, 0, 0.5}, {1, 1, 1, 1}};
    for (const BilinearWeights& w : ws) {
        for (double u = 0.05; u < 1; u += 0.1)
            for (double v = 0.05; v < 1; v += 0.1) {
                const Point2<double> p = SampleBilinear({u, v}, w);
                const Point2<double> back = InvertBilinearSample(p, w);
                EXPECT_NEAR(back.u, u, 1e-12);
                EXPECT_NEAR(back.v, v, 1e-12);
                // pdf = 1 / |d(sample)/d(u, v)|: the sample's u depends on u only.
                const double e = 1e-6;
                const Point2<double> pu = SampleBilinear({u + e, v}, w), pv = SampleBilinear({u, v + e, }, w);
                const double jac = (pu.u - p.u) / e * (pv.v - p.v) / e;
                EXPECT_NEAR(BilinearPDF(p, w) * jac, 1.0, 1e-4);
            }
        // The pdf integrates to 1 (midpoint rule on a fine grid; it is bilinear).
        double sum = 0;
        const int n = 100;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) sum += BilinearPDF({(i + 0.5) / n, (j + 0.5) / n}, w) / (n * n);
        EXPECT_NEAR(sum, 1.0, 1e-12);
    }
}

TEST(Bilinear, EndpointsStayInTheUnitSquare) {
    const BilinearWeights w = {0, 1, 0, 1};
    for (double u : {0.0, 1.0, std::nextafter(1.0, 0.0)})
        for (double v : {0.0, 1.0}) {
            const Point2<double> p = SampleBilinear({u, v}, w);
            EXPECT_GE(p.u, 0);
            EXPECT_LE(p.u, 1);
            EXPECT_GE(p.v, 0);
            EXPECT_LE(p.v, 1);
        }
    EXPECT_EQ(SampleLinear(0, 0, 1), 0);
    EXPECT_EQ(SampleLinear(1, 0, 1), 1);
}

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
