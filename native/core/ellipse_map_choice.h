// The renderer's choice between the spherical ellipse map and area sampling for one (shading point,
// ellipse light), under ellipse_technique = spherical_ellipse (integrator/ellipse_sampling_at.h).
// The map is uniform in solid angle but costs ~10x area sampling per sample plus a setup
// (docs/ellipse_map.md, section 9); where area sampling's solid-angle density is already nearly
// uniform, the map cannot lower the error enough to pay for that, so such setups are sampled by area.
// (pbrt-v4 samples spherical triangles by area below a solid-angle threshold, kMinSphericalSampleArea,
// for the same reason; a solid angle alone does not say how uniform area sampling is -- a small light
// seen edge-on nearby is not -- so the choice here bounds the density's spread instead.)
//
// Derivation (docs/ellipse_map.md, section 10).  Area sampling's solid-angle density at a point of
// the light at distance d is p(w) = d^3 / (pi a b h) (h the height of o above the light's plane).  It
// integrates to 1 over the spherical ellipse, so its minimum and maximum bracket the uniform 1 / Omega,
// and p Omega lies in [1/s, s] with s = (d_max / d_min)^3.  The ellipse lies in the disk of radius
// r = max(a, b) about its centre, at in-plane distance rho from the foot of o, so
//   d_min^2 >= h^2 + max(rho - r, 0)^2,   d_max^2 <= h^2 + (rho + r)^2,
// and s <= S = (d_max^2 / d_min^2)^(3/2): a square root, a division and a few products, no elliptic
// integral.  The choice is a pure function of (point, light), so Sample and PDF (also the MIS pdf of a
// BSDF or phase ray that hits the light) always agree on it.
#pragma once

#include <cmath>

#include "ellipse_light.h"

namespace sphrect {

// Largest bound S on area sampling's density spread max p / min p over the ellipse for which the
// renderer samples by area instead of the map.  Chosen by measurement (docs/ellipse_map.md, section 10:
// MSE x CPU time of 16 spp against a 4096-spp reference on 08_disk_room, 11_paper_disk, 12_disk_ceiling
// and 12 in fog, swept over S).
constexpr double kEllipseAreaMaxSpread = 8.0;

// The bound S^(2/3) = d_max^2 / d_min^2 for the ellipse of largest semi-axis r whose centre is at
// in-plane offset (cx, cy) and height h from o (infinite when o is in the plane over the ellipse).
inline double EllipseAreaDistanceSpread2(double cx, double cy, double h, double r) {
    const double rho = std::sqrt(cx * cx + cy * cy), h2 = h * h;
    const double near = rho > r ? rho - r : 0.0, far = rho + r;
    return (h2 + far * far) / (h2 + near * near);
}

// True: area sampling of the ellipse `frame` seen from `origin` is within max_spread of uniform in
// solid angle, and the renderer samples it by area.  False for a degenerate light or a point in its
// plane (the map's setup then answers, with pdf 0).
template <class T>
bool EllipseAreaSamplingSuffices(const Vec3<T>& origin, const EllipseLightFrame<T>& frame,
                                 double max_spread = kEllipseAreaMaxSpread) {
    if (!frame.valid) return false;
    const Vec3d d = frame.center - Vec3d(origin);
    const double s2 = EllipseAreaDistanceSpread2(Dot(d, frame.uh), Dot(d, frame.vh), Dot(d, frame.n),
                                                 frame.a > frame.b ? frame.a : frame.b);
    return s2 * s2 * s2 <= max_spread * max_spread;  // S^2 = (d_max^2 / d_min^2)^3; false for NaN
}

}  // namespace sphrect
