// The batched rectangle technique (core/rectangle_batch.h) against its scalar reference
// (rectangle.h), sample by sample: on the hard-case suite and on random lights and points.
//
// The batch computes in double, as the scalar code, and differs by rounding only (its own sin,
// cos and atan, a few operations reordered): errors the scalar code bounds in the map's (u, v)
// space by its estimate (19), which the batch keeps below 5e-11 (otherwise the lane takes the
// scalar path itself: those samples must be the scalar ones bit for bit).
//  - Random lights and points: a sample's point lies in the scalar map's image of the square
//    (u, v) +- 1e-9 (its bounding box in the light's edge coordinates, widened by 4 float ulps of
//    rounding); its pdf within 1e-6 relative of the scalar setup's; its direction within 1e-5.
//  - The hard-case suite: the suite's own guarantees (test_hard_cases.cpp), since there a tiny
//    (u, v) error is a large one on the light (a point 1e-6 above a light sees its far edges at
//    grazing angles: the scalar sample itself is up to 1e-5 of the light's size from the exact
//    map's there): no NaN or Inf; validity as the scalar setup's; the point on the light within
//    1e-5 of its size; the pdf within 1e-6 of the scalar setup's and equal to the scalar
//    RectanglePDF of the returned point within 2e-7 (its float rounding); the direction within
//    1e-4 of the scalar sample's.
// Every instruction set the build has code for and this machine runs (AVX-512, AVX2, SSE4, ...) is tested, each
// forced in turn.  Deterministic inputs (fixed seeds): no false failures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/hard_cases.h"
#include "core/rectangle.h"
#include "core/rectangle_batch.h"
#include "core/rectangle_cosine.h"
#include "core/rng.h"
#include "hwy/targets.h"
#include "rect_batch_inputs.h"
#include "simd_targets.h"

namespace sphrect {
namespace {

struct BatchComparison {
    size_t samples = 0, vector_points = 0, valid_points = 0;
};

// Whether the point p of the light lies in the scalar map's image of the square (u, v) +- delta: within the
// bounding box of its corners' images in the light's edge coordinates, widened by `slack`.
bool InImageOfSquare(const RectangleSetup<float>& setup, double u, double v, double delta, const Vec3f& p,
                     double slack) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (double du : {-delta, delta})
        for (double dv : {-delta, delta}) {
            double x, y, X, Y;
            RectangleMapLocal(setup, std::clamp(u + du, 0.0, 1.0), std::clamp(v + dv, 0.0, 1.0), &x, &y);
            RectangleToEdgeFrame(setup, x, y, &X, &Y);
            const double c[2] = {X, Y};
            for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
        }
    const Point2<double> e = EdgeOffsets(setup.plane, p);  // from the corner
    const double c[2] = {setup.plane.x0 + e.u, setup.plane.y0 + e.v};
    for (int a = 0; a < 2; ++a)
        if (!(c[a] >= lo[a] - slack && c[a] <= hi[a] + slack)) return false;
    return true;
}

// Compares the batch with SampleRectangle(MakeRectangleSetup(o, frame), uv) -- or, given normals, the cosine batch
// with SampleRectangleCosine(MakeRectangleCosineSetup(o, normal, frame), uv) -- for every point and sample; `hard`:
// by the hard-case suite's guarantees rather than sample by sample (see above).
BatchComparison CompareBatch(const RectLight<float>& light, const std::vector<Vec3f>& origins,
                             const std::vector<Point2<float>>& uv, int m, const std::string& what, bool hard = false,
                             const std::vector<Vec3f>* normals = nullptr) {
    const RectLightFrame<float> frame = MakeRectLightFrame(light);
    std::vector<LightSample<float>> batch(origins.size() * size_t(m));
    BatchComparison c;
    c.vector_points = normals ? SampleRectangleCosineBatch(frame, origins.data(), normals->data(), origins.size(),
                                                           uv.data(), m, batch.data())
                              : SampleRectangleBatch(frame, origins.data(), origins.size(), uv.data(), m, batch.data());
    for (size_t i = 0; i < origins.size(); ++i) {
        RectangleCosineSetup<float> cosine;
        if (normals) cosine = MakeRectangleCosineSetup(origins[i], (*normals)[i], frame);
        const RectangleSetup<float> setup = normals ? cosine.rect : MakeRectangleSetup(origins[i], frame);
        c.valid_points += setup.valid && !setup.area_fallback && !setup.polish_x && (!normals || cosine.valid);
        for (int k = 0; k < m; ++k) {
            const size_t j = i * size_t(m) + size_t(k);
            const LightSample<float> ref =
                normals ? SampleRectangleCosine(cosine, uv[j]) : SampleRectangle(setup, uv[j]);
            const LightSample<float> got = batch[j];
            // Where the map is evaluated: (u, v), or for the cosine its bilinear warp.
            const Point2<double> at =
                normals ? SampleBilinear({uv[j].u, uv[j].v}, cosine.w) : Point2<double>{uv[j].u, uv[j].v};
            ++c.samples;
            SCOPED_TRACE(what + " point " + std::to_string(i) + " sample " + std::to_string(k));
            EXPECT_EQ(ref.pdf > 0, got.pdf > 0);
            if (!(ref.pdf > 0) || !(got.pdf > 0)) continue;
            // (The cosine's pdf is a bilinear factor in [0, 4] times 1 / Omega: near 0 compared on that scale.)
            EXPECT_NEAR(got.pdf, ref.pdf, 1e-6 * ref.pdf + (normals ? 1e-7 * 4 * setup.pdf : 0.0));
            if (setup.area_fallback || setup.polish_x) {  // the scalar path's own samples
                EXPECT_EQ(Length(Vec3d(got.point) - Vec3d(ref.point)), 0.0);
                EXPECT_TRUE(got.pdf == ref.pdf && got.dist == ref.dist);
                continue;
            }
            const Vec3d p = Vec3d(ref.point);
            const double slack =
                4 * std::numeric_limits<float>::epsilon() * std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
            if (hard) {
                const Point2<double> e = EdgeOffsets(setup.plane, got.point);
                const double on_light = 1e-5 * std::max(frame.wx, frame.wy);
                EXPECT_TRUE(e.u >= -on_light && e.u <= frame.wx + on_light && e.v >= -on_light &&
                            e.v <= frame.wy + on_light);
                if (!normals) {
                    EXPECT_NEAR(RectanglePDF(setup, got.point) / got.pdf, 1.0, 2e-7);
                }
                EXPECT_LE(Length(Vec3d(got.dir) - Vec3d(ref.dir)), 1e-4);
            } else {
                EXPECT_TRUE(InImageOfSquare(setup, at.u, at.v, 1e-9, got.point, slack));
                EXPECT_LE(Length(Vec3d(got.dir) - Vec3d(ref.dir)), 1e-5);
            }
            EXPECT_TRUE(std::isfinite(got.pdf) && std::isfinite(got.dist) && IsFinite(got.dir) && IsFinite(got.point));
        }
    }
    return c;
}

void MatchesScalarOnTheHardCases();
void MatchesScalarOnRandomLightsAndPoints();

TEST(RectangleBatch, RunsOnEveryInstructionSet) {
    // The x86-64 targets a user's machine may take: AVX2 at least, AVX-512 where present.
    const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
    EXPECT_GE(targets.size(), 2u);
    EXPECT_NE(std::find(targets.begin(), targets.end(), int64_t(HWY_AVX2)), targets.end());
    // Each forced in turn is the one the dispatch takes.
    for (const int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        EXPECT_STREQ(RectangleBatchTarget(), hwy::TargetName(target));
    }
    hwy::SetSupportedTargetsForTest(0);
}

TEST(RectangleBatch, MatchesScalarOnTheHardCases) {
    ForEachTarget([] { MatchesScalarOnTheHardCases(); });
}

TEST(RectangleBatch, MatchesScalarOnRandomLightsAndPoints) {
    ForEachTarget([] { MatchesScalarOnRandomLightsAndPoints(); });
}

void MatchesScalarOnTheHardCases() {
    size_t vector_points = 0, points = 0;
    for (const HardCase& hc : HardCaseSuite()) {
        const RectBatchInputs b = HardCaseBatch(hc);
        vector_points += CompareBatch(b.light, b.origins, b.uv, b.m, b.name, true).vector_points;
        points += b.origins.size();
        const std::vector<Vec3f> normals(b.origins.size(), hc.normal);  // rectangle_cosine, with the suite's normals
        CompareBatch(b.light, b.origins, b.uv, b.m, b.name + " cosine", true, &normals);
    }
    // Most of the suite is handled by the vector code (the rest, nearly edge-on or degenerate, by the scalar path).
    std::printf("hard cases: %zu of %zu points on the vector path (%s)\n", vector_points, points,
                RectangleBatchTarget());
    EXPECT_GT(vector_points, points / 3);
}

void MatchesScalarOnRandomLightsAndPoints() {
    PCG32 rng(7, 3);
    size_t vector_points = 0, points = 0, cosine_vector_points = 0, cosine_points = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const RectBatchInputs b = RandomRectBatch(rng, trial);
        const BatchComparison c = CompareBatch(b.light, b.origins, b.uv, b.m, b.name);
        vector_points += c.vector_points;
        points += c.valid_points;
        // rectangle_cosine at the same points, with random normals (some facing away: weights 0 or invalid).
        std::vector<Vec3f> normals;
        for (size_t i = 0; i < b.origins.size(); ++i)
            normals.push_back(Vec3f(rng.NextFloat() - 0.5f, rng.NextFloat() - 0.5f, rng.NextFloat() - 0.5f));
        const BatchComparison cc = CompareBatch(b.light, b.origins, b.uv, b.m, "cosine " + b.name, false, &normals);
        cosine_vector_points += cc.vector_points;
        cosine_points += cc.valid_points;
    }
    EXPECT_GT(cosine_vector_points, cosine_points * 19 / 20);
    // Away from the hard cases nearly every setup that needs neither polish nor fallback is a vector lane.
    EXPECT_GT(vector_points, points * 19 / 20);
}

TEST(RectangleBatch, FollowsTheScalarPathWhereTheSetupIsInvalid) {
    const RectBatchInputs b = InvalidSetupBatch();
    EXPECT_EQ(CompareBatch(b.light, b.origins, b.uv, 1, b.name).vector_points, 1u);
    CompareBatch(DegenerateRectLight(), b.origins, b.uv, 1, "degenerate");
}

}  // namespace
}  // namespace sphrect
