// Chi-square goodness of fit of every technique against its own pdf (Mitsuba 3's
// chi2 warp tests, adapted): samples are binned on a 16 x 16 grid of cells on the
// light; the expected count of a cell is N times the integral of the technique's
// Pdf() over the cell in solid angle (adaptive Gauss-Legendre, sampling_test_util.h);
// cells expecting < 5 are pooled.  The integral over the whole light must be 1.
//
// False-failure rate: each test's p-value threshold is Sidak-corrected so that the
// whole file (kTests chi2 tests) fails by chance with probability 1% when every
// technique is right.  The seeds are fixed, so a run is deterministic.
#include <gtest/gtest.h>

#include <cstdio>

#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

namespace {

std::vector<LightConfig> Configs() {
    const RectLight<float> unit{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, true};
    const RectLight<float> wide{{-2.f, -0.25f, 0.5f}, {4, 0, 0}, {0, 0.5f, 0}, true};
    const RectLight<float> thin{{-0.5f, -5e-4f, 0}, {1, 0, 0}, {0, 1e-3f, 0}, true};
    const float s2 = std::sqrt(0.5f);
    const RectLight<float> rotated{{0.1f, -0.3f, 0.2f}, {0.8f * s2, 0.8f * s2, 0}, {0, 0, 1.2f}, true};
    return {
        // ordinary
        {"above", unit, {0.2f, 0.1f, 1.0f}, {0, 0.3f, -1}},
        {"oblique", unit, {1.5f, -0.7f, 0.4f}, {-1, 0.4f, -0.2f}},
        {"close", unit, {0.1f, -0.2f, 0.05f}, {0.2f, 0, -1}},
        {"wide", wide, {0.5f, 0.3f, 1.5f}, {0, 0, -1}},
        {"rotated", rotated, {-1.f, 1.f, 0.5f}, {1, -1, 0.1f}},
        {"below_two_sided", unit, {-0.2f, 0.3f, -0.6f}, {0, 0, 1}},
        // hard: grazing, nearly in the plane, far, thin, above an edge / corner, and
        // setups that use the area fallback (beside at h = 1e-6, far diagonal)
        {"grazing_beside_h1e-3", unit, {2.f, 0.1f, 1e-3f}, {-1, 0, 0}},
        {"interior_h1e-2", unit, {0.1f, 0.2f, 1e-2f}, {0.3f, 0, -1}},
        {"above_edge_h1e-3", unit, {0.5f, 0.1f, 1e-3f}, {-0.5f, 0, -1}},
        {"above_corner_h1e-2", unit, {-0.5f, 0.5f, 1e-2f}, {1, -1, -0.5f}},
        {"far_d1e3", unit, {0.3f, 0.1f, 1e3f}, {0, 0, -1}},
        {"thin_aspect1e3", thin, {0.2f, 0.3f, 0.2f}, {0, -0.5f, -1}},
        {"fallback_beside_h1e-6", unit, {2.f, 0.1f, 1e-6f}, {-1, 0, 0}},
        {"fallback_diagonal_far", unit, {3e3f, 3e3f, 2.f}, {-1, -1, 0}},
        // triangles: one spherical and one planar (area-sampled) triangle
        {"triangles_mixed_h2.5e-7", unit, {0.8f, -0.8f, 2.5e-7f}, {-1, 1, 0}},
    };
}

constexpr int kTechniques = 4;
const int kTests = kTechniques * int(Configs().size());
const double kAlpha = 1 - std::pow(1 - 0.01, 1.0 / kTests);  // Sidak

template <Technique K>
void Chi2All() {
    uint64_t seed = 1000 * uint64_t(K);
    for (const LightConfig& c : Configs()) {
        const Chi2Result r = Chi2Technique<K, float>(c.origin, c.normal, c.light, 200000, ++seed);
        std::printf("chi2 %-16s %-24s bins %3d chi2 %8.2f p %.4f integral %.6f\n", TechniqueName(K), c.name, r.bins,
                    r.statistic, r.p_value, r.total_expected);
        EXPECT_EQ(r.invalid_samples, 0) << c.name;
        EXPECT_NEAR(r.total_expected, 1.0, 1e-3) << c.name << ": the pdf does not integrate to 1 over the light";
        EXPECT_GT(r.p_value, kAlpha) << TechniqueName(K) << " " << c.name << " chi2 " << r.statistic << " bins "
                                     << r.bins;
    }
}

}  // namespace

TEST(Chi2, Area) { Chi2All<Technique::Area>(); }
TEST(Chi2, Triangles) { Chi2All<Technique::Triangles>(); }
TEST(Chi2, Rectangle) { Chi2All<Technique::Rectangle>(); }
TEST(Chi2, RectangleCosine) { Chi2All<Technique::RectangleCosine>(); }

// The test can fail: a technique whose pdf is off by a few percent is rejected.
TEST(Chi2, DetectsAWrongPdf) {
    const LightConfig c = Configs()[0];
    // Rectangle samples checked against a pdf 3% too large on half of the light.
    struct Skewed {
        LightSampler<Technique::Rectangle, float> s;
        LightSample<float> Sample(Point2<float> uv) const { return s.Sample(uv); }
        float Pdf(const Vec3f& p) const { return s.Pdf(p) * (p.x > 0 ? 1.03f : 0.97f); }
    };
    const Skewed sk{LightSampler<Technique::Rectangle, float>(c.origin, c.normal, c.light)};
    EXPECT_LT(Chi2Sampler(sk, c.origin, c.light, 200000, 3).p_value, kAlpha);
}
