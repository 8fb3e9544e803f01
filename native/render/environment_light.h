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

// The weights of Distribution2D, one per pixel: the luminance (negative channels as 0) the pixel's cell sends
// (linear interpolation: the mean of the bilinear lookup over the cell, 1/8 3/4 1/8 of the texel and its
// neighbours per axis, so that every cell with any radiance can be sampled; closest: the texel) times the
// solid angle of its row, 2 pi (cos theta0 - cos theta1) / width, which stays positive at the poles.
inline std::vector<double> EnvironmentPixelWeights(const EnvironmentLight& e, const Image& im) {
    const int w = im.width, h = im.height;
    std::vector<double> lum(size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Spectrum c = DecodeTexel(im, im.Texel(x, y)).rgb() * e.strength;
            c = {std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f)};
            lum[size_t(y) * size_t(w) + size_t(x)] = Luminance(c);
        }
    std::vector<double> weights(lum.size());
    const bool linear = e.interpolation == TextureInterpolation::kLinear;
    auto at = [&](int x, int y) {
        return lum[size_t(texture_detail::WrapRepeat(y, h)) * size_t(w) + size_t(texture_detail::WrapRepeat(x, w))];
    };
    constexpr double kTap[3] = {0.125, 0.75, 0.125};
    for (int y = 0; y < h; ++y) {
        const double theta0 = kPi * (1 - double(y) / h), theta1 = kPi * (1 - double(y + 1) / h);
        const double row_solid_angle = 2 * double(kPi) * (std::cos(theta1) - std::cos(theta0)) / w;
        for (int x = 0; x < w; ++x) {
            double l = 0;
            if (linear) {
                for (int j = -1; j <= 1; ++j)
                    for (int i = -1; i <= 1; ++i) l += kTap[j + 1] * kTap[i + 1] * at(x + i, y + j);
            } else {
                l = at(x, y);
            }
            weights[size_t(y) * size_t(w) + size_t(x)] = l * row_solid_angle;
        }
    }
    return weights;
}

inline void BuildEnvironmentDistribution(EnvironmentLight& e, const Image& im) {
    e.distribution.Build(im.width, im.height, EnvironmentPixelWeights(e, im));
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
