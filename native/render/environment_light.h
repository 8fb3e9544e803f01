// The environment light: an equirectangular image of the radiance arriving from infinitely far away, as Cycles
// 3.4's Environment Texture maps it (direction_to_equirectangular) behind a Background, importance-sampled by
// a 2-D piecewise-constant distribution over its pixels (Distribution2D) proportional to the radiance each
// pixel's cell sends, i.e. its luminance times the solid angle of its row (Cycles' background map, pbrt-v4's
// ImageInfiniteLight).
//
// Mapping, in the image's own frame (d = to_world^T w for a world direction w): phi = atan2(d.y, d.x),
// theta = acos(d.z); u = (pi - phi) / (2 pi), v = 1 - theta / pi.  So +X is the middle column, +Z the top row
// (v = 1; rows run bottom to top, texture.h), and u grows clockwise seen from +Z.  The Jacobian of (u, v) ->
// direction is 2 pi^2 sin(theta): a density p(u, v) is p / (2 pi^2 sin theta) per steradian.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "distribution_2d.h"
#include "sampling_util.h"
#include "texture.h"

namespace sphrect::render {

struct EnvironmentLight {
    int image = -1;  // into RenderScene::images
    Spectrum strength{1, 1, 1};
    float to_world[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // a rotation, row-major
    TextureInterpolation interpolation = TextureInterpolation::kLinear;
    Distribution2D distribution;  // over the image's pixels (BuildEnvironmentDistribution)
};

// ------------------------------------------------------------------ mapping

inline Vec3f EnvironmentToLocal(const EnvironmentLight& e, const Vec3f& w) {
    const float(&m)[3][3] = e.to_world;
    return {m[0][0] * w.x + m[1][0] * w.y + m[2][0] * w.z, m[0][1] * w.x + m[1][1] * w.y + m[2][1] * w.z,
            m[0][2] * w.x + m[1][2] * w.y + m[2][2] * w.z};
}

inline Vec3f EnvironmentToWorld(const EnvironmentLight& e, const Vec3f& d) {
    const float(&m)[3][3] = e.to_world;
    return {m[0][0] * d.x + m[0][1] * d.y + m[0][2] * d.z, m[1][0] * d.x + m[1][1] * d.y + m[1][2] * d.z,
            m[2][0] * d.x + m[2][1] * d.y + m[2][2] * d.z};
}

// Cycles' direction_to_equirectangular for a direction d of the image's frame (any length).
inline Point2<float> EquirectangularFromDirection(const Vec3f& d) {
    const float theta = std::atan2(std::sqrt(d.x * d.x + d.y * d.y), d.z);  // acos(d.z / |d|), exact at the poles
    return {(kPi - std::atan2(d.y, d.x)) * (0.5f * kInvPi), 1 - theta * kInvPi};
}

// Its inverse, with sin(theta) (the Jacobian's factor).
inline Vec3f DirectionFromEquirectangular(Point2<float> uv, float* sin_theta) {
    const float theta = kPi * (1 - uv.v), phi = kPi * (1 - 2 * uv.u);
    const float s = std::sin(theta);
    *sin_theta = s;
    return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

// ------------------------------------------------------------------ radiance

// The radiance arriving from world direction w (unit): the image's colour there times the strength.  The
// lookup repeats across the edges, as Cycles' environment image does (its default extension).
inline Spectrum EnvironmentRadiance(const EnvironmentLight& e, const Image& im, const Vec3f& w) {
    const Point2<float> uv = EquirectangularFromDirection(EnvironmentToLocal(e, w));
    return LookupImage(im, uv.u, uv.v, e.interpolation, TextureExtension::kRepeat).rgb() * e.strength;
}

// The sampling grid is the image's pixels, each split into k x l cells so that it has at least this many rows and
// columns: a tiny image (1 x 1, a two-tone 2 x 1) is still sampled by the solid angle of its rows, not densest at
// the poles.
constexpr int kMinEnvironmentRows = 32, kMinEnvironmentColumns = 64;

// The pixels of an image w x h are split kx x ky ways (the grid's columns w kx, rows h ky).
inline void EnvironmentGridSplit(int w, int h, int* kx, int* ky) {
    *kx = (kMinEnvironmentColumns + w - 1) / w;
    *ky = (kMinEnvironmentRows + h - 1) / h;
}

// What the sampling distribution of an image w x h takes (LightSelector: a cdf and a pmf float per cell and row).
inline uint64_t EnvironmentDistributionBytes(int w, int h) {
    int kx, ky;
    EnvironmentGridSplit(w, h, &kx, &ky);
    const uint64_t rows = uint64_t(h) * uint64_t(ky), cells = rows * uint64_t(w) * uint64_t(kx);
    return (cells + rows) * 2 * sizeof(float);
}

// The weights of Distribution2D over that grid: the luminance (negative channels as 0) its pixel sends (linear
// interpolation: the mean of the bilinear lookup over the pixel, 1/8 3/4 1/8 of the texel and its neighbours per
// axis, so that every cell with any radiance can be sampled; closest: the texel) times the solid angle of the cell's
// row, 2 pi (cos theta0 - cos theta1) / columns, which stays positive at the poles.  Sets *columns and *rows.
inline std::vector<double> EnvironmentCellWeights(const EnvironmentLight& e, const Image& im, int* columns, int* rows) {
    const int w = im.width, h = im.height;
    int kx, ky;
    EnvironmentGridSplit(w, h, &kx, &ky);
    *columns = w * kx;
    *rows = h * ky;
    std::vector<float> lum(size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Spectrum c = DecodeTexel(im, im.Texel(x, y)).rgb() * e.strength;
            c = {std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f)};
            lum[size_t(y) * size_t(w) + size_t(x)] = Luminance(c);
        }
    auto at = [&](int x, int y) {
        return double(
            lum[size_t(texture_detail::WrapRepeat(y, h)) * size_t(w) + size_t(texture_detail::WrapRepeat(x, w))]);
    };
    auto pixel = [&](int x, int y) {
        if (e.interpolation != TextureInterpolation::kLinear) return at(x, y);
        constexpr double kTap[3] = {0.125, 0.75, 0.125};
        double l = 0;
        for (int j = -1; j <= 1; ++j)
            for (int i = -1; i <= 1; ++i) l += kTap[j + 1] * kTap[i + 1] * at(x + i, y + j);
        return l;
    };
    std::vector<double> weights(size_t(*columns) * size_t(*rows));
    for (int r = 0; r < *rows; ++r) {
        const double theta0 = kPi * (1 - double(r) / *rows), theta1 = kPi * (1 - double(r + 1) / *rows);
        const double row_solid_angle = 2 * double(kPi) * (std::cos(theta1) - std::cos(theta0)) / *columns;
        for (int c = 0; c < *columns; ++c)
            weights[size_t(r) * size_t(*columns) + size_t(c)] = pixel(c / kx, r / ky) * row_solid_angle;
    }
    return weights;
}

inline void BuildEnvironmentDistribution(EnvironmentLight& e, const Image& im) {
    int columns, rows;
    const std::vector<double> weights = EnvironmentCellWeights(e, im, &columns, &rows);
    e.distribution.Build(columns, rows, weights);
}

// ------------------------------------------------------------------ sampling

struct EnvironmentSample {
    Vec3f wi;       // unit, world
    float pdf = 0;  // per steradian; 0: none (an all-black image, or a pole)
};

inline EnvironmentSample SampleEnvironment(const EnvironmentLight& e, Point2<float> u) {
    const Distribution2DSample s = SampleDistribution2D(e.distribution, u);
    if (!(s.pdf > 0)) return {};
    float sin_theta;
    const Vec3f d = DirectionFromEquirectangular(s.uv, &sin_theta);
    if (!(sin_theta > 0)) return {};
    return {EnvironmentToWorld(e, d), s.pdf / (2 * kPi * kPi * sin_theta)};
}

inline float EnvironmentPDF(const EnvironmentLight& e, const Vec3f& w) {
    const Vec3f d = EnvironmentToLocal(e, w);
    const float sin_theta = std::sqrt(std::max(0.0f, d.x * d.x + d.y * d.y));
    if (!(sin_theta > 0)) return 0;
    return Distribution2DPDF(e.distribution, EquirectangularFromDirection(d)) / (2 * kPi * kPi * sin_theta);
}

// The u that SampleEnvironment maps to world direction w.
inline Point2<float> InvertEnvironmentSample(const EnvironmentLight& e, const Vec3f& w) {
    return InvertDistribution2DSample(e.distribution, EquirectangularFromDirection(EnvironmentToLocal(e, w)));
}

}  // namespace sphrect::render
