// A 2-D piecewise-constant distribution over a grid of cells, as pbrt-v4's PiecewiseConstant2D and Cycles'
// background map: a marginal distribution over the rows, a conditional one over each row's cells, each the 1-D
// discrete distribution LightSelector (light_selector.h); the chosen cell is filled uniformly.  Coordinates
// (u, v) in [0, 1)^2: cell column floor(u * width), row floor(v * height).
#pragma once

#include <algorithm>
#include <vector>

#include "core/rng.h"  // kOneMinusEpsilonF
#include "core/vec3.h"
#include "light_selector.h"

namespace sphrect::render {

struct Distribution2D {
    int width = 0, height = 0;
    LightSelector marginal;                  // over the rows, by their summed weights
    std::vector<LightSelector> conditional;  // per row, over its cells

    // weights: width x height, row-major (row 0 first); non-finite or negative weights count as 0.
    void Build(int w, int h, const std::vector<double>& weights) {
        width = w;
        height = h;
        conditional.assign(size_t(h), {});
        std::vector<double> row_sums(static_cast<size_t>(h), 0.0), row(static_cast<size_t>(w));
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const double v = weights[size_t(y) * size_t(w) + size_t(x)];
                row[size_t(x)] = v > 0 && v < 1e300 ? v : 0.0;
                row_sums[size_t(y)] += row[size_t(x)];
            }
            conditional[size_t(y)].Build(row);
        }
        marginal.Build(row_sums);
    }
    // No cell has weight: nothing to sample (and every pdf is 0).
    bool Empty() const { return marginal.Empty(); }
};

namespace distribution_detail {

// Cell i of n and the point r in [0, 1) inside it, as a coordinate in [0, 1).
inline float CellCoordinate(int i, float r, int n) { return std::min((float(i) + r) / float(n), kOneMinusEpsilonF); }

inline int CellOf(float x, int n) { return std::clamp(int(x * float(n)), 0, n - 1); }

// The 1-D inverse: the u that SelectRemapped maps to cell i at relative position r.
inline float InvertSelect(const LightSelector& s, int i, float r) {
    const float lo = i > 0 ? s.cdf[size_t(i) - 1] : 0.0f;
    return std::clamp(lo + r * (s.cdf[size_t(i)] - lo), 0.0f, kOneMinusEpsilonF);
}

}  // namespace distribution_detail

struct Distribution2DSample {
    Point2<float> uv;
    float pdf = 0;  // w.r.t. du dv; 0: nothing sampled (an empty distribution)
};

// u.v picks the row (marginal), u.u the cell within it (conditional).
inline Distribution2DSample SampleDistribution2D(const Distribution2D& d, Point2<float> u) {
    using namespace distribution_detail;
    if (d.Empty()) return {};
    float rv, ru;
    const int y = d.marginal.SelectRemapped(u.v, &rv);
    const LightSelector& row = d.conditional[size_t(y)];
    const int x = row.SelectRemapped(u.u, &ru);
    const float pdf = d.marginal.pmf[size_t(y)] * float(d.height) * row.pmf[size_t(x)] * float(d.width);
    return {{CellCoordinate(x, ru, d.width), CellCoordinate(y, rv, d.height)}, pdf};
}

inline float Distribution2DPDF(const Distribution2D& d, Point2<float> uv) {
    using namespace distribution_detail;
    if (d.Empty()) return 0;
    const int x = CellOf(uv.u, d.width), y = CellOf(uv.v, d.height);
    return d.marginal.pmf[size_t(y)] * float(d.height) * d.conditional[size_t(y)].pmf[size_t(x)] * float(d.width);
}

// The u that SampleDistribution2D maps to uv (a cell of positive weight).
inline Point2<float> InvertDistribution2DSample(const Distribution2D& d, Point2<float> uv) {
    using namespace distribution_detail;
    if (d.Empty()) return {};
    const int x = CellOf(uv.u, d.width), y = CellOf(uv.v, d.height);
    const float rx = std::clamp(uv.u * float(d.width) - float(x), 0.0f, 1.0f);
    const float ry = std::clamp(uv.v * float(d.height) - float(y), 0.0f, 1.0f);
    return {InvertSelect(d.conditional[size_t(y)], x, rx), InvertSelect(d.marginal, y, ry)};
}

}  // namespace sphrect::render
