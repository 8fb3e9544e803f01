// Pixel filters as Cycles 3.4 offers them (Film > Pixel Filter), by filter importance sampling: a camera
// sample's film offset from the pixel centre is drawn, in x and in y separately, from the filter's
// distribution, and every sample has weight 1 (the image is the radiance convolved with the separable
// filter f(x) f(y), normalised).  The filter functions are Cycles' (scene/film.cpp), of a width w in pixels:
//   box              f = 1 on |v| <= w / 2;
//   gaussian         f = exp(-2 (2 v / w)^2) = exp(-v^2 / (2 (w/4)^2)) on |v| <= 1.5 w (sigma = w / 4, 6 sigma);
//   blackman_harris  f = 0.35875 - 0.48829 cos x + 0.14128 cos 2x - 0.01168 cos 3x, x = 2 pi (v / (2 w) + 1/2),
//                    on |v| <= w (Blender's default: width 1.5).
// Sampling inverts the filter's CDF through a table of kPixelFilterTableSize offsets (as Cycles'
// FILTER_TABLE_SIZE), built once per camera and read with linear interpolation; a box needs none.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace sphrect::render {

enum class PixelFilterType { Box, Gaussian, BlackmanHarris };
constexpr const char* kPixelFilterNames[] = {"box", "gaussian", "blackman_harris"};  // PixelFilterType's order
// Blender's range of the Filter Width setting (Cycles' filter_width), pixels.
constexpr float kMinPixelFilterWidth = 0.01f, kMaxPixelFilterWidth = 10.0f;
constexpr int kPixelFilterTableSize = 1024;

// Half the filter's support, pixels.
inline double PixelFilterRadius(PixelFilterType type, double width) {
    switch (type) {
        case PixelFilterType::Box: return 0.5 * width;
        case PixelFilterType::Gaussian: return 1.5 * width;
        case PixelFilterType::BlackmanHarris: return width;
    }
    return 0.5 * width;
}

// The filter's (unnormalised) value at offset v from the pixel centre, |v| <= PixelFilterRadius.
inline double PixelFilterValue(PixelFilterType type, double width, double v) {
    switch (type) {
        case PixelFilterType::Box: return 1.0;
        case PixelFilterType::Gaussian: {
            const double s = 2.0 * v / width;  // Cycles: v * 6 / (3 w)
            return std::exp(-2.0 * s * s);
        }
        case PixelFilterType::BlackmanHarris: {
            const double x = 2.0 * M_PI * (v / (2.0 * width) + 0.5);
            return 0.35875 - 0.48829 * std::cos(x) + 0.14128 * std::cos(2 * x) - 0.01168 * std::cos(3 * x);
        }
    }
    return 1.0;
}

struct PixelFilter {
    PixelFilterType type = PixelFilterType::Box;
    float width = 1;
    // Offsets from the pixel centre at the CDF's values k / (size - 1), k = 0..size-1 (empty for a box).
    std::vector<float> inverse_cdf;

    // The 1-px box: a sample's film position is the pixel corner plus the pattern point, exactly as without filters.
    bool IsUnitBox() const { return type == PixelFilterType::Box && width == 1; }
};

// The filter with its table.  The CDF is integrated with the trapezoid rule on 64 steps per table interval (in
// double), then inverted by linear interpolation; the table is made antisymmetric, as the filters are even.
inline PixelFilter MakePixelFilter(PixelFilterType type, float width) {
    PixelFilter f;
    f.type = type;
    f.width = width;
    if (type == PixelFilterType::Box) return f;
    const int n = kPixelFilterTableSize, steps = 64 * (n - 1);
    const double radius = PixelFilterRadius(type, width), h = 2 * radius / steps;
    std::vector<double> cdf(size_t(steps) + 1, 0.0);
    double previous = PixelFilterValue(type, width, -radius);
    for (int i = 1; i <= steps; ++i) {
        const double value = PixelFilterValue(type, width, -radius + i * h);
        cdf[i] = cdf[i - 1] + 0.5 * (previous + value) * h;
        previous = value;
    }
    const double total = cdf[steps];
    f.inverse_cdf.assign(size_t(n), 0.0f);
    int i = 0;
    for (int k = 0; k < n / 2; ++k) {  // the lower half; the upper one mirrors it
        const double target = total * k / (n - 1);
        while (i < steps - 1 && cdf[i + 1] < target) ++i;
        const double span = cdf[i + 1] - cdf[i];
        const double t = span > 0 ? std::clamp((target - cdf[i]) / span, 0.0, 1.0) : 0.0;
        const float offset = float(-radius + (i + t) * h);
        f.inverse_cdf[size_t(k)] = offset;
        f.inverse_cdf[size_t(n - 1 - k)] = -offset;
    }
    return f;
}

// A film offset from the pixel centre, in pixels, drawn from the filter by the uniform u in [0, 1); monotone
// in u, so a stratified pattern stays stratified.  A box of width 1 gives u - 0.5 exactly.
inline float SamplePixelFilter(const PixelFilter& f, float u) {
    if (f.type == PixelFilterType::Box) return (u - 0.5f) * f.width;
    const int last = int(f.inverse_cdf.size()) - 1;
    const float x = std::clamp(u, 0.0f, 1.0f) * float(last);
    const int i = std::min(int(x), last - 1);
    const float t = x - float(i);
    return f.inverse_cdf[size_t(i)] + t * (f.inverse_cdf[size_t(i) + 1] - f.inverse_cdf[size_t(i)]);
}

// The film coordinate (pixels) of a sample of pixel `pixel` (its row or column) at pattern coordinate u.
inline float FilmCoordinate(const PixelFilter& f, int pixel, float u) {
    if (f.IsUnitBox()) return float(pixel) + u;  // bit-identical to the renderer before pixel filters
    return float(pixel) + 0.5f + SamplePixelFilter(f, u);
}

}  // namespace sphrect::render
