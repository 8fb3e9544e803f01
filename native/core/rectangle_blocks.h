// A rectangle light sampled by the power of its blocks and by solid angle (the paper's "future work": importance
// sampling of an emissive texture together with the solid angle).  The light is cut into nx x ny equal blocks
// along its edges; a block is chosen from a fixed discrete distribution (its share of the emitted power), then a
// point in it by the rectangle map (rectangle.h) of that block's sub-rectangle.  The pdf of a point p in block b
// is P(b) / Omega(b) -- P(b) times the map's pdf, which is the area fallback's where the map falls back (21).
// With one block this is the rectangle map itself.  Every block must have P(b) > 0 wherever the light emits (the
// caller's floor), else the estimate is biased.
#pragma once

#include <algorithm>
#include <cmath>

#include "rectangle.h"

namespace sphrect {

// The blocks' distribution: block (i, j) -- i along ex, j along ey -- is entry k = j nx + i of pmf, and
// cdf[k] = sum of pmf[0 .. k) (cdf[nx ny] = 1).  Storage is the caller's.
struct RectangleBlocks {
    int nx = 0, ny = 0;
    const float* pmf = nullptr;
    const float* cdf = nullptr;
    int count() const { return nx * ny; }
};

// The block of CDF value u, and u rescaled to [0, 1) within its interval (for the point in the block).
inline int ChooseRectangleBlock(const RectangleBlocks& b, float u, float* remapped) {
    const int n = b.count();
    // The last k with cdf[k] <= u, among blocks of pmf > 0.
    int k = int(std::upper_bound(b.cdf, b.cdf + n + 1, u) - b.cdf) - 1;
    k = std::clamp(k, 0, n - 1);
    while (k > 0 && !(b.pmf[k] > 0)) --k;
    const float r = b.pmf[k] > 0 ? (u - b.cdf[k]) / b.pmf[k] : u;
    *remapped = std::clamp(r, 0.0f, std::nextafter(1.0f, 0.0f));
    return k;
}

// Block k's sub-rectangle of the light frame f.
template <class T>
RectLightFrame<T> RectangleBlockFrame(const RectLightFrame<T>& f, const RectangleBlocks& b, int k) {
    const int i = k % b.nx, j = k / b.nx;
    const double u0 = f.wx * i / b.nx, u1 = i + 1 == b.nx ? f.wx : f.wx * (i + 1) / b.nx;
    const double v0 = f.wy * j / b.ny, v1 = j + 1 == b.ny ? f.wy : f.wy * (j + 1) / b.ny;
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

// A point of the light seen from origin: the block by uv.u, the point in it by the rectangle map of (u', uv.v).
// pdf: P(block) times the block's solid-angle pdf at origin; 0 (invalid) where the block subtends nothing.
template <class T>
LightSample<T> SampleRectangleBlocks(const Vec3<T>& origin, const RectLightFrame<T>& f, const RectangleBlocks& b,
                                     Point2<T> uv) {
    float u = 0;
    const int k = ChooseRectangleBlock(b, float(uv.u), &u);
    const RectangleSetup<T> sr = MakeRectangleSetup(origin, RectangleBlockFrame(f, b, k));
    LightSample<T> s = SampleRectangle(sr, Point2<T>{T(u), uv.v});
    s.pdf *= T(b.pmf[k]);
    return s;
}

// Solid-angle pdf at origin of SampleRectangleBlocks producing point p of the light.
template <class T>
T RectangleBlocksPDF(const Vec3<T>& origin, const RectLightFrame<T>& f, const RectangleBlocks& b, const Vec3<T>& p) {
    const int k = RectangleBlockOf(f, b, p);
    if (!(b.pmf[k] > 0)) return 0;
    return T(b.pmf[k]) * RectanglePDF(MakeRectangleSetup(origin, RectangleBlockFrame(f, b, k)), p);
}

}  // namespace sphrect
