// The image world's pieces (render/distribution_2d.h, render/environment_light.h): the 2-D piecewise-constant
// distribution (its pdf a density, samples only in cells of weight, Invert undoing Sample), the equirectangular
// mapping (Cycles 3.4's axes), and the solid-angle pdf integrating to 1 over the sphere.  The chi-square test of
// SampleEnvironment against EnvironmentPDF goes through the project's harness (tests/python/test_environment.py).
// Deterministic: fixed seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "render/distribution_2d.h"
#include "render/environment_light.h"

namespace {

using namespace sphrect;
using namespace sphrect::render;

TEST(Distribution2D, PdfIsADensityAndSamplesOnlyCellsOfWeight) {
    const int w = 5, h = 3;
    const std::vector<double> weights = {1, 0, 2, 3, 0, 0, 0, 0, 0, 0, 4, 1, 0, 0.5, 7};
    Distribution2D d;
    d.Build(w, h, weights);
    double total = 0;
    for (double v : weights) total += v;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float pdf = Distribution2DPDF(d, {(x + 0.5f) / w, (y + 0.5f) / h});
            EXPECT_NEAR(pdf / (w * h), weights[y * w + x] / total, 1e-6) << x << ", " << y;
        }
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    for (int i = 0; i < 20000; ++i) {
        const Point2<float> u{uni(rng), uni(rng)};
        const Distribution2DSample s = SampleDistribution2D(d, u);
        ASSERT_GT(s.pdf, 0);
        ASSERT_GE(s.uv.u, 0);
        ASSERT_LT(s.uv.u, 1);
        ASSERT_GE(s.uv.v, 0);
        ASSERT_LT(s.uv.v, 1);
        const int x = int(s.uv.u * w), y = int(s.uv.v * h);
        ASSERT_GT(weights[y * w + x], 0) << "sampled a cell of no weight";
        EXPECT_FLOAT_EQ(s.pdf, Distribution2DPDF(d, s.uv));
        const Point2<float> back = InvertDistribution2DSample(d, s.uv);
        EXPECT_NEAR(back.u, u.u, 2e-5);
        EXPECT_NEAR(back.v, u.v, 2e-5);
    }
}

TEST(Distribution2D, AllZeroIsEmpty) {
    Distribution2D d;
    d.Build(2, 2, {0, 0, 0, 0});
    EXPECT_TRUE(d.Empty());
    EXPECT_EQ(SampleDistribution2D(d, {0.3f, 0.6f}).pdf, 0);
    EXPECT_EQ(Distribution2DPDF(d, {0.3f, 0.6f}), 0);
}

TEST(EnvironmentLight, EquirectangularAxesAreCycles) {
    auto uv = [](Vec3f d) { return EquirectangularFromDirection(d); };
    EXPECT_NEAR(uv({1, 0, 0}).u, 0.5f, 1e-7);  // +X: the middle column, on the horizon
    EXPECT_NEAR(uv({1, 0, 0}).v, 0.5f, 1e-7);
    EXPECT_NEAR(uv({0, 1, 0}).u, 0.25f, 1e-7);  // u grows clockwise seen from +Z
    EXPECT_NEAR(uv({0, -1, 0}).u, 0.75f, 1e-7);
    EXPECT_NEAR(uv({0, 0, 1}).v, 1.0f, 1e-7);  // +Z: the top row
    EXPECT_NEAR(uv({0, 0, -1}).v, 0.0f, 1e-7);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uni(0.01f, 0.99f);
    for (int i = 0; i < 1000; ++i) {
        const Point2<float> p{uni(rng), uni(rng)};
        float sin_theta;
        const Vec3f d = DirectionFromEquirectangular(p, &sin_theta);
        EXPECT_NEAR(Length(d), 1.0f, 1e-6f);
        const Point2<float> q = EquirectangularFromDirection(d);
        EXPECT_NEAR(q.u, p.u, 1e-5);
        EXPECT_NEAR(q.v, p.v, 1e-5);
    }
}

// The integral of EnvironmentPDF over the sphere, by the midpoint rule on a fine (u, v) grid (d omega =
// 2 pi^2 sin(theta) du dv).
double IntegratePdf(const EnvironmentLight& e, int n) {
    double sum = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < 2 * n; ++i) {
            float sin_theta;
            const Vec3f d = DirectionFromEquirectangular({(i + 0.5f) / (2 * n), (j + 0.5f) / n}, &sin_theta);
            sum += EnvironmentPDF(e, EnvironmentToWorld(e, d)) * 2 * kPi * kPi * sin_theta / (2.0 * n * n);
        }
    return sum;
}

TEST(EnvironmentLight, PdfIntegratesToOneAndDegenerateImages) {
    const float pixels[] = {0, 0, 0, 5, 5, 5, 0.1f, 0.2f, 0.3f, 1, 1, 1, 0, 0, 0, 0, 0, 0};  // 3 x 2, RGB
    EnvironmentLight e;
    const float c = std::cos(0.7f), s = std::sin(0.7f);
    const float rotation[3][3] = {{c, 0, s}, {0, 1, 0}, {-s, 0, c}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) e.to_world[i][j] = rotation[i][j];
    for (TextureInterpolation interp : {TextureInterpolation::kLinear, TextureInterpolation::kClosest}) {
        e.interpolation = interp;
        BuildEnvironmentDistribution(e, MakeImage("small", 3, 2, 3, nullptr, pixels, false));
        EXPECT_NEAR(IntegratePdf(e, 384), 1.0, 2e-3);
    }
    // 1 x 1: sampled by solid angle (kMinEnvironmentRows rows), so the pdf is ~1 / (4 pi) away from the poles.
    const float one[] = {2, 2, 2};
    EnvironmentLight u;
    BuildEnvironmentDistribution(u, MakeImage("one", 1, 1, 3, nullptr, one, false));
    EXPECT_NEAR(EnvironmentPDF(u, {1, 0, 0}), 1 / (4 * kPi), 0.01 / (4 * kPi));
    EXPECT_NEAR(IntegratePdf(u, 256), 1.0, 2e-3);
    // All black: no light.
    const float black[] = {0, 0, 0, 0, 0, 0};
    EnvironmentLight b;
    BuildEnvironmentDistribution(b, MakeImage("black", 2, 1, 3, nullptr, black, false));
    EXPECT_TRUE(b.distribution.Empty());
    EXPECT_EQ(SampleEnvironment(b, {0.5f, 0.5f}).pdf, 0);
    EXPECT_EQ(EnvironmentPDF(b, {0, 0, 1}), 0);
}

}  // namespace
