// The bilinear warp (bilinear.h): round trip, pdf = Jacobian, endpoints.
#include <gtest/gtest.h>

#include "core/bilinear.h"

using namespace sphrect;

TEST(Bilinear, SampleInvertRoundTripAndPDFIsTheJacobian) {
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
                const Point2<double> pu = SampleBilinear({u + e, v}, w), pv = SampleBilinear(
                                                                             {
                                                                                 u,
                                                                                 v + e,
                                                                             },
                                                                             w);
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
