// Pixel filters (render/pixel_filter.h): the table's samples follow the filter, and the 1-px box is the
// renderer's jitter unchanged.
// Settings: chi-square of 400,000 table samples over 64 equal-probability bins of each filter, false-failure
// rate 1e-3 per case; the same test fails Blackman-Harris against a Gaussian of the same width and a Gaussian
// 3% too wide (so it can tell the filters apart); the 1-px box maps u to u - 0.5 exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bsdf_chi_square.h"  // ChiSquareQuantile
#include "core/rng.h"
#include "render/pixel_filter.h"

namespace {

using namespace sphrect;
using namespace sphrect::render;

// The filter's CDF by composite Simpson on `steps` intervals over its support (the test's own quadrature,
// independent of the table's trapezoid sums), normalised: cdf[i] at -radius + i * 2 radius / steps.
std::vector<double> ReferenceCdf(PixelFilterType type, double width, int steps) {
    const double radius = PixelFilterRadius(type, width), h = 2 * radius / steps;
    std::vector<double> cdf(size_t(steps) + 1, 0.0);
    for (int i = 0; i < steps; ++i) {
        const double a = -radius + i * h;
        cdf[i + 1] = cdf[i] + h / 6 *
                                  (PixelFilterValue(type, width, a) + 4 * PixelFilterValue(type, width, a + h / 2) +
                                   PixelFilterValue(type, width, a + h));
    }
    for (double& c : cdf) c /= cdf.back();
    return cdf;
}

// Edges of `bins` bins of equal probability under the filter (bins expecting few samples would need pooling:
// equal-probability bins expect n / bins each).
std::vector<double> EqualProbabilityEdges(PixelFilterType type, double width, int bins) {
    const int steps = 1 << 16;
    const std::vector<double> cdf = ReferenceCdf(type, width, steps);
    const double radius = PixelFilterRadius(type, width), h = 2 * radius / steps;
    std::vector<double> edges(size_t(bins) + 1);
    edges[0] = -radius;
    edges[bins] = radius;
    int i = 0;
    for (int b = 1; b < bins; ++b) {
        const double target = double(b) / bins;
        while (cdf[i + 1] < target) ++i;
        edges[b] = -radius + (i + (target - cdf[i]) / (cdf[i + 1] - cdf[i])) * h;
    }
    return edges;
}

// Pearson's statistic of n samples of `f` (independent uniforms through SamplePixelFilter) over the bins.
double ChiSquareAgainst(const PixelFilter& f, const std::vector<double>& edges, int n, uint64_t seed) {
    const int bins = int(edges.size()) - 1;
    std::vector<double> observed(size_t(bins), 0.0);
    PCG32 rng(seed);
    for (int k = 0; k < n; ++k) {
        const double v = SamplePixelFilter(f, rng.NextFloat());
        int b = int(std::upper_bound(edges.begin(), edges.end(), v) - edges.begin()) - 1;
        observed[size_t(std::clamp(b, 0, bins - 1))] += 1;
    }
    const double expected = double(n) / bins;
    double chi2 = 0;
    for (double o : observed) chi2 += (o - expected) * (o - expected) / expected;
    return chi2;
}

constexpr int kBins = 64, kSamples = 400000;
// Normal score of the chi-square bound: a correct table fails with probability 1e-3 per case for a random
// seed (the seeds are fixed, so the outcome is too).
constexpr double kZ = 3.09;

struct FilterCase {
    PixelFilterType type;
    float width;
};

TEST(PixelFilter, SamplesFollowTheFilter) {
    const FilterCase cases[] = {{PixelFilterType::Gaussian, 1.5f},
                                {PixelFilterType::Gaussian, 0.5f},
                                {PixelFilterType::BlackmanHarris, 1.5f},
                                {PixelFilterType::BlackmanHarris, 4.0f},
                                {PixelFilterType::Box, 2.5f}};
    const double bound = ChiSquareQuantile(kBins - 1, kZ);
    uint64_t seed = 11;
    for (const FilterCase& c : cases) {
        const PixelFilter f = MakePixelFilter(c.type, c.width);
        const double chi2 = ChiSquareAgainst(f, EqualProbabilityEdges(c.type, c.width, kBins), kSamples, seed++);
        EXPECT_LT(chi2, bound) << kPixelFilterNames[int(c.type)] << " width " << c.width;
    }
}

// The test can fail: Blackman-Harris 1.5 against the bins of a Gaussian 1.5 (both bell-shaped, close to each
// other), and a Gaussian against the bins of a wider one.
TEST(PixelFilter, ChiSquareTellsCloseFiltersApart) {
    const double bound = ChiSquareQuantile(kBins - 1, kZ);
    const PixelFilter bh = MakePixelFilter(PixelFilterType::BlackmanHarris, 1.5f);
    EXPECT_GT(ChiSquareAgainst(bh, EqualProbabilityEdges(PixelFilterType::Gaussian, 1.5, kBins), kSamples, 21), bound);
    const PixelFilter gaussian = MakePixelFilter(PixelFilterType::Gaussian, 1.5f);
    EXPECT_GT(ChiSquareAgainst(gaussian, EqualProbabilityEdges(PixelFilterType::Gaussian, 1.55, kBins), kSamples, 22),
              bound);
}

TEST(PixelFilter, TableSpansTheSupportMonotoneAndSymmetric) {
    for (PixelFilterType type : {PixelFilterType::Gaussian, PixelFilterType::BlackmanHarris}) {
        const PixelFilter f = MakePixelFilter(type, 1.5f);
        ASSERT_EQ(int(f.inverse_cdf.size()), kPixelFilterTableSize);
        const float radius = float(PixelFilterRadius(type, 1.5));
        EXPECT_FLOAT_EQ(f.inverse_cdf.front(), -radius);
        EXPECT_FLOAT_EQ(f.inverse_cdf.back(), radius);
        for (size_t k = 1; k < f.inverse_cdf.size(); ++k) EXPECT_LE(f.inverse_cdf[k - 1], f.inverse_cdf[k]);
        for (size_t k = 0; k < f.inverse_cdf.size(); ++k)
            EXPECT_EQ(f.inverse_cdf[k], -f.inverse_cdf[f.inverse_cdf.size() - 1 - k]);
        EXPECT_EQ(SamplePixelFilter(f, 0.5f), 0.0f);
        EXPECT_FLOAT_EQ(SamplePixelFilter(f, 0.0f), -radius);
        EXPECT_LE(SamplePixelFilter(f, 1.0f), radius);
    }
}

TEST(PixelFilter, UnitBoxIsThePixelJitterExactly) {
    const PixelFilter box;  // the camera's default
    ASSERT_TRUE(box.IsUnitBox());
    EXPECT_TRUE(MakePixelFilter(PixelFilterType::Box, 1.0f).IsUnitBox());
    EXPECT_FALSE(MakePixelFilter(PixelFilterType::Box, 1.5f).IsUnitBox());
    EXPECT_FALSE(MakePixelFilter(PixelFilterType::Gaussian, 1.0f).IsUnitBox());
    PCG32 rng(5);
    std::vector<float> us = {0.0f, 1e-30f, 0.25f, 0.5f, std::nextafter(1.0f, 0.0f)};
    for (int k = 0; k < 100000; ++k) us.push_back(rng.NextFloat());
    for (float u : us) {
        EXPECT_EQ(SamplePixelFilter(box, u), u - 0.5f);
        EXPECT_EQ(FilmCoordinate(box, 37, u), 37.0f + u);  // what the camera stage computed before filters
    }
}

TEST(PixelFilter, WideBoxScalesTheJitterAboutTheCentre) {
    const PixelFilter box = MakePixelFilter(PixelFilterType::Box, 2.0f);
    EXPECT_EQ(SamplePixelFilter(box, 0.0f), -1.0f);
    EXPECT_EQ(SamplePixelFilter(box, 0.75f), 0.5f);
    EXPECT_EQ(FilmCoordinate(box, 3, 0.5f), 3.5f);
}

}  // namespace
