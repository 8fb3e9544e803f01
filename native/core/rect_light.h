// A rectangular emitter: corner s and two orthogonal edges ex, ey.
// The emitting side of a one-sided light is the one cross(ex, ey) points to.
#pragma once

#include <cmath>
#include <string>

#include "vec3.h"

namespace sphrect {

template <class T>
struct RectLight {
    Vec3<T> corner;
    Vec3<T> ex;
    Vec3<T> ey;
    bool two_sided = true;

    Vec3<T> Normal() const { return Normalize(Cross(ex, ey)); }
    T Area() const { return Length(Cross(ex, ey)); }
};

// Empty string when the rectangle is usable; otherwise what is wrong with it.
// Zero-length edges are *not* an error here: they are a degenerate light that
// every technique answers with pdf 0 (the renderer skips such lights).
template <class T>
std::string ValidateRectLight(const RectLight<T>& r) {
    if (!IsFinite(r.corner) || !IsFinite(r.ex) || !IsFinite(r.ey))
        return "rectangle corner and edges must be finite";
    const double lx = std::sqrt(double(Dot(r.ex, r.ex))), ly = std::sqrt(double(Dot(r.ey, r.ey)));
    if (lx > 0 && ly > 0 && std::abs(double(Dot(r.ex, r.ey))) > 1e-4 * lx * ly)
        return "rectangle edges edge_x and edge_y must be orthogonal (|cos angle| = " +
               std::to_string(std::abs(double(Dot(r.ex, r.ey))) / (lx * ly)) + ")";
    return {};
}

}  // namespace sphrect
