// Ellipse technique `spherical_ellipse`: an area-preserving map from [0,1]^2 onto the spherical
// ellipse an elliptical light (a disk is the special case) subtends, after Guillen, Urena, King,
// Fajardo, Georgiev, Lopez-Moreno & Jarabo, "Area-Preserving Parameterizations for Spherical
// Ellipses" (EGSR 2017).  du dv = dw / Omega: the pdf of every sample is 1 / Omega.
//
// Which of the paper's parameterizations: the parallel (cylindrical) one.  The spherical ellipse
// is cut by the planes through its major axis (Archimedes' equal-area cylinder about that axis):
// u picks the plane, at angle theta, by the solid angle on one side of it, and v moves linearly in
// the major-axis coordinate of the unit direction along the chord in that plane.  It is the
// rectangle map's construction (rectangle.h) on the ellipse: continuous over the whole square with
// no seam (the polar map has one at phi = 0 and squeezes its strata into wedges at the centre;
// the concentric one is continuous but inherits the square-to-disk kinks along the diagonals), and
// a grid of strata stays a grid of cells shaped like the ellipse.  Cost: the polar and concentric
// maps invert an incomplete elliptic integral (Booth's sector area) for their angle just as this
// one does, so none is cheaper; this one's second step is closed form.  Polar is out: its variance is
// lower only facing a disk and higher beside the light or for a tilted receiver; parallel and
// concentric are on par (the measured variances: docs/ellipse_map.md section 9).  Parallel is kept
// for the rectangle's structure (the same robust steps, fallback and inverse) rather than for a
// variance margin it does not have.
//
// The derivation, with the equation numbers the comments cite, is docs/ellipse_map.md.  In short:
// setup and map in double from the (float) inputs, rounded to T once.  The cone over the ellipse
// is reduced to its principal frame through the secular equation of its dual quadric (3)-(6), all
// in sums of positive terms; the solid angle and the cumulative solid angle of the map's first
// step are one Carlson integral R_J each (10) (ellipse_carlson.h; no cancellation anywhere in [0, 1]);
// the first step is solved by safeguarded Halley steps on Omega_left (on Omega_left^(2/3) near the
// ends) (11), the second is closed form (12).  The few setups whose spherical ellipse is too thin for double directions
// to resolve (u, v) (15) switch to area sampling (16), which Sample, PDF and Invert all follow, so the pdf returned is
// always the pdf of the point returned.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "ellipse_area.h"
#include "ellipse_carlson.h"
#include "ellipse_light.h"

namespace sphrect {

// Largest accepted estimate of the map's rounding error in (u, v) space, (15) -> (16).
constexpr double kEllipseMaxError = 1e-7;

// The u-step's Halley iteration stops when the error it predicts for t (which moves u by at most
// about as much) is below this, (11).
constexpr double kEllipseLastError = 1e-13;
// Below this share of Omega from the end, the u-step iterates on Omega_left^(2/3), (11).
constexpr double kEllipseTipShare = 0.05;

// The per-(shading point, light) constants of the map (docs/ellipse_map.md, table of section 8).
template <class T>
struct SphericalEllipseSetup {
    LocalEllipse<T> plane;       // the light's frame around o; also the area map of the fallback
    bool valid = false;          // false: every sample has pdf 0
    bool area_fallback = false;  // (16)
    double omega = 0;            // solid angle (double)
    T solid_angle = 0;           // Omega
    T pdf = 0;                   // 1 / Omega
    // The spherical ellipse's principal frame in local coordinates (x along uh, y along vh, z along
    // az): axis w (the cone's axis), ea (major), eb (minor), (4), (6).
    Vec3d w = Vec3d(), ea = Vec3d(), eb = Vec3d();
    double A = 0, B = 0;  // tangents of the semi-arcs [tan alpha >= tan beta], (6)
    double beta = 0;      // the minor semi-arc, atan B
    double gamma = 0;     // pi/2 - beta = atan(1 / B), (8b)
    double sin_beta = 0, cos_beta = 0;
    double K = 0, Q = 0, R = 0;  // Omega_left's constants, (10)
    double error_estimate = 0;   // first-order rounding error of the map in (u, v) space, (15)
};

// The cone's axis parameter m = -mu3 > 0, the root of (3)
//   G(m) = m - cx^2 m / (a^2 + m) - cy^2 m / (b^2 + m) - h^2,
// convex and increasing past its root: Newton from a point where G >= 0 decreases monotonically.
inline double SphericalEllipseAxisRoot(double cx, double cy, double h, double a2, double b2) {
    const double cx2 = cx * cx, cy2 = cy * cy, h2 = h * h, c2 = cx2 + cy2 + h2;
    auto G = [&](double m) { return m - cx2 * m / (a2 + m) - cy2 * m / (b2 + m) - h2; };
    double m = c2;                         // G(|C|^2) >= 0
    const double mid = h * std::sqrt(c2);  // nearer the root when o is close to the plane
    if (G(mid) >= 0) m = mid;
    for (int it = 0; it < 200; ++it) {
        const double g = G(m);
        if (!(g > 0)) break;
        const double ta = a2 + m, tb = b2 + m;
        const double dg = 1 - cx2 * a2 / (ta * ta) - cy2 * b2 / (tb * tb);
        const double mn = m - g / dg;
        if (!(mn < m) || !(mn > 0)) break;
        m = mn;
    }
    return m;
}

template <class T>
SphericalEllipseSetup<T> MakeSphericalEllipseSetup(const Vec3<T>& origin, const EllipseLightFrame<T>& frame) {
    SphericalEllipseSetup<T> se{MakeLocalEllipse(origin, frame)};
    const LocalEllipse<T>& p = se.plane;
    if (!p.valid) return se;
    const double cx = p.cx, cy = p.cy, h = p.h, a = p.a, b = p.b, a2 = a * a, b2 = b * b;

    // (3)-(4): the cone's axis.
    const double m = SphericalEllipseAxisRoot(cx, cy, h, a2, b2);
    const double pw = cx * cx / (a2 + m), qw = cy * cy / (b2 + m), rw = h * h / m;  // p + q + r = 1
    se.w = Normalize(Vec3d(cx / (a2 + m), cy / (b2 + m), h / m));
    // (5): the other two eigenvalues of the dual quadric, sum and discriminant as sums of squares.
    const double S = a2 * (qw + rw) + b2 * (pw + rw);
    const double dd = (a - b) * (a + b) * rw + a2 * qw - b2 * pw;
    const double mu1 = 0.5 * (S + std::sqrt(dd * dd + 4 * a2 * b2 * pw * qw));
    const double mu2 = a2 * b2 * rw / mu1;
    se.A = std::sqrt(mu1 / m);
    se.B = std::sqrt(mu2 / m);
    // (6): the principal directions, from the dual quadric restricted to the plane orthogonal to w
    // (a 2x2 symmetric matrix, diagonalised by one rotation).
    const Vec3d& w = se.w;
    const Vec3d ax = std::abs(w.x) <= std::abs(w.y) && std::abs(w.x) <= std::abs(w.z) ? Vec3d(1, 0, 0)
                     : std::abs(w.y) <= std::abs(w.z)                                 ? Vec3d(0, 1, 0)
                                                                                      : Vec3d(0, 0, 1);
    const Vec3d e1 = Normalize(ax - w * Dot(ax, w)), e2 = Cross(w, e1);
    const Vec3d C(cx, cy, h);
    const double c1 = Dot(e1, C), c2 = Dot(e2, C);
    const double m11 = a2 * e1.x * e1.x + b2 * e1.y * e1.y - c1 * c1;
    const double m22 = a2 * e2.x * e2.x + b2 * e2.y * e2.y - c2 * c2;
    const double m12 = a2 * e1.x * e2.x + b2 * e1.y * e2.y - c1 * c2;
    const double phi = 0.5 * std::atan2(2 * m12, m11 - m22);
    se.ea = e1 * std::cos(phi) + e2 * std::sin(phi);
    se.eb = Cross(w, se.ea);

    // (10): Omega = 2 Omega_left(0).
    const double A = se.A, B = se.B, pB = 1 + B * B;
    se.beta = std::atan(B);
    se.gamma = std::atan(1 / B);
    se.sin_beta = B / std::sqrt(pB);
    se.cos_beta = 1 / std::sqrt(pB);
    se.Q = (1 + A * A) / pB;
    se.R = 1 / pB;
    se.K = 2 * A * B / (3 * pB * std::sqrt(pB));
    se.omega = 2 * se.K * CarlsonRJ(0, 1, se.Q, se.R);
    if (!(se.omega > 0) || !std::isfinite(se.omega)) return se;
    se.solid_angle = T(se.omega);
    se.pdf = T(1 / se.omega);
    if (!(se.solid_angle > 0) || !std::isfinite(se.pdf)) return se;
    se.valid = true;

    // (15): a direction is resolved to a few eps; the frame's rotation by eps moves the major
    // semi-arc's end by eps A; both relative to the minor semi-arc.
    constexpr double eps = std::numeric_limits<double>::epsilon();
    se.error_estimate = 8 * eps * (1 + A) / B;
    se.area_fallback = !(se.error_estimate <= kEllipseMaxError) || !std::isfinite(se.K) || !(se.beta > 0);
    return se;
}

template <class T>
SphericalEllipseSetup<T> MakeSphericalEllipseSetup(const Vec3<T>& origin, const EllipseLight<T>& light) {
    return MakeSphericalEllipseSetup(origin, MakeEllipseLightFrame(light));
}

// The plane through the major axis at theta = -beta t, t in [0, 1] (the side u < 1/2): the
// quantities (8b) in angles whose complements are sums of positive terms, so that they keep their
// relative precision at both ends of t and for spherical ellipses near a hemisphere (beta ~ pi/2,
// where tan(theta) / B would lose eps B^2).
struct EllipseSlice {
    double sin_t, cos_t;  // sin|theta|, cos theta
    double s2, w;         // sigma^2 = (tan theta / B)^2 and 1 - sigma^2
    double one_plus;      // 1 + B^2 sigma^2 = 1 / cos^2 theta
};

template <class T>
EllipseSlice SphericalEllipseSliceAt(const SphericalEllipseSetup<T>& se, double t) {
    t = ClampNaN(t, 0, 1);
    const double rest = se.beta * (1 - t);  // beta - |theta|
    double st, ct, w;
    if (se.beta <= 1) {
        // |theta| <= 1: cos|theta| >= 0.54 keeps its precision, and 1 - sigma^2 = (1 - sigma)(1 + sigma)
        // loses only relative digits near the ends, where Omega_left ~ w^(3/2) is negligible.
        st = std::sin(se.beta * t);
        ct = std::cos(se.beta * t);
        const double sig = std::min(st * se.cos_beta / (ct * se.sin_beta), 1.0);  // (rounding at t = 1)
        return {st, ct, sig * sig, (1 - sig) * (1 + sig), 1 / (ct * ct)};
    }
    st = std::sin(se.beta * t);
    ct = std::sin(se.gamma + rest);  // cos|theta| = sin(pi/2 - |theta|)
    // sin(beta + |theta|) from the smaller of the supplementary angles: pi - beta - |theta| = 2 gamma + rest.
    const double plus = se.beta * (1 + t), sup = 2 * se.gamma + rest;
    const double d = ct * se.sin_beta;
    const double sig = st * se.cos_beta / d;
    w = std::max(std::sin(rest) * std::sin(std::min(plus, sup)) / (d * d), 0.0);  // sin(beta -+ |theta|)
    return {st, ct, sig * sig, w, 1 / (ct * ct)};
}

// The solid angle of the part of the spherical ellipse on the far side of the slice, (10).
template <class T>
double SphericalEllipseLeft(const SphericalEllipseSetup<T>& se, const EllipseSlice& sl) {
    const double w = sl.w;
    return se.K * w * std::sqrt(w) * CarlsonRJ(sl.s2, 1, sl.s2 + w * se.Q, sl.s2 + w * se.R);
}

// The chord's half-length x1 in the slice and the denominator of (8).
template <class T>
double SphericalEllipseChord(const SphericalEllipseSetup<T>& se, const EllipseSlice& sl, double* den) {
    *den = (1 + se.A * se.A) * sl.w + (1 + se.B * se.B) * sl.s2;
    return std::min(se.A * std::sqrt(sl.w / *den), 1.0);
}

// The u-step (11): t = |theta| / beta in [0, 1] with Omega_left = ut Omega, ut in [0, 1/2].
// Safeguarded Halley iteration with Omega_left' and Omega_left'' from (9) and (8); near the end
// (ut < kEllipseTipShare), where Omega_left ~ (1 - t)^(3/2), on G = Omega_left^(2/3) instead, which
// is nearly linear there.
template <class T>
double SphericalEllipseSolveT(const SphericalEllipseSetup<T>& se, double ut) {
    if (!(ut > 0)) return 1;
    if (ut >= 0.5) return 0;
    const bool tip = ut < kEllipseTipShare;
    const double target = ut * se.omega, target_cbrt = tip ? std::cbrt(target) : 0;
    const double A2 = se.A * se.A, B2 = se.B * se.B;
    double lo = 0, hi = 1;  // Omega_left(lo) >= target >= Omega_left(hi)
    double prev = 0;        // the last Halley step's size (0: none, or a bisection)
    double t = std::cbrt(2 * ut);
    t = 1 - t * t;
    for (int it = 0; it < 60; ++it) {
        const EllipseSlice sl = SphericalEllipseSliceAt(se, t);
        const double left = SphericalEllipseLeft(se, sl);
        const double cl = tip ? std::cbrt(left) : 0;
        const double g = tip ? cl * cl - target_cbrt * target_cbrt : left - target;
        if (g == 0) break;
        (g > 0 ? lo : hi) = t;
        double den;
        const double x1 = SphericalEllipseChord(se, sl, &den);
        const double d1 = -2 * se.beta * x1;  // d Omega_left / dt, (9)
        double d2 = 0;                        // d^2 Omega_left / dt^2, from d x1 / d sigma (8)
        if (x1 > 0) {
            const double sigma = std::sqrt(sl.s2);  // (|sigma|: d x1 / d|sigma| < 0, d|sigma| / dt > 0)
            const double dsigma = se.beta * sl.one_plus / se.B;
            d2 = -2 * se.beta * (-sigma * A2 * (1 + B2) / (x1 * den * den)) * dsigma;
        }
        const double dg = tip ? (2.0 / 3.0) / cl * d1 : d1;
        const double d2g = tip ? (2.0 / 3.0) / cl * (d2 - d1 * d1 / (3 * left)) : d2;
        double step = g / dg;  // Newton, or Halley where its denominator allows
        const double q = 2 * dg * dg - g * d2g;
        if (x1 > 0 && q > 0) step = 2 * g * dg / q;
        double tn = t - step;
        const bool inside = tn > lo && tn < hi;
        if (!inside) tn = 0.5 * (lo + hi);
        // Converging cubically, e_next ~ K step^3 with K estimated from the last two Halley steps:
        // when that is below kEllipseLastError the step is taken without evaluating again.
        const double size = std::abs(tn - t);
        const double predicted = prev > 0 ? size / (prev * prev * prev) * size * size * size : size;
        const bool done = inside && (predicted <= kEllipseLastError || size <= 1e-15);
        prev = inside ? size : 0;
        t = tn;
        if (done || hi - lo <= 1e-15) break;
    }
    return t;
}

// The map M(u, v) as a unit direction in local coordinates (valid, non-fallback setups).
template <class T>
Vec3d SphericalEllipseDirection(const SphericalEllipseSetup<T>& se, double u, double v) {
    u = ClampNaN(u, 0, 1);
    v = ClampNaN(v, 0, 1);
    // (11), mirrored about the major axis for u > 1/2 (theta = +beta t).
    const bool upper = u > 0.5;
    const EllipseSlice sl = SphericalEllipseSliceAt(se, SphericalEllipseSolveT(se, upper ? 1 - u : u));
    double den;
    const double x1 = SphericalEllipseChord(se, sl, &den);
    const double omx1 = sl.one_plus / den;  // 1 - x1^2, (8)
    // (12): linear in the major-axis coordinate, 1 - x^2 as a sum of non-negative terms.
    const double x = x1 * (2 * v - 1);
    const double r = std::sqrt(omx1 + x1 * x1 * 4 * v * (1 - v));
    return se.ea * x + se.eb * (r * (upper ? sl.sin_t : -sl.sin_t)) + se.w * (r * sl.cos_t);
}

// (13b): a point (p, q) just outside the unit disk (rounding: at grazing incidence the ray meets
// the plane eps d^2 / h away from the exact point) brought back onto the rim along the line from
// the foot of o, (fx, fy), rather than towards the centre: along that line the move changes the
// direction from o by about (h / d) of its length only, so that (u, v) is kept.
inline void ClampAlongRay(double fx, double fy, double& p, double& q) {
    const double dx = p - fx, dy = q - fy;
    const double d2 = dx * dx + dy * dy, fd = fx * dx + fy * dy, c = fx * fx + fy * fy - 1;
    const double disc = fd * fd - d2 * c;
    if (d2 > 0 && disc >= 0) {
        const double root = std::sqrt(disc);
        // The crossing nearer (p, q): the larger root of |f + s d|^2 = 1, cancellation-free form.
        const double s = fd <= 0 ? (root - fd) / d2 : -c / (fd + root);
        if (s >= 0 && s <= 1) {
            p = fx + s * dx;
            q = fy + s * dy;
        }
    }
    // (what is left outside, by rounding or a missed rim, EllipseSampleAt scales onto the disk)
}

template <class T>
LightSample<T> SampleSphericalEllipseAt(const SphericalEllipseSetup<T>& se, double u, double v) {
    if (!se.valid) return {};
    const LocalEllipse<T>& pl = se.plane;
    if (se.area_fallback) return SampleEllipseAreaAt(pl, u, v);
    const Vec3d d = SphericalEllipseDirection(se, u, v);
    // (13): where the ray meets the light's plane, as offsets from the centre in semi-axes.
    double p, q;
    if (d.z > 0) {
        const double t = pl.h / d.z;
        p = (d.x * t - pl.cx) / pl.a;
        q = (d.y * t - pl.cy) / pl.b;
    } else {  // (rounding at the horizon: the rim point in the direction's in-plane heading)
        p = d.x / pl.a;
        q = d.y / pl.b;
        const double n = std::hypot(p, q);
        p /= n;
        q /= n;
    }
    if (p * p + q * q > 1) {
        ClampAlongRay(-pl.cx / pl.a, -pl.cy / pl.b, p, q);
        return EllipseSampleAt(pl, p, q, se.pdf);
    }
    return EllipseSampleAt(pl, p, q, se.pdf, &d);  // the map's direction itself
}

template <class T>
LightSample<T> SampleSphericalEllipse(const SphericalEllipseSetup<T>& se, Point2<T> uv) {
    return SampleSphericalEllipseAt(se, double(uv.u), double(uv.v));
}

// Solid-angle pdf of choosing p (a point on the light): 1 / Omega, or the fallback's (16).
template <class T>
T SphericalEllipsePDF(const SphericalEllipseSetup<T>& se, const Vec3<T>& p) {
    if (!se.valid) return 0;
    if (se.area_fallback) return EllipseAreaPDF(se.plane, p);
    return se.pdf;
}

// The inverse map in double, (14): point on the light -> (u, v) in [0,1]^2.
template <class T>
Point2<double> InvertSphericalEllipse(const SphericalEllipseSetup<T>& se, const Vec3<T>& point) {
    if (!se.valid) return {};
    const LocalEllipse<T>& pl = se.plane;
    if (se.area_fallback) return InvertEllipseArea(pl, point);
    const Point2<double> e = EllipseOffsets(pl, point);
    double p = e.u / pl.a, q = e.v / pl.b;
    ClampToUnitDisk(p, q);
    const Vec3d d = Normalize(Vec3d(pl.cx + p * pl.a, pl.cy + q * pl.b, pl.h));
    const double X = Dot(d, se.ea), Y = Dot(d, se.eb), Z = Dot(d, se.w);
    const double theta = std::atan2(Y, Z);
    const EllipseSlice sl = SphericalEllipseSliceAt(se, std::abs(theta) / se.beta);
    const double left = SphericalEllipseLeft(se, sl);
    const double u = theta <= 0 ? left / se.omega : 1 - left / se.omega;
    double den;
    const double x1 = SphericalEllipseChord(se, sl, &den);
    const double v = x1 > 0 ? 0.5 * (X / x1 + 1) : 0.5;
    return {ClampNaN(u, 0, 1), ClampNaN(v, 0, 1)};
}

// Solid angle of the ellipse seen from `origin` (0 where the setup is invalid), in double, (10).
template <class T>
double EllipseSolidAngle(const Vec3<T>& origin, const EllipseLight<T>& light) {
    const SphericalEllipseSetup<T> se = MakeSphericalEllipseSetup(origin, light);
    return se.valid ? se.omega : 0.0;
}

}  // namespace sphrect
