// The batched triangle emitter (core/triangle_batch.h) against its scalar reference (core/triangle_emitter.h),
// request by request, on every instruction set (simd_targets.h).
//
// The batch computes in double, as the scalar code, and differs by rounding only (its own sin, cos and atan, a few
// operations reordered, fused multiply-adds); the lanes whose solid angle may need the planar recomputation take the
// scalar path (those samples must be the scalar ones bit for bit).
//  - Random triangles and points: the direction within 1e-6 of the scalar sample's, the distance and the pdf within
//    1e-6 relative.
//  - Hard configurations (points 1e-7 .. 1e-3 of the size from the plane, triangles 1e4 sizes away, slivers of
//    aspect 1e-4, points on the triangle's edges' lines): validity as the scalar setup's, no NaN or Inf, the pdf
//    within 1e-6 relative, the direction within 1e-4, the point on the triangle's plane within 1e-5 of the size
//    (plus float rounding of its coordinates).
// Deterministic inputs (fixed seeds): no false failures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/rng.h"
#include "core/triangle_batch.h"
#include "core/triangle_emitter.h"
#include "simd_targets.h"

namespace sphrect {
namespace {

struct Request {
    TriangleEmitter tri;
    Vec3f origin;
    Point2<float> uv;
};

// Compares the batch over `requests` with the scalar reference; returns how many took the vector path.
size_t CompareBatch(const std::vector<Request>& requests, bool hard) {
    std::vector<TriangleEmitter> tris;
    std::vector<Vec3f> origins;
    std::vector<Point2<float>> uv;
    for (const Request& r : requests) {
        tris.push_back(r.tri);
        origins.push_back(r.origin);
        uv.push_back(r.uv);
    }
    std::vector<LightSample<float>> out(requests.size());
    const size_t vector_requests =
        SampleTriangleEmitterBatch(tris.data(), origins.data(), tris.size(), uv.data(), out.data());
    for (size_t i = 0; i < requests.size(); ++i) {
        const Request& r = requests[i];
        SCOPED_TRACE("request " + std::to_string(i));
        const LightSample<float> ref = SampleTriangleSolidAngle(
                                     MakeTriangleSolidAngleSetup(r.tri.v0, r.tri.e1, r.tri.e2, r.origin), r.origin,
                                     r.uv),
                                 got = out[i];
        EXPECT_EQ(ref.pdf > 0, got.pdf > 0);
        if (!(ref.pdf > 0) || !(got.pdf > 0)) continue;
        EXPECT_TRUE(std::isfinite(got.pdf) && std::isfinite(got.dist) && IsFinite(got.dir) && IsFinite(got.point));
        EXPECT_NEAR(got.pdf / ref.pdf, 1.0, 1e-6);
        if (!hard) {
            EXPECT_LE(Length(Vec3d(got.dir) - Vec3d(ref.dir)), 1e-6);
            EXPECT_NEAR(got.dist / ref.dist, 1.0, 1e-6);
            continue;
        }
        EXPECT_LE(Length(Vec3d(got.dir) - Vec3d(ref.dir)), 1e-4);
        const Vec3d n = Normalize(Cross(Vec3d(r.tri.e1), Vec3d(r.tri.e2)));
        const double size = std::max(Length(Vec3d(r.tri.e1)), Length(Vec3d(r.tri.e2)));
        const Vec3d p(got.point);
        const double rounding =
            4 * std::numeric_limits<float>::epsilon() * std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
        EXPECT_LE(std::abs(Dot(p - Vec3d(r.tri.v0), n)), 1e-5 * size + rounding);
    }
    return vector_requests;
}

Vec3f RandomVector(PCG32& rng, float scale) {
    return Vec3f(rng.NextFloat() - 0.5f, rng.NextFloat() - 0.5f, rng.NextFloat() - 0.5f) * scale;
}

void MatchesScalarOnRandomTriangles() {
    PCG32 rng(11, 5);
    std::vector<Request> requests;
    for (int i = 0; i < 2000; ++i)
        requests.push_back({{RandomVector(rng, 4), RandomVector(rng, 2), RandomVector(rng, 2)},
                            RandomVector(rng, 10),
                            {rng.NextFloat(), rng.NextFloat()}});
    const size_t vector_requests = CompareBatch(requests, false);
    EXPECT_GT(vector_requests, requests.size() * 19 / 20);  // nearly all: these are well-conditioned
}

void MatchesScalarOnHardTriangles() {
    PCG32 rng(13, 7);
    std::vector<Request> requests;
    const TriangleEmitter unit{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
        sliver{{0.3f, -0.2f, 0.1f}, {1, 0, 0}, {0.5f, 1e-4f, 0}};
    for (const TriangleEmitter& tri : {unit, sliver})
        for (float height : {1e-7f, 1e-5f, 1e-3f, 1.0f})
            for (const Vec3f& foot : {Vec3f(0.2f, 0.2f, 0), Vec3f(0.5f, 0, 0), Vec3f(-0.5f, -0.5f, 0),
                                      Vec3f(3, 0.1f, 0), Vec3f(1e4f, 2e4f, 0)})
                for (int k = 0; k < 20; ++k) {
                    const float u = k == 0 ? 0.0f : k == 1 ? std::nextafter(1.0f, 0.0f) : rng.NextFloat();
                    requests.push_back({tri, tri.v0 + foot + Vec3f(0, 0, height), {u, rng.NextFloat()}});
                }
    const size_t vector_requests = CompareBatch(requests, true);
    EXPECT_GT(vector_requests, 0u);
}

TEST(TriangleBatch, MatchesScalarOnRandomTriangles) {
    ForEachTarget([] { MatchesScalarOnRandomTriangles(); });
}

TEST(TriangleBatch, MatchesScalarOnHardTriangles) {
    ForEachTarget([] { MatchesScalarOnHardTriangles(); });
}

TEST(TriangleBatch, FollowsTheScalarPathWhereTheSetupIsInvalid) {
    const TriangleEmitter tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const std::vector<Request> requests = {{tri, {0.2f, 0.2f, 0}, {0.5f, 0.5f}},  // in its plane
                                           {tri, {NAN, 0, 1}, {0.5f, 0.5f}},      // not finite
                                           {{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {0, 0, 1}, {0.5f, 0.5f}},  // degenerate
                                           {tri, {0.2f, 0.2f, 1}, {0.5f, 0.5f}}};
    EXPECT_EQ(CompareBatch(requests, true), 1u);
}

}  // namespace
}  // namespace sphrect
