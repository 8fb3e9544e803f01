// Technique `rectangle`: the area-preserving map of Urena, Fajardo & King,
// "An Area Preserving Parametrization for Spherical Rectangles" (EGSR 2013),
// M(u, v): x from u alone through the sub-rectangle of solid angle u * Omega,
// then y linearly in the y-coordinate on the unit sphere.  du dv = dw / Omega.
//
// A numerically robust formulation of the paper's map (whose float code is kept in
// textbook_rectangle.h as a baseline).  The derivation, with the equation numbers the
// comments below cite and a table from every variable here to the paper's, is
// docs/rectangle_map.md.  In short: setup and map in double from the (float) inputs,
// rounded to T once; solid angles by solid_angle.h; the x-step solves (8) for the sine of
// the angle, (10), in a frame chosen per setup (13) so that u Omega is not lost; the y-step
// interpolates 1 - hy beside the light (16); nearly edge-on setups refine x by Newton steps
// (20) and the few setups where even that cannot resolve (u, v) switch to area sampling
// (21), which Sample, PDF and Invert all follow, so the pdf returned is always the pdf of
// the point returned.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "area.h"
#include "local_rect.h"
#include "solid_angle.h"

namespace sphrect {

// Largest accepted estimate of the map's rounding error in (u, v) space, (19) -> (21).
constexpr double kRectangleMaxError = 1e-7;
// The x-step's closed form is refined by (safeguarded) Newton steps on the stable
// sub-rectangle solid angle when its error estimate exceeds this, (20).
constexpr double kRectanglePolishAbove = 1e-10;
// What is left of the x-step's error after the Newton refinement.
constexpr double kRectanglePolishedError = 1e-12;

// b(yb) - b(ya) with b(y) = y / sqrt(y^2 + d^2), eq. (15) when ya, yb have the same sign;
// dy = yb - ya (passed, exact), ra = sqrt(ya^2 + d^2), rb = sqrt(yb^2 + d^2) and d2 = d^2.
inline double DiffB(double ya, double yb, double ra, double rb, double d2, double dy) {
    if (ya * yb > 0) return d2 * dy * (yb + ya) / (ra * rb * (yb * ra + ya * rb));
    return yb / rb - ya / ra;
}

// The same from d alone.
inline double DiffB(double ya, double yb, double d, double dy) {
    const double d2 = d * d;
    return DiffB(ya, yb, std::sqrt(ya * ya + d2), std::sqrt(yb * yb + d2), d2, dy);
}

// 1 - b(y) for y >= 0, with r = sqrt(y^2 + d^2) and d2 = d^2, eq. (16).
inline double OneMinusB(double y, double r, double d2) { return d2 / (r * (r + y)); }

// The per-(shading point, light) constants of the map (docs/rectangle_map.md, table of section 7;
// the paper's names in brackets).
template <class T>
struct RectangleSetup {
    LocalRect<T> plane;          // the light's frame around o; also the area map of the fallback
    bool valid = false;          // false: every sample has pdf 0
    bool area_fallback = false;  // (21)
    double omega = 0;            // solid angle (double)
    T solid_angle = 0;           // Omega [S]
    T pdf = 0;                   // 1 / Omega, (2)
    // The map's frame (13): local x = sx * (swap ? Y : X), y = sy * (swap ? X : Y), where
    // (X, Y) are the coordinates along the light's edges ex, ey.
    bool swap = false;
    double sx = 1, sy = 1;
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0, h = 0;  // (1) [x0, x1, y0, y1, h = -z0]
    double wx = 0, wy = 0;                         // x1 - x0 and y1 - y0 (exact: the edge lengths)
    // (7), (9) in the paper's b0, b1: T0 [k - pi], neg_b0 = -b0, b1, b1_plus_b0, b1_minus_b0; s_i = sin(theta) at x_i.
    double T0 = 0, neg_b0 = 0, b1 = 0, b1_plus_b0 = 0, b1_minus_b0 = 0, s0 = 0, s1 = 0;
    bool y_beside = false;      // y0 > 0: the y-step interpolates 1 - hy, (16)
    bool polish_x = false;      // refine the x-step by Newton steps (nearly edge-on setups), (20)
    double error_estimate = 0;  // first-order rounding error of the map in (u, v) space, (19)
};

template <class T>
RectangleSetup<T> MakeRectangleSetup(const Vec3<T>& origin, const RectLightFrame<T>& frame) {
    RectangleSetup<T> sr{MakeLocalRect(origin, frame)};  // the plane built in place
    const LocalRect<T>& p = sr.plane;
    if (!p.valid) return sr;
    // Choose the frame (13): the x-slab should contain the foot of o (or be the nearer one).
    const double X0 = p.x0, X1 = p.x0 + p.wx, Y0 = p.y0, Y1 = p.y0 + p.wy;
    // Gaps relative to the edge lengths, gy / wy < gx / wx, compared without dividing.
    sr.swap = std::max({0.0, Y0, -Y1}) * p.wx < std::max({0.0, X0, -X1}) * p.wy;
    double a0 = sr.swap ? Y0 : X0, a1 = sr.swap ? Y1 : X1;
    double c0 = sr.swap ? X0 : Y0, c1 = sr.swap ? X1 : Y1;
    if (a1 < 0) {
        sr.sx = -1;
        std::swap(a0, a1);
        a0 = -a0;
        a1 = -a1;
    }  // near edge first
    if (c1 < 0) {
        sr.sy = -1;
        std::swap(c0, c1);
        c0 = -c0;
        c1 = -c1;
    }  // y1 > 0
    sr.x0 = a0;
    sr.x1 = a1;
    sr.y0 = c0;
    sr.y1 = c1;
    const double wa = sr.wx = sr.swap ? p.wy : p.wx, wc = sr.wy = sr.swap ? p.wx : p.wy;
    const double h = sr.h = p.h;

    // Omega (6), and T0 (9) = the signed solid angle of the strip between the foot of o and
    // the x0 edge (the strips share their pieces when the foot is inside the x-slab).
    const Interval Y{c0, c1, wc};
    if (a0 < 0) {
        const double left = RectSolidAngleLocal({a0, 0, -a0}, Y, h), right = RectSolidAngleLocal({0, a1, a1}, Y, h);
        sr.omega = left + right;
        sr.T0 = -left;
    } else {
        sr.omega = RectSolidAngleLocal({a0, a1, wa}, Y, h);
        sr.T0 = RectSolidAngleLocal({0, a0, a0}, Y, h);
    }
    if (!(sr.omega > 0)) return sr;
    sr.solid_angle = T(sr.omega);
    sr.pdf = T(1 / sr.omega);
    if (!(sr.solid_angle > 0) || !std::isfinite(sr.pdf)) return sr;
    sr.valid = true;

    // Distances shared by the constants below (each square root taken once).
    const double h2 = h * h;
    const double rc0 = std::sqrt(c0 * c0 + h2), rc1 = std::sqrt(c1 * c1 + h2);  // |(0, y_i, h)|
    const double ra0 = std::sqrt(a0 * a0 + h2), ra1 = std::sqrt(a1 * a1 + h2);  // |(x_i, 0, h)|
    sr.neg_b0 = c0 / rc0;                                                       // (7)
    sr.b1 = c1 / rc1;
    sr.b1_plus_b0 = DiffB(c0, c1, rc0, rc1, h2, wc);                                      // (15) at d = h
    sr.b1_minus_b0 = c0 < 0 ? DiffB(-c0, c1, rc0, rc1, h2, c1 + c0) : sr.b1 + sr.neg_b0;  // b(y1) - b(-y0) by (15)
    sr.s0 = a0 / ra0;                                                                     // (9)
    sr.s1 = a1 / ra1;
    sr.y_beside = c0 > 0;

    // First-order rounding error of the map in (u, v) space, (19).
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double e0 = h2 / (h2 + c0 * c0), e1 = h2 / (h2 + c1 * c1);  // 1 - b_i^2
    // |F'(s) s| at x, s = x / |(x, 0, h)|; F'(s) = b1/q1 + b0/q0, cancellation-free when b0 <= 0.
    auto slope = [&](double x, double s) {
        const double oms2 = h2 / (x * x + h2);  // 1 - s^2
        const double q0 = std::sqrt(e0 + sr.neg_b0 * sr.neg_b0 * oms2), q1 = std::sqrt(e1 + sr.b1 * sr.b1 * oms2);
        const double fp = sr.neg_b0 >= 0
                              ? sr.b1_plus_b0 * (sr.b1 + sr.neg_b0) / (q0 * q1 * (sr.b1 * q0 + sr.neg_b0 * q1))
                              : sr.b1 / q1 - sr.neg_b0 / q0;
        return std::abs(fp * s);
    };
    const double ex = eps * (std::abs(sr.T0) + sr.omega + std::max(slope(a0, sr.s0), slope(a1, sr.s1))) / sr.omega;
    // (Inside the y-slab |hy| <= hy1 - hy0, so the error is a few eps.)
    double ey = 2 * eps;
    if (sr.y_beside) {
        const double dmax = std::max(ra0, ra1), dmax2 = dmax * dmax;
        const double r0 = std::sqrt(c0 * c0 + dmax2), r1 = std::sqrt(c1 * c1 + dmax2);
        ey = eps * OneMinusB(c0, r0, dmax2) / DiffB(c0, c1, r0, r1, dmax2, wc);  // (1 - hy0) / (hy1 - hy0)
    }
    sr.polish_x = ex > kRectanglePolishAbove;
    sr.error_estimate = (sr.polish_x ? kRectanglePolishedError : ex) + ey;
    sr.area_fallback = !(sr.error_estimate <= kRectangleMaxError);
    return sr;
}

template <class T>
RectangleSetup<T> MakeRectangleSetup(const Vec3<T>& origin, const RectLight<T>& light) {
    return MakeRectangleSetup(origin, MakeRectLightFrame(light));
}

// Local map coordinates (x, y) -> coordinates (X, Y) along the light's edges, (13).
template <class T>
inline void RectangleToEdgeFrame(const RectangleSetup<T>& sr, double x, double y, double* X, double* Y) {
    const double a = sr.sx * x, b = sr.sy * y;
    *X = sr.swap ? b : a;
    *Y = sr.swap ? a : b;
}

// The map M(u, v) in local coordinates (valid, non-fallback setups).
template <class T>
inline void RectangleMapLocal(const RectangleSetup<T>& sr, double u, double v, double* px, double* py,
                              double* dist = nullptr) {
    // x-step: solve F(s) = T0 + u Omega, (9) -> (10).
    const double Tu = sr.T0 + u * sr.omega;  // T [au - pi]
    const double sT = std::sin(Tu), cT = std::cos(Tu);
    const double omc = cT > 0 ? sT * sT / (1 + cT) : 1 - cT;  // 1 - cos T, (11)
    // |b1 + b0 e^{iT}|^2 as a sum of positive terms, (11).
    double R2;
    if (sr.neg_b0 >= 0) {  // light beside o in y (b0 <= 0): b1 + b0 > 0 small, 1 - cos T
        R2 = sr.b1_plus_b0 * sr.b1_plus_b0 + 2 * sr.neg_b0 * sr.b1 * omc;
    } else {  // b0, b1 > 0: b1 - b0 (stable, may be ~0) and 1 + cos T (~0 as |T| nears pi: grazing)
        const double opc = cT < 0 ? sT * sT / (1 - cT) : 1 + cT;
        R2 = sr.b1_minus_b0 * sr.b1_minus_b0 - 2 * sr.neg_b0 * sr.b1 * opc;
    }
    const double s = ClampNaN(sT / std::sqrt(R2), sr.s0, sr.s1);                 // (10) [cu]
    double x = ClampNaN(sr.h * s / std::sqrt((1 - s) * (1 + s)), sr.x0, sr.x1);  // (12) [xu]
    if (sr.polish_x) {
        // Nearly edge-on: x(s) loses precision where |s| -> 1.  Newton on the stable
        // W([x0, x] x [y0, y1]) = u Omega, with W' from (20).
        const Interval Y{sr.y0, sr.y1, sr.wy};
        double lo = sr.x0, hi = sr.x1;
        for (int it = 0; it < 64; ++it) {
            // Residual from the nearer end, so that W is small and exact near it.
            const double g = u < 0.5 ? RectSolidAngleLocal({sr.x0, x, x - sr.x0}, Y, sr.h) - u * sr.omega
                                     : (1 - u) * sr.omega - RectSolidAngleLocal({x, sr.x1, sr.x1 - x}, Y, sr.h);
            const double d2 = x * x + sr.h * sr.h;
            const double dg = sr.h / d2 * DiffB(sr.y0, sr.y1, std::sqrt(d2), sr.wy);
            // Safeguarded: keep a bracket of the root (W is increasing), bisect when the
            // Newton step leaves it.
            if (g == 0) break;
            (g < 0 ? lo : hi) = x;
            double xn = x - g / dg;
            if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
            const bool done = std::abs(xn - x) <= 1e-15 * (std::abs(x) + sr.h);
            x = xn;
            if (done) break;
        }
    }
    // y-step: linear in hy = y / sqrt(y^2 + d^2), d^2 = x^2 + h^2, (14).
    const double d2 = x * x + sr.h * sr.h, d = std::sqrt(d2);
    const double r0 = std::sqrt(sr.y0 * sr.y0 + d2), r1 = std::sqrt(sr.y1 * sr.y1 + d2);
    double hy, omh;     // hy and 1 - hy [hv, 1 - hv]
    if (sr.y_beside) {  // interpolate 1 - hy = (1 - hy0) - v (hy1 - hy0), (16) and (15)
        omh = OneMinusB(sr.y0, r0, d2) - v * DiffB(sr.y0, sr.y1, r0, r1, d2, sr.wy);
        hy = 1 - omh;
    } else {  // y0 <= 0 < y1: hy1 - hy0 is a sum of two non-negative terms
        const double hy0 = sr.y0 / r0;
        hy = hy0 + v * (sr.y1 / r1 - hy0);
        omh = 1 - hy;
    }
    const double c = std::sqrt(omh * (1 + hy));  // sqrt(1 - hy^2) = d / r
    const double y = hy * d / c;                 // (14) [yv]
    *px = x;
    *py = ClampNaN(y, sr.y0, sr.y1);
    if (dist) *dist = *py == y ? d / c : std::sqrt(d2 + *py * *py);  // |(x, y, h)|, (17)
}

template <class T>
LightSample<T> SampleRectangleAt(const RectangleSetup<T>& sr, double u, double v) {
    if (!sr.valid) return {};
    if (sr.area_fallback) return SampleAreaAt(sr.plane, u, v);
    double x, y, dist, X, Y;
    RectangleMapLocal(sr, u, v, &x, &y, &dist);
    RectangleToEdgeFrame(sr, x, y, &X, &Y);
    return LightSampleFromLocal(sr.plane, X, Y, sr.pdf, dist);
}

template <class T>
LightSample<T> SampleRectangle(const RectangleSetup<T>& sr, Point2<T> uv) {
    return SampleRectangleAt(sr, double(uv.u), double(uv.v));
}

// Solid-angle pdf of choosing p (a point on the light), (2) or the fallback's (21).
template <class T>
T RectanglePDF(const RectangleSetup<T>& sr, const Vec3<T>& p) {
    if (!sr.valid) return 0;
    if (sr.area_fallback) return AreaPDF(sr.plane, p);
    return sr.pdf;
}

// The inverse map in double, (18): point on the light -> (u, v) in [0,1]^2.
template <class T>
Point2<double> InvertRectangle(const RectangleSetup<T>& sr, const Vec3<T>& p) {
    if (!sr.valid) return {};
    if (sr.area_fallback) return InvertArea(sr.plane, p);
    const Point2<double> e = EdgeOffsets(sr.plane, p);
    // Offsets from the map's x0 / y0 edges.
    const double oa = sr.swap ? e.v : e.u, ob = sr.swap ? e.u : e.v;
    const double ox = ClampNaN(sr.sx > 0 ? oa : sr.wx - oa, 0, sr.wx);
    const double oy = ClampNaN(sr.sy > 0 ? ob : sr.wy - ob, 0, sr.wy);
    const double x = sr.x0 + ox;
    const Interval Y{sr.y0, sr.y1, sr.wy};
    const double u = ox <= sr.wx / 2 ? RectSolidAngleLocal({sr.x0, x, ox}, Y, sr.h) / sr.omega
                                     : 1 - RectSolidAngleLocal({x, sr.x1, sr.wx - ox}, Y, sr.h) / sr.omega;
    const double d = std::sqrt(x * x + sr.h * sr.h);
    const double v = DiffB(sr.y0, sr.y0 + oy, d, oy) / DiffB(sr.y0, sr.y1, d, sr.wy);
    return {ClampNaN(u, 0, 1), ClampNaN(v, 0, 1)};
}

// Vector from o to the light corner that M maps (i, j) in {0,1}^2 to (any length).
template <class T>
Vec3d RectangleCornerVector(const RectangleSetup<T>& sr, int i, int j) {
    double X, Y;
    if (sr.area_fallback) {
        X = sr.plane.x0 + i * sr.plane.wx;
        Y = sr.plane.y0 + j * sr.plane.wy;
    } else {
        RectangleToEdgeFrame(sr, i ? sr.x1 : sr.x0, j ? sr.y1 : sr.y0, &X, &Y);
    }
    return LocalVector(sr.plane, X, Y);
}

// Solid angle of the light seen from `origin` (0 where the setup is invalid), in double.
template <class T>
double RectangleSolidAngle(const Vec3<T>& origin, const RectLight<T>& light) {
    const RectangleSetup<T> sr = MakeRectangleSetup(origin, light);
    return sr.valid ? sr.omega : 0.0;
}

}  // namespace sphrect
