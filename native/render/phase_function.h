// The Henyey-Greenstein phase function of the medium (medium.h): its value and its sampling.
#pragma once

#include <algorithm>
#include <cmath>

#include "sampling_util.h"

namespace sphrect::render {

// p(cos theta) with cos theta = dot(wi, d), wi pointing to the light and d the camera ray's
// direction: light travelling along -wi is scattered into -d (towards the camera), so the
// scattering angle's cosine is dot(-wi, -d).  g > 0 favours wi ~ d (forward scattering).
inline float HenyeyGreenstein(float cos_theta, float g) {
    const float denom = 1 + g * g - 2 * g * cos_theta;
    return (1 - g * g) / (4 * kPi * denom * std::sqrt(denom));
}

// Direction wi with density HenyeyGreenstein(dot(wi, axis), g) (inverse of its cdf in cos theta).
inline Vec3f SampleHenyeyGreenstein(const Vec3f& axis, float g, Point2<float> u) {
    float cos_theta;
    if (std::abs(g) < 1e-3f) {
        cos_theta = 1 - 2 * u.u;
    } else {
        const float q = (1 - g * g) / (1 - g + 2 * g * u.u);
        cos_theta = (1 + g * g - q * q) / (2 * g);
    }
    cos_theta = std::clamp(cos_theta, -1.0f, 1.0f);
    const float sin_theta = SafeSqrt(1 - cos_theta * cos_theta), phi = 2 * kPi * u.v;
    return Frame::FromZ(axis).FromLocal({sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta});
}

}  // namespace sphrect::render
