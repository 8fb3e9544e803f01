// The inputs the batched rectangle-light techniques' tests share (test_rectangle_batch.cpp, test_triangles_batch.cpp):
// the hard-case suite's points with its (u, v) grid, random lights and points, and the setups that must be invalid.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "core/hard_cases.h"
#include "core/rng.h"

namespace sphrect {

// One batch of one light: points with m sample points each (uv[i m + k]).
struct RectBatchInputs {
    RectLight<float> light;
    std::vector<Vec3f> origins;
    std::vector<Point2<float>> uv;
    int m = 1;
    std::string name;
};

// A hard case's point three times (every lane position of a vector), each with the suite's 9 x 9 (u, v) grid.
inline RectBatchInputs HardCaseBatch(const HardCase& hc) {
    RectBatchInputs b{hc.light, std::vector<Vec3f>(3, hc.origin), {}, 0, hc.name};
    for (int r = 0; r < 3; ++r)
        for (float u : HardCaseUV())
            for (float v : HardCaseUV()) b.uv.push_back({u, v});
    b.m = int(b.uv.size() / 3);
    return b;
}

// Trial `trial` of the random batches: a random orthogonal pair of edges of random lengths, one- or two-sided, and
// 1 .. 19 points in [-5, 5]^3 (every remainder of a vector's lanes) with 1 .. 4 sample points each.
inline RectBatchInputs RandomRectBatch(PCG32& rng, int trial) {
    const Vec3d a = Normalize(Vec3d(rng.NextFloat() - 0.5, rng.NextFloat() - 0.5, rng.NextFloat() - 0.5));
    const Vec3d b = Normalize(Cross(a, Vec3d(0.3, 0.5, 0.8)));
    RectBatchInputs in{
        {Vec3f(float(rng.NextFloat() * 4 - 2), float(rng.NextFloat() * 4 - 2), 1.f),
         Vec3f(a * (0.05 + 3 * rng.NextFloat())), Vec3f(b * (0.05 + 3 * rng.NextFloat())), trial % 3 != 0},
        {},
        {},
        1 + trial % 4,
        "trial " + std::to_string(trial)};
    const int n = 1 + trial % 19;
    for (int i = 0; i < n; ++i) {
        in.origins.push_back(Vec3f(rng.NextFloat() * 10 - 5, rng.NextFloat() * 10 - 5, rng.NextFloat() * 10 - 5));
        for (int k = 0; k < in.m; ++k) in.uv.push_back({rng.NextFloat(), rng.NextFloat()});
    }
    return in;
}

// A one-sided unit square at z = 1 emitting towards -z, seen from points whose setups are invalid but the second's.
inline RectBatchInputs InvalidSetupBatch() {
    RectBatchInputs b{{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, false},
                      {{0.5f, 0.5f, 2},  // behind: pdf 0
                       {0.5f, 0.5f, 0},  // in front
                       {0.5f, 0.5f, 1},  // in its plane: pdf 0
                       {NAN, 0, 0},      // not finite: pdf 0
                       {0, INFINITY, 0}},
                      {},
                      1,
                      "one-sided"};
    b.uv.assign(b.origins.size(), {0.3f, 0.6f});
    return b;
}

// A degenerate light (a zero edge): every sample invalid.
inline RectLight<float> DegenerateRectLight() { return {{0, 0, 1}, {0, 0, 0}, {0, 1, 0}, true}; }

}  // namespace sphrect
