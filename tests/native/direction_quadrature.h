// Directions by (cos theta, phi) about +z and midpoint quadrature over them, shared by the BSDF tests.
#pragma once

#include <algorithm>
#include <cmath>

#include "render/sampling_util.h"

namespace sphrect::render {

inline Vec3f SphericalDirection(float cos_theta, float phi) {
    const float s = std::sqrt(std::max(0.0f, 1 - cos_theta * cos_theta));
    return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

// Midpoint quadrature of g(w) over the directions with cos theta in [cos_lo, 1] (uniform in cos theta and phi).
template <class F>
double IntegrateDirections(F g, float cos_lo, int n_theta, int n_phi) {
    double sum = 0;
    for (int i = 0; i < n_theta; ++i)
        for (int j = 0; j < n_phi; ++j) {
            const float c = cos_lo + (1 - cos_lo) * (i + 0.5f) / n_theta, phi = 2 * kPi * (j + 0.5f) / n_phi;
            sum += g(SphericalDirection(c, phi));
        }
    return sum * (2 * (1 - double(cos_lo))) * M_PI / (double(n_theta) * n_phi);
}

template <class F>
double IntegrateSphere(F g, int n_theta = 400, int n_phi = 400) {
    return IntegrateDirections(g, -1, n_theta, n_phi);
}

template <class F>
double IntegrateHemisphere(F g, int n_theta = 600, int n_phi = 600) {
    return IntegrateDirections(g, 0, n_theta, n_phi);
}

}  // namespace sphrect::render
