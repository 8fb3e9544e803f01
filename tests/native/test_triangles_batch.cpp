// The batched `triangles` technique (core/triangles_batch.h) against its scalar reference (triangles.h), sample by
// sample, on every instruction set (simd_targets.h).
//
// The batch computes in double, as the scalar code, and differs by rounding only (its own sin, cos and atan, a few
// operations reordered, fused multiply-adds); the lanes whose triangles' solid angles may need the planar
// recomputation take the scalar path (those samples must be the scalar ones bit for bit).
//  - Random lights and points: the pdf within 1e-6 relative of the scalar setup's, the direction within 1e-5 of the
//    scalar sample's, the point within 1e-5 of the light's size of it.
//  - The hard-case suite (points 1e-9 .. 1e-1 of the size above the plane, 1e-6 .. 1e6 sizes away): validity as the
//    scalar setup's, no NaN or Inf, the pdf within 1e-6 relative, the direction within 1e-4, the point on the light
//    within 1e-5 of its size -- there a rounding-sized change of the map's inputs moves the point that much (as for
//    the rectangle's batch, test_rectangle_batch.cpp).
//  - Where u lies within 1e-12 of the split p1 between the two triangles (the suite's points on the diagonal's plane
//    have p1 = 1/2 = u up to rounding), rounding decides the triangle: there the sample is compared on the light and
//    by its pdf only.
// Deterministic inputs (fixed seeds): no false failures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/hard_cases.h"
#include "core/rng.h"
#include "core/triangles.h"
#include "core/triangles_batch.h"
#include "simd_targets.h"

namespace sphrect {
namespace {

struct BatchComparison {
    size_t vector_points = 0, valid_points = 0;
};

BatchComparison CompareBatch(const RectLight<float>& light, const std::vector<Vec3f>& origins,
                             const std::vector<Point2<float>>& uv, int m, const std::string& what, bool hard) {
    const RectLightFrame<float> frame = MakeRectLightFrame(light);
    std::vector<LightSample<float>> batch(origins.size() * size_t(m));
    BatchComparison c;
    c.vector_points = SampleTrianglesBatch(frame, origins.data(), origins.size(), uv.data(), m, batch.data());
    const double size = std::max(frame.wx, frame.wy);
    for (size_t i = 0; i < origins.size(); ++i) {
        const TrianglesSetup<float> setup = MakeTrianglesSetup(origins[i], frame);
        c.valid_points += setup.valid;
        for (int k = 0; k < m; ++k) {
            const size_t j = i * size_t(m) + size_t(k);
            const LightSample<float> ref = SampleTriangles(setup, uv[j]), got = batch[j];
            SCOPED_TRACE(what + " point " + std::to_string(i) + " sample " + std::to_string(k));
            EXPECT_EQ(ref.pdf > 0, got.pdf > 0);
            if (!(ref.pdf > 0) || !(got.pdf > 0)) continue;
            EXPECT_TRUE(std::isfinite(got.pdf) && std::isfinite(got.dist) && IsFinite(got.dir) && IsFinite(got.point));
            EXPECT_NEAR(got.pdf / ref.pdf, 1.0, 1e-6);
            // (u at the split between the triangles, p1 up to rounding, may go to either: compared on the light only.)
            const bool at_split = std::abs(double(uv[j].u) - setup.p1) <= 1e-12;
            if (!at_split) {
                EXPECT_LE(Length(Vec3d(got.point) - Vec3d(ref.point)), 1e-5 * size + 4e-7 * Length(Vec3d(ref.point)));
                EXPECT_LE(Length(Vec3d(got.dir) - Vec3d(ref.dir)), hard ? 1e-4 : 1e-5);
            }
            // On the light: its offsets from the corner along the edges within [0, w] (+ 1e-5 of the size).
            const Point2<double> e = EdgeOffsets(setup.plane, got.point);
            const double on_light = 1e-5 * size;
            EXPECT_TRUE(e.u >= -on_light && e.u <= frame.wx + on_light && e.v >= -on_light &&
                        e.v <= frame.wy + on_light);
        }
    }
    return c;
}

void MatchesScalarOnTheHardCases() {
    std::vector<Point2<float>> grid;
    for (float u : HardCaseUV())
        for (float v : HardCaseUV()) grid.push_back({u, v});
    const int m = int(grid.size());
    size_t vector_points = 0, points = 0;
    for (const HardCase& hc : HardCaseSuite()) {
        // Each case's point three times (a batch of one light): every lane position of a vector.
        const std::vector<Vec3f> origins(3, hc.origin);
        std::vector<Point2<float>> uv;
        for (int r = 0; r < 3; ++r) uv.insert(uv.end(), grid.begin(), grid.end());
        vector_points += CompareBatch(hc.light, origins, uv, m, hc.name, true).vector_points;
        points += origins.size();
    }
    // Most of the suite is handled by the vector code (the rest, nearly edge-on or degenerate, by the scalar path).
    std::printf("hard cases: %zu of %zu points on the vector path\n", vector_points, points);
    EXPECT_GT(vector_points, points / 3);
}

void MatchesScalarOnRandomLightsAndPoints() {
    PCG32 rng(13, 9);
    size_t vector_points = 0, points = 0;
    for (int trial = 0; trial < 200; ++trial) {
        // A random orthogonal pair of edges of random lengths, one- or two-sided.
        const Vec3d a = Normalize(Vec3d(rng.NextFloat() - 0.5, rng.NextFloat() - 0.5, rng.NextFloat() - 0.5));
        const Vec3d b = Normalize(Cross(a, Vec3d(0.3, 0.5, 0.8)));
        const RectLight<float> light{Vec3f(float(rng.NextFloat() * 4 - 2), float(rng.NextFloat() * 4 - 2), 1.f),
                                     Vec3f(a * (0.05 + 3 * rng.NextFloat())), Vec3f(b * (0.05 + 3 * rng.NextFloat())),
                                     trial % 3 != 0};
        const int n = 1 + trial % 19, m = 1 + trial % 4;  // every remainder of a vector's lanes
        std::vector<Vec3f> origins;
        std::vector<Point2<float>> uv;
        for (int i = 0; i < n; ++i) {
            origins.push_back(Vec3f(rng.NextFloat() * 10 - 5, rng.NextFloat() * 10 - 5, rng.NextFloat() * 10 - 5));
            for (int k = 0; k < m; ++k) uv.push_back({rng.NextFloat(), rng.NextFloat()});
        }
        const BatchComparison c = CompareBatch(light, origins, uv, m, "trial " + std::to_string(trial), false);
        vector_points += c.vector_points;
        points += c.valid_points;
    }
    // Away from the hard cases nearly every valid setup is a vector lane.
    EXPECT_GT(vector_points, points * 19 / 20);
}

TEST(TrianglesBatch, MatchesScalarOnTheHardCases) {
    ForEachTarget([] { MatchesScalarOnTheHardCases(); });
}

TEST(TrianglesBatch, MatchesScalarOnRandomLightsAndPoints) {
    ForEachTarget([] { MatchesScalarOnRandomLightsAndPoints(); });
}

TEST(TrianglesBatch, FollowsTheScalarPathWhereTheSetupIsInvalid) {
    ForEachTarget([] {
        const RectLight<float> one_sided{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, false};  // emits towards -z
        const std::vector<Vec3f> origins = {{0.5f, 0.5f, 2},                       // behind: pdf 0
                                            {0.5f, 0.5f, 0},                       // in front
                                            {0.5f, 0.5f, 1},                       // in its plane: pdf 0
                                            {NAN, 0, 0},                           // not finite: pdf 0
                                            {0, INFINITY, 0}};
        const std::vector<Point2<float>> uv(origins.size(), {0.3f, 0.6f});
        EXPECT_EQ(CompareBatch(one_sided, origins, uv, 1, "one-sided", false).vector_points, 1u);
        // A degenerate light: every sample invalid.
        CompareBatch({{0, 0, 1}, {0, 0, 0}, {0, 1, 0}, true}, origins, uv, 1, "degenerate", false);
    });
}

}  // namespace
}  // namespace sphrect
