// Light selection "ris" (integrator/resampled_light_choice.h): its images' means are "tree"'s -- on a scene of 4
// lights and on one of 2,000 small lights with point and spot lights in the tree, MIS on -- and under many small
// lights its variance at equal samples is well below the tree's.
//
// Statistics: fixed seeds; each image is the mean of kRuns independent renders (seeds 1..kRuns, independent pattern).
// Means: Welch's t of each of 16 blocks of pixels, |t| < 6 with ~2 x (kRuns - 1) degrees of freedom: P(|t| > 6)
// < 1e-6 per block, so the false-failure rate is below 1e-4 for the file (64 blocks).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "core/rng.h"
#include "render/integrator/resampled_light_choice.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace sphrect::render {
namespace {

constexpr int kSide = 24;  // image side, pixels
constexpr int kBlock = 6;  // the t-tests' blocks: (kSide / kBlock)^2 of them
constexpr int kRuns = 24;

// A floor seen from above at an angle, lit by `area_lights` small rectangles (random sizes, heights, tilts, colours,
// some two-sided) and, with `delta_lights`, by more point lights than stay beside the tree and a spot, so that the
// tree chooses them too.
std::shared_ptr<RenderScene> FloorUnderLights(int area_lights, bool delta_lights, bool glossy, float light_size) {
    auto s = std::make_shared<RenderScene>();
    CameraModel c;
    c.width = c.height = kSide;
    c.half_width = c.half_height = 0.5f;
    const float m[3][4] = {{1, 0, 0, 0}, {0, 0.8f, -0.6f, -4}, {0, 0.6f, 0.8f, 3}};
    std::copy(&m[0][0], &m[0][0] + 12, &c.to_world[0][0]);
    s->SetCamera(c);
    Material floor = DiffuseMaterial({0.6f, 0.6f, 0.6f});
    if (glossy) {
        floor.kind = MaterialKind::kGlossy;
        floor.inputs.roughness = 0.15f;
        floor.inputs.metallic = 1;
    }
    s->AddMaterial(floor);
    const float v[] = {-6, -6, 0, 6, -6, 0, 6, 6, 0, -6, 6, 0};
    const int32_t t[] = {0, 1, 2, 0, 2, 3};
    s->AddMesh("floor", v, 4, t, 2, nullptr, nullptr);
    PCG32 rng(17);
    const float scale = area_lights > 100 ? 30.0f / std::sqrt(float(area_lights)) : 1.0f;  // about the same light
    for (int i = 0; i < area_lights; ++i) {
        const Vec3f corner(-3 + 6 * rng.NextFloat(), -3 + 6 * rng.NextFloat(), 0.3f + 2 * rng.NextFloat());
        const float size = light_size * (0.5f + rng.NextFloat()), tilt = rng.NextFloat() - 0.5f;
        const Spectrum radiance = Spectrum(0.2f + rng.NextFloat(), 0.2f + rng.NextFloat(), 0.2f + rng.NextFloat()) *
                                  (scale / (light_size * light_size));
        EXPECT_EQ(s->AddRectLight(corner, {0, size, size * tilt}, {size, 0, 0}, radiance, i % 3 == 0, false), "");
    }
    if (delta_lights) {
        for (int i = 0; i < int(kMaxDeltaLightsBesideTree) + 4; ++i)
            s->AddPointLight({-3 + 6 * rng.NextFloat(), -3 + 6 * rng.NextFloat(), 1 + rng.NextFloat()},
                             {0.3f, 0.3f, 0.3f}, i % 2 ? 0.05f : 0.0f);
        s->AddSpotLight({0, 0, 2}, {0, 0.3f, -1}, {4, 4, 4}, 1.0f, 0.2f);
    }
    s->Commit();
    return s;
}

// Per pixel (the sum of its RGB channels), the mean and the variance of the mean over kRuns
// renders.
struct RunStatistics {
    std::vector<double> mean, variance_of_mean;
};

// bsdf_samples_on_diffuse: both strategies at diffuse hits too (the MIS partition under test), else the defaults.
RunStatistics RenderRuns(std::shared_ptr<RenderScene> scene, LightSelection selection, int samples,
                         int candidates = RenderOptions{}.ris_candidates, bool bsdf_samples_on_diffuse = true) {
    const size_t pixels = size_t(kSide) * kSide;
    std::vector<double> sum(pixels, 0), sum2(pixels, 0);
    std::vector<float> img(pixels * 4);
    for (int run = 1; run <= kRuns; ++run) {
        RenderOptions o;
        o.light_selection = selection;
        o.ris_candidates = candidates;
        o.pattern = Pattern::Independent;
        o.bsdf_samples_on_diffuse = bsdf_samples_on_diffuse;
        o.seed = uint64_t(run);
        o.threads = 2;
        Renderer r(scene, o);
        EXPECT_TRUE(r.Render(samples));
        r.Image(0, img.data());
        for (size_t p = 0; p < pixels; ++p) {
            const double x = double(img[4 * p]) + img[4 * p + 1] + img[4 * p + 2];
            sum[p] += x;
            sum2[p] += x * x;
        }
    }
    RunStatistics out{std::vector<double>(pixels), std::vector<double>(pixels)};
    for (size_t p = 0; p < pixels; ++p) {
        out.mean[p] = sum[p] / kRuns;
        out.variance_of_mean[p] = std::max(0.0, sum2[p] / kRuns - out.mean[p] * out.mean[p]) / (kRuns - 1);
    }
    return out;
}

// Welch's t of each block's mean between a and b (runs independent across blocks' pixels too: the block's mean
// is a mean over its pixels' independent estimates).
void ExpectBlockMeansAgree(const RunStatistics& a, const RunStatistics& b) {
    int lit_blocks = 0;
    for (int by = 0; by < kSide; by += kBlock)
        for (int bx = 0; bx < kSide; bx += kBlock) {
            double ma = 0, mb = 0, va = 0, vb = 0;
            for (int y = by; y < by + kBlock; ++y)
                for (int x = bx; x < bx + kBlock; ++x) {
                    const size_t p = size_t(y) * kSide + x;
                    ma += a.mean[p], mb += b.mean[p], va += a.variance_of_mean[p], vb += b.variance_of_mean[p];
                }
            if (ma > 0) ++lit_blocks;
            const double sigma = std::sqrt(va + vb);
            EXPECT_LE(std::abs(ma - mb), 6 * sigma + 1e-9 * (ma + mb))
                << "block (" << bx << ", " << by << "): " << ma << " vs " << mb << ", sigma " << sigma;
        }
    EXPECT_GT(lit_blocks, 8);
}

double MeanVarianceOfMean(const RunStatistics& s) {
    double v = 0;
    for (double x : s.variance_of_mean) v += x;
    return v / double(s.variance_of_mean.size());
}

TEST(RisLightSelection, MeanIsTheTreesOnFourLights) {
    auto scene = FloorUnderLights(4, false, false, 0.6f);
    ExpectBlockMeansAgree(RenderRuns(scene, LightSelection::Ris, 8), RenderRuns(scene, LightSelection::Tree, 8));
}

TEST(RisLightSelection, MeanIsTheTreesOnManyLightsWithDeltaLightsInTheTree) {
    auto scene = FloorUnderLights(2000, true, true, 0.1f);
    ExpectBlockMeansAgree(RenderRuns(scene, LightSelection::Ris, 4), RenderRuns(scene, LightSelection::Tree, 4));
    // Two candidates and 16: each unbiased, whatever M.
    ExpectBlockMeansAgree(RenderRuns(scene, LightSelection::Ris, 2, 2), RenderRuns(scene, LightSelection::Ris, 2, 16));
}

// 10,000 lights (the largest): still the tree's mean (one camera sample per run, 24 runs).
TEST(RisLightSelection, MeanIsTheTreesOnTenThousandLights) {
    auto scene = FloorUnderLights(10000, false, false, 0.05f);
    ExpectBlockMeansAgree(RenderRuns(scene, LightSelection::Ris, 1), RenderRuns(scene, LightSelection::Tree, 1));
}

// Under many small lights the tree's choice follows its nodes' bounds, the target each light's exact unshadowed
// contribution: at equal samples (default M and MIS, diffuse hits taking light samples alone) ris's variance is well
// below the tree's (measured: docs/light_selection_ris.md); asserted < 0.4.
TEST(RisLightSelection, LowerVarianceThanTheTreeUnderManyLights) {
    auto scene = FloorUnderLights(2000, false, false, 0.1f);
    const double ris = MeanVarianceOfMean(RenderRuns(scene, LightSelection::Ris, 4, 8, false));
    const double tree = MeanVarianceOfMean(RenderRuns(scene, LightSelection::Tree, 4, 8, false));
    ASSERT_GT(tree, 0);
    EXPECT_LT(ris / tree, 0.4) << "ris " << ris << ", tree " << tree;
}

// With one candidate the resampling keeps it whenever it adds light, with weight 1: "tree"'s image up to rounding
// (the tree's samples of rectangles are batched, ris's not).
TEST(RisLightSelection, OneCandidateIsTheTree) {
    auto scene = FloorUnderLights(50, true, true, 0.3f);
    const size_t n = size_t(kSide) * kSide * 4;
    std::vector<float> ris(n), tree(n);
    for (LightSelection selection : {LightSelection::Ris, LightSelection::Tree}) {
        RenderOptions o;
        o.light_selection = selection;
        o.ris_candidates = 1;
        Renderer r(scene, o);
        ASSERT_TRUE(r.Render(4));
        r.Image(0, selection == LightSelection::Ris ? ris.data() : tree.data());
    }
    for (size_t i = 0; i < n; ++i) ASSERT_NEAR(ris[i], tree[i], 1e-4f * (1 + tree[i])) << i;
}

// The reservoir over a queue: the kept entry is the one Weigh kept, scaled by (sum w / M) / w_kept; entries queued
// before it are left alone.
TEST(RisLightSelection, ReservoirKeepsOneEntryWithItsWeight) {
    std::vector<DeferredShadowRay> queue(1);
    queue[0].contribution = {7, 7, 7};
    const ShadowSink sink{&queue, 0, {2, 2, 2}};
    LightSampleReservoir reservoir(sink);
    const ShadowSink candidates = reservoir.CandidateSink();
    candidates.Add({0, 0, 0}, {0, 0, 1}, 1, {1, 1, 1});  // w 1: kept (the first)
    reservoir.Weigh(0.9f);
    reservoir.Weigh(0.5f);                               // nothing queued: w 0
    candidates.Add({0, 0, 0}, {0, 0, 1}, 1, {3, 3, 3});  // w 3: kept for u < 3 / 4
    reservoir.Weigh(0.7f);
    candidates.Add({0, 0, 0}, {0, 0, 1}, 1, {4, 4, 4});  // w 4: dropped for u >= 4 / 8
    reservoir.Weigh(0.5f);
    reservoir.Finish();
    ASSERT_EQ(queue.size(), 2u);
    EXPECT_EQ(queue[0].contribution.x, 7);
    // (3, 3, 3) x 2 x (8 / 4) / 3
    EXPECT_NEAR(queue[1].contribution.x, 4.0f, 1e-6f);
}

}  // namespace
}  // namespace sphrect::render
