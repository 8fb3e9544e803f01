// Bilinear warp of [0,1]^2 (Hart, Pharr, Mueller, Lopes, McGuire, Shirley,
// "Practical Product Sampling by Fitting and Composing Warps", EGSR 2020):
// density p(u, v) proportional to the bilinear interpolation of four corner
// weights w = {w00, w10, w01, w11} (w_ij at u = i, v = j), sampled as a linear
// marginal in u, then a linear conditional in v.
#pragma once

#include <array>
#include <cmath>

#include "vec3.h"

namespace sphrect {

using BilinearWeights = std::array<double, 4>;  // w00, w10, w01, w11

// x in [0,1] with density proportional to (1 - x) a + x b (a, b >= 0, not both 0):
// the root of the quadratic CDF, in the form without cancellation.
inline double SampleLinear(double xi, double a, double b) {
    if (a == b) return xi;
    const double x = xi * (a + b) / (a + std::sqrt((1 - xi) * a * a + xi * b * b));
    return ClampNaN(x, 0, 1);  // NaN (a = xi = 0) -> 0
}

// The CDF: xi such that SampleLinear(xi, a, b) = x.
inline double InvertLinearSample(double x, double a, double b) {
    if (a == b) return x;
    return x * (a * (2 - x) + b * x) / (a + b);
}

inline Point2<double> SampleBilinear(Point2<double> uv, const BilinearWeights& w) {
    const double u = SampleLinear(uv.u, w[0] + w[2], w[1] + w[3]);
    const double v = SampleLinear(uv.v, (1 - u) * w[0] + u * w[1], (1 - u) * w[2] + u * w[3]);
    return {u, v};
}

inline double BilinearPDF(Point2<double> uv, const BilinearWeights& w) {
    const double sum = w[0] + w[1] + w[2] + w[3];
    if (!(sum > 0)) return 0;
    const double u = uv.u, v = uv.v;
    return 4 * ((1 - u) * (1 - v) * w[0] + u * (1 - v) * w[1] + (1 - u) * v * w[2] + u * v * w[3]) / sum;
}

inline Point2<double> InvertBilinearSample(Point2<double> uv, const BilinearWeights& w) {
    const double u = uv.u;
    return {InvertLinearSample(u, w[0] + w[2], w[1] + w[3]),
            InvertLinearSample(uv.v, (1 - u) * w[0] + u * w[1], (1 - u) * w[2] + u * w[3])};
}

}  // namespace sphrect
