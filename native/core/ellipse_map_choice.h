// The renderer's choice between the spherical ellipse map and area sampling for one (shading point,
// ellipse light), under ellipse_technique = spherical_ellipse (integrator/ellipse_sampling_at.h).
// The map is uniform in solid angle but costs many times area sampling per sample plus a setup
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
// and s <= S = (d_max^2 / d_min^2)^(3/2): two dot products and a dozen products, no square root,
// division or elliptic integral (below).  The choice is a pure function of (point, light), so Sample
// and PDF (also the MIS pdf of a BSDF or phase ray that hits the light) always agree on it.
#pragma once

#include "ellipse_light.h"

namespace sphrect {

// Largest bound S on area sampling's density spread max p / min p over the ellipse for which the
// renderer samples by area instead of the map.  Chosen by measurement (docs/ellipse_map.md, section 10:
// MSE x CPU time of 16 spp against a 4096-spp reference on 08_disk_room, 11_paper_disk, 12_disk_ceiling
// and 12 in fog, swept over S).
constexpr double kEllipseAreaMaxSpread = 8.0;

// The threshold on the squared distances, d_max^2 / d_min^2 <= S^(2/3) (4 for S = 8).
constexpr double EllipseAreaMaxDistanceRatio2(double spread) {
    const double a = spread * spread;
    double x = a > 1 ? a : 1;  // Newton on x^3 = a from above: decreases monotonically to the root
    for (int i = 0; i < 100; ++i) x -= (x * x * x - a) / (3 * x * x);
    return x;
}

// True: area sampling of the ellipse `frame` seen from `origin` is within kEllipseAreaMaxSpread of
// uniform in solid angle, and the renderer samples it by area.  False for a degenerate light or a
// point in its plane over the ellipse (the map's setup then answers, with pdf 0), and for NaN.
// With D^2 = |C - o|^2 = h^2 + rho^2 and q = D^2 + r^2, d_max^2 = q + 2 r rho and d_min^2 = q - 2 r rho
// (rho >= r) or h^2 (rho < r), so d_max^2 <= k d_min^2 is, squared, free of square roots and divisions:
//   rho >= r:  (2 r rho)^2 <= (q (k - 1) / (k + 1))^2,    rho < r:  0 <= k h^2 - q,  (2 r rho)^2 <= (k h^2 - q)^2.
// (rho^2 = D^2 - h^2 loses eps D^2 absolutely where rho << h, where the bound hardly depends on rho.)
template <class T>
bool EllipseAreaSamplingSuffices(const Vec3<T>& origin, const EllipseLightFrame<T>& frame) {
    constexpr double k = EllipseAreaMaxDistanceRatio2(kEllipseAreaMaxSpread);
    if (!frame.valid) return false;
    const Vec3d d = frame.center - Vec3d(origin);
    const double r = frame.a > frame.b ? frame.a : frame.b, r2 = r * r;
    const double d2 = Dot(d, d), h = Dot(d, frame.n), h2 = h * h;
    const double rho2 = d2 > h2 ? d2 - h2 : 0.0;
    const double q = d2 + r2, two_r_rho2 = 4 * r2 * rho2;
    if (rho2 >= r2) {
        const double m = q * ((k - 1) / (k + 1));
        return two_r_rho2 <= m * m;
    }
    const double m = k * h2 - q;
    return m >= 0 && two_r_rho2 <= m * m;  // (false for NaN)
}

}  // namespace sphrect
