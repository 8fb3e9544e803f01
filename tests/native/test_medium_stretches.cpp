// Distance sampling through a camera ray's stretches of media (render/medium_stretches.h): chi-square of the samples
// against DistanceThroughStretchesPDF (the one harness, bsdf_chi_square.h), the pdf a sample returns is the pdf's,
// and the mass past the last stretch is no sample.  Fixed seeds; a correct sampler fails a case with probability
// 1e-6 (normal score 4.753).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bsdf_chi_square.h"
#include "core/rng.h"
#include "render/medium_stretches.h"

namespace sphrect::render {
namespace {

// Segments from the camera: [0, 0.5) empty, [0.5, 1.5) thin, [1.5, 2) empty, [2, 3) dense, [3, inf) medium.
VolumeSegments Segments(float sigma_last) {
    VolumeSegments s;
    auto add = [&](float t0, float t1, float sigma) {
        s.segment[size_t(s.count++)] = {t0, t1, {{sigma, sigma, sigma}, {sigma, 0.5f * sigma, 2 * sigma}, 0}};
    };
    add(0, 0.5f, 0);
    add(0.5f, 1.5f, 0.4f);
    add(1.5f, 2, 0);
    add(2, 3, 1.6f);
    add(3, kInf, sigma_last);
    return s;
}

TEST(MediumStretches, DistanceSamplesFollowTheirPdf) {
    const HomogeneousMedium world{{0.05f, 0.05f, 0.05f}, {0.1f, 0.1f, 0.1f}, 0, 0.1f};
    const struct {
        float t_end, sigma_last;
        const HomogeneousMedium* world;
    } cases[] = {{4.5f, 0.3f, nullptr}, {2.6f, 0.3f, nullptr}, {20, 0.0f, nullptr}, {4.5f, 0.3f, &world}};
    PCG32 rng(17);
    for (const auto& c : cases) {
        const MediumStretches st = MakeMediumStretches(Segments(c.sigma_last), c.t_end, c.world);
        const double end = st.stretch[size_t(st.count - 1)].t1;  // past it nothing (the third case: t_end 20, 3)
        std::vector<double> edges;
        for (int k = 0; k <= 90; ++k) edges.push_back(end * k / 90.0);
        int mismatched = 0;
        const ChiSquare chi2 = IntervalSamplingChiSquare([&](float t) { return DistanceThroughStretchesPDF(st, t); },
                                                         [&](float u, float* t) {
                                                             const ScatterDistance d =
                                                                 SampleDistanceThroughStretches(st, u);
                                                             if (!(d.pdf > 0)) return false;
                                                             const float pdf = DistanceThroughStretchesPDF(st, d.t);
                                                             mismatched += std::abs(pdf - d.pdf) > 1e-4f * pdf;
                                                             *t = d.t;
                                                             return true;
                                                         },
                                                         rng, edges, 16, 400000);
        EXPECT_EQ(mismatched, 0) << c.t_end;
        ASSERT_GT(chi2.cells, 40) << c.t_end;
        EXPECT_LT(chi2.statistic, ChiSquareQuantile(chi2.cells - 1, 4.753)) << c.t_end << ", " << chi2.cells;
    }
}

TEST(MediumStretches, TransmittanceAndTheMassPastTheLastStretch) {
    const MediumStretches st = MakeMediumStretches(Segments(0.3f), 4.5f, nullptr);
    ASSERT_EQ(st.count, 3);
    // Optical depth to t = 3.5: 0.4 x 1 + 1.6 x 1 + 0.3 x 0.5 (red), half that (green), twice (blue).
    const Spectrum tr = TransmittanceInStretch(st.stretch[2], 3.5f);
    EXPECT_NEAR(tr.x, std::exp(-2.15f), 1e-6f);
    EXPECT_NEAR(tr.y, std::exp(-1.075f), 1e-6f);
    EXPECT_NEAR(tr.z, std::exp(-4.3f), 1e-6f);
    // A u past the whole optical depth (of the channels' mean extinction) samples nothing.
    const float tau_sampling = st.stretch[2].tau_sampling0 + st.stretch[2].sigma_sampling * 1.5f;
    EXPECT_EQ(SampleDistanceThroughStretches(st, 1 - 0.999f * std::exp(-tau_sampling)).pdf, 0.0f);
    EXPECT_GT(SampleDistanceThroughStretches(st, 1 - 1.001f * std::exp(-tau_sampling)).pdf, 0.0f);
    EXPECT_EQ(DistanceThroughStretchesPDF(st, 1.75f), 0.0f);  // the empty gap
}

}  // namespace
}  // namespace sphrect::render
