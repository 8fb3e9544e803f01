// A rectangle light of varying radiance sampled by its blocks' radiance and solid angle (the paper's "future work":
// importance sampling of an emissive texture together with the solid angle).  The light is cut into nx x ny equal
// blocks along its edges, each of a mean radiance L_b (the caller's, from its texture).  At a shading point a block
// is chosen with probability P(b) = w_b / sum w, w_b = L_b x Omega~_b, Omega~_b a cheap estimate of the solid angle
// the block subtends (its area x cosine / distance^2 at its centre, at most 2 pi: MakeRectangleBlocksAt); then a point
// in it by the rectangle map (rectangle.h) of that block's sub-rectangle.  The pdf of a point p in block b is P(b) /
// Omega(b) -- P(b) times the map's pdf, which is the area fallback's where the map falls back (21).  Were Omega~ exact,
// the pdf would be L_b / sum L Omega: the piecewise-constant radiance over the solid angle, sampled exactly.  Any P(b)
// > 0 keeps the estimate unbiased (Omega~ only steers the choice); every block needs L_b > 0 wherever the light emits
// (the caller's floor).  With one block it is the rectangle map itself.
#pragma once

#include <algorithm>
#include <cmath>

#include "rectangle.h"

namespace sphrect {

// Blocks along each edge, at most: 16 x 16 finds the bright parts of a window, a screen or a logo, and its table at
// a shading point is ~256 multiply-adds.
constexpr int kMaxRectangleBlocksPerSide = 16;
constexpr int kMaxRectangleBlocks = kMaxRectangleBlocksPerSide * kMaxRectangleBlocksPerSide;

// The blocks' radiance: block (i, j) -- i along ex, j along ey -- is radiance[j nx + i].  Storage is the caller's.
struct RectangleBlocks {
    int nx = 0, ny = 0;
    const float* radiance = nullptr;
    int count() const { return nx * ny; }
};

// Block k's bounds along the unit edges, [u0, u1] x [v0, v1] (lengths from the corner).
template <class T>
void RectangleBlockBounds(const RectLightFrame<T>& f, const RectangleBlocks& b, int k, double* u0, double* v0,
                          double* u1, double* v1) {
    const int i = k % b.nx, j = k / b.nx;
    *u0 = f.wx * i / b.nx;
    *u1 = i + 1 == b.nx ? f.wx : f.wx * (i + 1) / b.nx;
    *v0 = f.wy * j / b.ny;
    *v1 = j + 1 == b.ny ? f.wy : f.wy * (j + 1) / b.ny;
}

// Block k's sub-rectangle of the light frame f.
template <class T>
RectLightFrame<T> RectangleBlockFrame(const RectLightFrame<T>& f, const RectangleBlocks& b, int k) {
    double u0, v0, u1, v1;
    RectangleBlockBounds(f, b, k, &u0, &v0, &u1, &v1);
    return SubRectLightFrame(f, u0, v0, u1, v1);
}

// The block holding point p of the light (clamped to the light: points on it up to rounding).
template <class T>
int RectangleBlockOf(const RectLightFrame<T>& f, const RectangleBlocks& b, const Vec3<T>& p) {
    const Vec3d q = Vec3d(p) - f.corner;
    const double s = Dot(q, f.exh) / f.wx, t = Dot(q, f.eyh) / f.wy;
    const int i = std::clamp(int(std::floor(ClampNaN(s, 0.0, 1.0) * b.nx)), 0, b.nx - 1);
    const int j = std::clamp(int(std::floor(ClampNaN(t, 0.0, 1.0) * b.ny)), 0, b.ny - 1);
    return j * b.nx + i;
}

// The blocks' table at one shading point, as a 2-D piecewise-constant distribution (pbrt's PiecewiseConstant2D): a
// column i by its weight, then a row j of it by the block's weight in the column, each coordinate of the sample
// point rescaled within its interval -- a warp that keeps the sample pattern's stratification over the light, as the
// rectangle map alone does (choosing the block by one coordinate lost it: 12x the map's MSE on a uniform image).
// column_cdf[i] = sum of the columns' weights before column i (column_cdf[nx] the total); row_cdf[i (ny + 1) + j]
// = sum of the weights of column i's blocks before row j.  Left uninitialised until set up (MakeRectangleBlocksAt):
// it lives in the light sampler of every shading point.
struct RectangleBlocksAt {
    int nx, ny;
    float column_cdf[kMaxRectangleBlocksPerSide + 1];
    float row_cdf[kMaxRectangleBlocksPerSide * (kMaxRectangleBlocksPerSide + 1)];
    bool Valid() const { return nx > 0 && column_cdf[nx] > 0 && std::isfinite(column_cdf[nx]); }
    const float* Rows(int i) const { return row_cdf + i * (ny + 1); }
};

// Sets up the table at `origin`: w_b = L_b x Omega~_b, Omega~_b the block's solid angle estimated at its centre c_b,
// area |h| / |c_b - o|^3 (h the origin's height over the light's plane), at most 2 pi; in float, its squared
// distances separable along the edges (the table costs ~256 multiply-adds and square roots per (point, light)).
template <class T>
void MakeRectangleBlocksAt(const Vec3<T>& origin, const RectLightFrame<T>& f, const RectangleBlocks& b,
                           RectangleBlocksAt& at) {
    constexpr float kTwoPi = 6.2831853f;  // a block subtends at most a hemisphere
    at.nx = f.valid ? b.nx : 0;
    at.ny = b.ny;
    const Vec3d q = Vec3d(origin) - f.corner;
    const double bw = f.wx / b.nx, bh = f.wy / b.ny, x0 = Dot(q, f.exh), y0 = Dot(q, f.eyh);
    const float h = float(std::abs(Dot(q, f.n))), h2 = h * h, area_h = float(bw * bh) * h;
    float dy2[kMaxRectangleBlocksPerSide];
    for (int j = 0; j < at.ny; ++j) {
        const float dy = float((j + 0.5) * bh - y0);
        dy2[j] = dy * dy + h2;
    }
    double total = 0;
    at.column_cdf[0] = 0;
    for (int i = 0; i < at.nx; ++i) {
        const float dx = float((i + 0.5) * bw - x0), dx2 = dx * dx;
        float* rows = at.row_cdf + i * (at.ny + 1);
        float column = 0;
        rows[0] = 0;
        for (int j = 0; j < at.ny; ++j) {
            const float d2 = dx2 + dy2[j], omega = area_h / (d2 * std::sqrt(d2));
            column += b.radiance[j * b.nx + i] * (omega < kTwoPi ? omega : kTwoPi);  // (NaN: 2 pi)
            rows[j + 1] = column;
        }
        total += column;
        at.column_cdf[i + 1] = float(total);
    }
}

// The interval of `cdf` (n + 1 entries) holding x in [0, cdf[n]), one of positive width, and x rescaled within it.
inline int ChooseInCdf(const float* cdf, int n, float x, float* rescaled, float* width) {
    int k = std::clamp(int(std::upper_bound(cdf, cdf + n + 1, x) - cdf) - 1, 0, n - 1);
    while (k > 0 && !(cdf[k + 1] > cdf[k])) --k;  // (x at the end of the table)
    *width = cdf[k + 1] - cdf[k];
    *rescaled = *width > 0 ? std::clamp((x - cdf[k]) / *width, 0.0f, std::nextafter(1.0f, 0.0f)) : 0.0f;
    return k;
}

// P(block (i, j)) at this point, as the sampling chooses it: (column i's share) x (block's share of the column).
inline float RectangleBlockProbability(const RectangleBlocksAt& at, int i, int j) {
    const float column = at.column_cdf[i + 1] - at.column_cdf[i];
    const float* rows = at.Rows(i);
    const float block = rows[j + 1] - rows[j];
    if (!(column > 0 && block > 0)) return 0;
    return (column / at.column_cdf[at.nx]) * (block / rows[at.ny]);
}

// A point of the light seen from origin: the block (i, j) by uv (column by uv.u, row by uv.v), the point in it by the
// rectangle map of uv rescaled within the block's intervals.  pdf: P(block) times the block's solid-angle pdf; 0
// (invalid) where the block subtends nothing.
template <class T>
LightSample<T> SampleRectangleBlocks(const Vec3<T>& origin, const RectLightFrame<T>& f, const RectangleBlocks& b,
                                     const RectangleBlocksAt& at, Point2<T> uv) {
    if (!at.Valid()) return {};
    float u, v, column, block;
    const int i = ChooseInCdf(at.column_cdf, at.nx, float(uv.u) * at.column_cdf[at.nx], &u, &column);
    const float* rows = at.Rows(i);
    const int j = ChooseInCdf(rows, at.ny, float(uv.v) * rows[at.ny], &v, &block);
    const float p = RectangleBlockProbability(at, i, j);
    if (!(p > 0)) return {};
    LightSample<T> s =
        SampleRectangle(MakeRectangleSetup(origin, RectangleBlockFrame(f, b, j * b.nx + i)), Point2<T>{T(u), T(v)});
    s.pdf *= T(p);
    return s;
}

// Solid-angle pdf at origin of SampleRectangleBlocks producing point p of the light.
template <class T>
T RectangleBlocksPDF(const Vec3<T>& origin, const RectLightFrame<T>& f, const RectangleBlocks& b,
                     const RectangleBlocksAt& at, const Vec3<T>& p) {
    if (!at.Valid()) return 0;
    const int k = RectangleBlockOf(f, b, p);
    const float pb = RectangleBlockProbability(at, k % b.nx, k / b.nx);
    if (!(pb > 0)) return 0;
    return T(pb) * RectanglePDF(MakeRectangleSetup(origin, RectangleBlockFrame(f, b, k)), p);
}

}  // namespace sphrect
