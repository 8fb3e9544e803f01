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

#include "core/triangles.h"
#include "core/triangles_batch.h"
#include "rect_batch_inputs.h"
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
    size_t vector_points = 0, points = 0;
    for (const HardCase& hc : HardCaseSuite()) {
        const RectBatchInputs b = HardCaseBatch(hc);
        vector_points += CompareBatch(b.light, b.origins, b.uv, b.m, b.name, true).vector_points;
        points += b.origins.size();
    }
    // Most of the suite is handled by the vector code (the rest, nearly edge-on or degenerate, by the scalar path).
    std::printf("hard cases: %zu of %zu points on the vector path\n", vector_points, points);
    EXPECT_GT(vector_points, points / 3);
}

void MatchesScalarOnRandomLightsAndPoints() {
    PCG32 rng(13, 9);
    size_t vector_points = 0, points = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const RectBatchInputs b = RandomRectBatch(rng, trial);
        const BatchComparison c = CompareBatch(b.light, b.origins, b.uv, b.m, b.name, false);
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
        const RectBatchInputs b = InvalidSetupBatch();
        EXPECT_EQ(CompareBatch(b.light, b.origins, b.uv, 1, b.name, false).vector_points, 1u);
        CompareBatch(DegenerateRectLight(), b.origins, b.uv, 1, "degenerate", false);
    });
}

}  // namespace
}  // namespace sphrect
