// Technique `rectangle`: the area-preserving map of Urena, Fajardo & King,
// "An Area Preserving Parametrization for Spherical Rectangles" (EGSR 2013),
// M(u, v): x from u alone through the sub-rectangle of solid angle u * Omega,
// then y linearly in the y-coordinate on the unit sphere.  du dv = dw / Omega.
//
// Numerically robust formulation (the paper's float formulas are kept in
// textbook_spherical_rectangle.h as a baseline):
//
//  * Local frame.  The shading point o is the origin, the light is the rectangle
//    [x0,x1] x [y0,y1] in the plane z = h > 0.  All setup is done in double from
//    the (float) inputs; the per-sample work is done in double as well and the
//    results are rounded to T once (float interface, mixed precision inside).
//
//  * Solid angles (Omega, and every sub-rectangle) without cancellation: the
//    rectangle is split at the foot of o into up to four pieces, each mirrored into
//    the first quadrant, and each piece is two triangles for Van Oosterom & Strackee,
//    tan(W/2) = |a.(b x c)| / (abc + (a.b)c + (a.c)b + (b.c)a).  With all corners at
//    height h the triple product is exactly h w l (column operations), and inside
//    one quadrant every dot product is positive, so the denominator is a sum of
//    positive terms.  (Without the split, a foot of o on a diagonal makes it cancel:
//    error eps / h.)  A piece with a corner at the foot is atan(w l / (h r)).  The
//    half-angles of all pieces are summed as the argument of a complex product
//    (HalfAngleSum): one atan2 per solid angle instead of one per triangle.
//    Omega is accurate to a few ulps of double in every configuration.
//
//  * x-step.  With s = sin(theta), x = h tan(theta), the solid angle of the strip
//    [0, x] x [y0, y1] is F(s) = asin(b1 s) - asin(b0 s), b_i = y_i / sqrt(y_i^2+h^2)
//    (integrate dW = (h1 - h0) dtheta).  Solving F(s) = T gives
//        s = sin T / |b1 - b0 e^{iT}|,
//    the paper's formula in other variables.  (Its sign factor, the sign of
//    b1 - b0 cos T, is always +: b1 - b0 cos T >= b1 - b0 > 0 when b0 >= 0, and when
//    b0 < 0 every reachable T has |T| <= asin b1 + asin|b0|, so that
//    b1 - b0 cos T >= b1 (1 - b0^2) + |b0| sqrt((1 - b1^2)(1 - b0^2)) > 0.  Testing the
//    computed sign could only flip s to the wrong side where rounding makes it ~0.)  T = T0 + u Omega with T0 = F(s0), the
//    signed strip from the foot of o to the near edge, computed by Van Oosterom &
//    Strackee.  The frame is chosen (axes swapped / mirrored, once per setup) so
//    that the foot of o lies inside the x-slab, or as close to it as possible, and
//    x0 is the near edge: then |T0| <= Omega, or small, and u Omega is not lost
//    when it is added (the paper's k + u S loses u entirely when S << k ~ pi).
//    |b1 - b0 e^{iT}|^2 is a sum of positive terms: (b1 - b0)^2 + 2 b0 b1 (1 - cos T)
//    when b0 >= 0, (b1 + b0)^2 - 2 b0 b1 (1 + cos T) when b0 < 0 < b1, with b1 -+ b0
//    cancellation-free and 1 -+ cos T = sin^2 T / (1 +- cos T).
//
//  * y-step.  y is linear in hy = y / sqrt(y^2 + d^2), d^2 = x^2 + h^2.  When the
//    light is beside o in y (y0 > 0 after mirroring), 1 - hy = d^2 / (r (r + y)) is
//    interpolated instead of hy, so that a light 10^6 sizes away keeps its v.
//
//  * Inverse: u = W([x0, x] x [y0, y1]) / Omega by Van Oosterom & Strackee, v by
//    a cancellation-free difference of hy.  Stable in every configuration.
//
//  * What remains ill-conditioned: x(s) near s = +-1 (a light seen almost edge-on,
//    much larger than the height of o), and the y-offset of a thin light ~1e6 sizes
//    away beside o in y.  Per setup, a first-order estimate of the map's rounding
//    error in (u, v) space is computed (error_estimate).  When the x-step's part
//    exceeds kSphericalRectanglePolishAbove, the x-step is refined by safeguarded
//    Newton steps on the stable W([x0, x] x [y0, y1]) = u Omega (polish_x; costs
//    a few solid-angle evaluations per sample, only in such setups).  When the
//    remaining estimate exceeds kSphericalRectangleMaxError, the setup switches to
//    uniform area sampling (area_fallback; in the hard-case suite only thin lights
//    1e6 sizes away, where area sampling is practically exact).  Both decisions are
//    made once per setup and Sample, PDF and Invert all follow them, so the pdf
//    returned is always the true pdf of the point returned (unlike Cycles / pbrt-v4,
//    whose fallback keeps returning 1 / Omega).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "area_sampling.h"
#include "light_sample.h"
#include "rect_light.h"

namespace sphrect {

// Largest accepted estimate of the map's rounding error in (u, v) space.
constexpr double kSphericalRectangleMaxError = 1e-7;
// The x-step's closed form is refined by (safeguarded) Newton steps on the stable
// sub-rectangle solid angle when its error estimate exceeds this.
constexpr double kSphericalRectanglePolishAbove = 1e-10;
// What is left of the x-step's error after the Newton refinement.
constexpr double kSphericalRectanglePolishedError = 1e-12;

namespace srect {

// An interval [a0, a1] with its width w = a1 - a0 carried exactly: both the endpoints
// and the width matter, and neither can be recomputed from the others (a light 1e6
// sizes away loses its width in a1 - a0; a foot of o 1e-9 from a1 loses a1 in a0 + w).
struct Interval {
    double a0, a1, w;
};

// Half solid angles added as arguments of a complex product: each spherical triangle (or
// corner piece) contributes the factor 1 + i tan(W_k / 2), and W = 2 arg(prod), so a region
// made of up to eight triangles costs one atan2 instead of eight.  Every factor has
// 0 <= tan(W_k / 2) <= 1 (a triangle inside one quadrant of the plane subtends less than
// pi / 2), so the product stays between 1 and 16 in magnitude (no overflow).  Precision: the
// imaginary part is a sum of non-negative terms while the real part is positive, i.e. while
// W < pi, so a small W keeps a relative error of a few ulps; the real part can cancel, but
// only near W = pi, where the few-ulp normwise error of the product is also a few ulps of W.
struct HalfAngleSum {
    double re = 1, im = 0;
    void Add(double tan_half) {
        const double r = re - im * tan_half, i = im + re * tan_half;
        re = r;
        im = i;
    }
    // (im >= 0 mathematically; rounding could push it below 0 only when W is within a few ulps
    // of 2 pi, where +0 keeps W = 2 pi rather than jumping to -2 pi.)
    double SolidAngle() const { return 2 * std::atan2(std::max(im, 0.0), re); }
};

// Adds the solid angle of X x Y in the plane z = h > 0 seen from the origin, for a0 >= 0
// in both: Van Oosterom & Strackee on the triangles (00,10,11), (00,11,01),
// tan(W/2) = |a.(b x c)| / (abc + (a.b)c + (a.c)b + (b.c)a).  In one quadrant every dot
// product is >= h^2 > 0, so the denominators are sums of positive terms, and the triple
// product is exactly h wx wy: a relative error of a few ulps.
inline void AddQuadrantRectSolidAngle(const Interval& X, const Interval& Y, double h, HalfAngleSum& sum) {
    const double x0 = X.a0, x1 = X.a1, y0 = Y.a0, y1 = Y.a1, h2 = h * h;
    if (x0 == 0 && y0 == 0) {
        // A corner at the foot of o: W = atan(w l / (h r)), whose half-angle tangent is
        // w l / (h r + |(h r, w l)|), |(h r, w l)|^2 = (h^2 + w^2)(h^2 + l^2): all terms positive.
        const double r = std::sqrt(x1 * x1 + y1 * y1 + h2);
        sum.Add(X.w * Y.w / (h * r + std::sqrt((h2 + x1 * x1) * (h2 + y1 * y1))));
        return;
    }
    const double l00 = std::sqrt(x0 * x0 + y0 * y0 + h2), l10 = std::sqrt(x1 * x1 + y0 * y0 + h2);
    const double l11 = std::sqrt(x1 * x1 + y1 * y1 + h2), l01 = std::sqrt(x0 * x0 + y1 * y1 + h2);
    const double num = h * X.w * Y.w;
    const double den1 = l00 * l10 * l11 + (x0 * x1 + y0 * y0 + h2) * l11 + (x0 * x1 + y0 * y1 + h2) * l10 +
                        (x1 * x1 + y0 * y1 + h2) * l00;
    const double den2 = l00 * l11 * l01 + (x0 * x1 + y0 * y1 + h2) * l01 + (x0 * x0 + y0 * y1 + h2) * l11 +
                        (x0 * x1 + y1 * y1 + h2) * l00;
    sum.Add(num / den1);
    sum.Add(num / den2);
}

// Adds the solid angle of X x Y in the plane z = h > 0 seen from the origin: split at
// x = 0 and y = 0 into up to four quadrant pieces, each mirrored into the first quadrant.
// (Without the split, a foot of o on a diagonal or near an edge makes the denominators
// cancel: relative error eps / h.)
inline void AddRectSolidAngleLocal(const Interval& X, const Interval& Y, double h, HalfAngleSum& sum) {
    Interval xs[2], ys[2];
    auto pieces = [](const Interval& I, Interval* out) {
        if (I.a0 >= 0) { out[0] = I; return 1; }
        if (I.a1 <= 0) { out[0] = {-I.a1, -I.a0, I.w}; return 1; }
        out[0] = {0, -I.a0, -I.a0};
        out[1] = {0, I.a1, I.a1};
        return 2;
    };
    const int nx = pieces(X, xs), ny = pieces(Y, ys);
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) AddQuadrantRectSolidAngle(xs[i], ys[j], h, sum);
}

inline double RectSolidAngleLocal(const Interval& X, const Interval& Y, double h) {
    HalfAngleSum sum;
    AddRectSolidAngleLocal(X, Y, h, sum);
    return sum.SolidAngle();
}

// b(yb) - b(ya) with b(y) = y / sqrt(y^2 + d^2), without cancellation; dy = yb - ya
// (passed, exact), ra = sqrt(ya^2 + d^2), rb = sqrt(yb^2 + d^2) and d2 = d^2.
inline double DiffB(double ya, double yb, double ra, double rb, double d2, double dy) {
    if (ya * yb > 0) return d2 * dy * (yb + ya) / (ra * rb * (yb * ra + ya * rb));
    return yb / rb - ya / ra;
}

// The same from d alone.
inline double DiffB(double ya, double yb, double d, double dy) {
    const double d2 = d * d;
    return DiffB(ya, yb, std::sqrt(ya * ya + d2), std::sqrt(yb * yb + d2), d2, dy);
}

// 1 - b(y) for y >= 0, with r = sqrt(y^2 + d^2) and d2 = d^2.
inline double OneMinusB(double y, double r, double d2) { return d2 / (r * (r + y)); }

}  // namespace srect

template <class T>
struct SphericalRectangle {
    AreaRect<T> plane;      // the light's frame around o; also the area map of the fallback
    bool valid = false;     // false: every sample has pdf 0
    bool area_fallback = false;
    double omega = 0;       // solid angle (double)
    T solid_angle = 0;      // Omega
    T pdf = 0;              // 1 / Omega
    // The map's frame: local x = sx * (swap ? Y : X), y = sy * (swap ? X : Y), where
    // (X, Y) are the coordinates along the light's edges ex, ey.
    bool swap = false;
    double sx = 1, sy = 1;
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0, h = 0;
    double wx = 0, wy = 0;  // x1 - x0 and y1 - y0 (exact: the edge lengths)
    double T0 = 0, b0 = 0, b1 = 0, db = 0, pb = 0, s0 = 0, s1 = 0;  // db = b1 - b0, pb = b1 + b0
    bool y_beside = false;  // y0 > 0: the y-step interpolates 1 - hy
    bool polish_x = false;  // refine the x-step by Newton steps (nearly edge-on setups)
    double error_estimate = 0;  // first-order rounding error of the map in (u, v) space
};

template <class T>
SphericalRectangle<T> MakeSphericalRectangle(const Vec3<T>& origin, const RectLightFrame<T>& frame) {
    using namespace srect;
    SphericalRectangle<T> sr{MakeAreaRect(origin, frame)};  // the plane built in place
    const AreaRect<T>& p = sr.plane;
    if (!p.valid) return sr;
    // Choose the frame: the x-slab should contain the foot of o (or be the nearer one).
    const double X0 = p.x0, X1 = p.x0 + p.wx, Y0 = p.y0, Y1 = p.y0 + p.wy;
    // Gaps relative to the edge lengths, gy / wy < gx / wx, compared without dividing.
    sr.swap = std::max({0.0, Y0, -Y1}) * p.wx < std::max({0.0, X0, -X1}) * p.wy;
    double a0 = sr.swap ? Y0 : X0, a1 = sr.swap ? Y1 : X1;
    double c0 = sr.swap ? X0 : Y0, c1 = sr.swap ? X1 : Y1;
    if (a1 < 0) { sr.sx = -1; std::swap(a0, a1); a0 = -a0; a1 = -a1; }  // near edge first
    if (c1 < 0) { sr.sy = -1; std::swap(c0, c1); c0 = -c0; c1 = -c1; }  // y1 > 0
    sr.x0 = a0; sr.x1 = a1; sr.y0 = c0; sr.y1 = c1;
    const double wa = sr.wx = sr.swap ? p.wy : p.wx, wc = sr.wy = sr.swap ? p.wx : p.wy;
    const double h = sr.h = p.h;

    // Omega, and T0 = the signed solid angle of the strip between the foot of o and the
    // x0 edge (the strips share their pieces when the foot is inside the x-slab).
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
    sr.b0 = c0 / rc0;
    sr.b1 = c1 / rc1;
    sr.db = DiffB(c0, c1, rc0, rc1, h2, wc);
    sr.pb = c0 < 0 ? DiffB(-c0, c1, rc0, rc1, h2, c1 + c0) : sr.b1 + sr.b0;
    sr.s0 = a0 / ra0;
    sr.s1 = a1 / ra1;
    sr.y_beside = c0 > 0;

    // First-order rounding error of the map in (u, v) space (unit roundoff eps):
    //  x-step: T = T0 + u Omega, and s rounded near its ends: eps (|T0| + Omega + |F'(s) s|) / Omega;
    //  y-step: eps max(|hy|) / (hy1 - hy0) at the largest d.
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double e0 = h2 / (h2 + c0 * c0), e1 = h2 / (h2 + c1 * c1);  // 1 - b_i^2
    // |F'(s) s| at x, s = x / |(x, 0, h)|; F'(s) = b1/q1 - b0/q0, q_i^2 = 1 - b_i^2 s^2, cancellation-free.
    auto slope = [&](double x, double s) {
        const double oms2 = h2 / (x * x + h2);  // 1 - s^2
        const double q0 = std::sqrt(e0 + sr.b0 * sr.b0 * oms2), q1 = std::sqrt(e1 + sr.b1 * sr.b1 * oms2);
        const double fp = sr.b0 >= 0 ? sr.db * (sr.b1 + sr.b0) / (q0 * q1 * (sr.b1 * q0 + sr.b0 * q1))
                                     : sr.b1 / q1 - sr.b0 / q0;
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
    sr.polish_x = ex > kSphericalRectanglePolishAbove;
    sr.error_estimate = (sr.polish_x ? kSphericalRectanglePolishedError : ex) + ey;
    sr.area_fallback = !(sr.error_estimate <= kSphericalRectangleMaxError);
    return sr;
}

template <class T>
SphericalRectangle<T> MakeSphericalRectangle(const Vec3<T>& origin, const RectLight<T>& light) {
    return MakeSphericalRectangle(origin, MakeRectLightFrame(light));
}

// Local map coordinates (x, y) -> coordinates (X, Y) along the light's edges.
template <class T>
inline void SphericalRectangleToEdgeFrame(const SphericalRectangle<T>& sr, double x, double y, double* X,
                                          double* Y) {
    const double a = sr.sx * x, b = sr.sy * y;
    *X = sr.swap ? b : a;
    *Y = sr.swap ? a : b;
}

// The map M(u, v) in local coordinates (valid, non-fallback setups).
template <class T>
inline void SphericalRectangleMapLocal(const SphericalRectangle<T>& sr, double u, double v, double* px,
                                       double* py, double* dist = nullptr) {
    // x-step: solve F(s) = T0 + u Omega.
    const double Tu = sr.T0 + u * sr.omega;
    const double sT = std::sin(Tu), cT = std::cos(Tu);
    const double omc = cT > 0 ? sT * sT / (1 + cT) : 1 - cT;  // 1 - cos T
    // |b1 - b0 e^{iT}|^2 as a sum of positive terms.
    double R2;
    if (sr.b0 >= 0) {  // light beside o in y: b1 - b0 > 0 small, 1 - cos T
        R2 = sr.db * sr.db + 2 * sr.b0 * sr.b1 * omc;
    } else {  // b0 < 0 < b1: b1 + b0 (stable, may be ~0) and 1 + cos T (~0 as |T| nears pi: grazing)
        const double opc = cT < 0 ? sT * sT / (1 - cT) : 1 + cT;
        R2 = sr.pb * sr.pb - 2 * sr.b0 * sr.b1 * opc;
    }
    const double s = ClampNaN(sT / std::sqrt(R2), sr.s0, sr.s1);
    double x = ClampNaN(sr.h * s / std::sqrt((1 - s) * (1 + s)), sr.x0, sr.x1);
    if (sr.polish_x) {
        // Nearly edge-on: x(s) loses precision where |s| -> 1.  Newton on the stable
        // W([x0, x] x [y0, y1]) = u Omega, W' = h / (x^2 + h^2) (hy1 - hy0).
        const srect::Interval Y{sr.y0, sr.y1, sr.wy};
        double lo = sr.x0, hi = sr.x1;
        for (int it = 0; it < 64; ++it) {
            // Residual from the nearer end, so that W is small and exact near it.
            const double g = u < 0.5 ? srect::RectSolidAngleLocal({sr.x0, x, x - sr.x0}, Y, sr.h) - u * sr.omega
                                     : (1 - u) * sr.omega - srect::RectSolidAngleLocal({x, sr.x1, sr.x1 - x}, Y, sr.h);
            const double d2 = x * x + sr.h * sr.h;
            const double dg = sr.h / d2 * srect::DiffB(sr.y0, sr.y1, std::sqrt(d2), sr.wy);
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
    // y-step: linear in hy = y / sqrt(y^2 + d^2), d^2 = x^2 + h^2.
    const double d2 = x * x + sr.h * sr.h, d = std::sqrt(d2);
    const double r0 = std::sqrt(sr.y0 * sr.y0 + d2), r1 = std::sqrt(sr.y1 * sr.y1 + d2);
    double hy, omh;  // hy and 1 - hy
    if (sr.y_beside) {  // interpolate 1 - hy: q0 - v (hy1 - hy0), both terms cancellation-free
        omh = srect::OneMinusB(sr.y0, r0, d2) - v * srect::DiffB(sr.y0, sr.y1, r0, r1, d2, sr.wy);
        hy = 1 - omh;
    } else {  // y0 <= 0 < y1: hy1 - hy0 is a sum of two non-negative terms
        const double hy0 = sr.y0 / r0;
        hy = hy0 + v * (sr.y1 / r1 - hy0);
        omh = 1 - hy;
    }
    const double c = std::sqrt(omh * (1 + hy));  // sqrt(1 - hy^2) = d / r
    const double y = hy * d / c;
    *px = x;
    *py = ClampNaN(y, sr.y0, sr.y1);
    if (dist) *dist = *py == y ? d / c : std::sqrt(d2 + *py * *py);  // |(x, y, h)|
}

template <class T>
LightSample<T> SampleSphericalRectangleAt(const SphericalRectangle<T>& sr, double u, double v) {
    if (!sr.valid) return {};
    if (sr.area_fallback) return AreaSampleAt(sr.plane, u, v);
    double x, y, dist, X, Y;
    SphericalRectangleMapLocal(sr, u, v, &x, &y, &dist);
    SphericalRectangleToEdgeFrame(sr, x, y, &X, &Y);
    return LightSampleFromLocal(sr.plane, X, Y, sr.pdf, dist);
}

template <class T>
LightSample<T> SampleSphericalRectangle(const SphericalRectangle<T>& sr, Point2<T> uv) {
    return SampleSphericalRectangleAt(sr, double(uv.u), double(uv.v));
}

// Solid-angle pdf of choosing p (a point on the light).
template <class T>
T SphericalRectanglePDF(const SphericalRectangle<T>& sr, const Vec3<T>& p) {
    if (!sr.valid) return 0;
    if (sr.area_fallback) return RectangleAreaPDF(sr.plane, p);
    return sr.pdf;
}

// The inverse map in double: point on the light -> (u, v) in [0,1]^2.
template <class T>
Point2<double> InvertSphericalRectangleLocal(const SphericalRectangle<T>& sr, const Vec3<T>& p) {
    if (!sr.valid) return {};
    if (sr.area_fallback) return InvertRectangleAreaLocal(sr.plane, p);
    const Vec3d q = Vec3d(p) - Vec3d(sr.plane.light.corner);
    // Offsets along the light's edges (no difference of two large coordinates).
    const double oX = Dot(q, sr.plane.exh), oY = Dot(q, sr.plane.eyh);
    // Offsets from the map's x0 / y0 edges.
    const double oa = sr.swap ? oY : oX, ob = sr.swap ? oX : oY;
    const double ox = ClampNaN(sr.sx > 0 ? oa : sr.wx - oa, 0, sr.wx);
    const double oy = ClampNaN(sr.sy > 0 ? ob : sr.wy - ob, 0, sr.wy);
    const double x = sr.x0 + ox;
    const srect::Interval Y{sr.y0, sr.y1, sr.wy};
    const double u = ox <= sr.wx / 2 ? srect::RectSolidAngleLocal({sr.x0, x, ox}, Y, sr.h) / sr.omega
                                     : 1 - srect::RectSolidAngleLocal({x, sr.x1, sr.wx - ox}, Y, sr.h) / sr.omega;
    const double d = std::sqrt(x * x + sr.h * sr.h);
    const double v = srect::DiffB(sr.y0, sr.y0 + oy, d, oy) / srect::DiffB(sr.y0, sr.y1, d, sr.wy);
    return {ClampNaN(u, 0, 1), ClampNaN(v, 0, 1)};
}

template <class T>
Point2<T> InvertSphericalRectangleSample(const SphericalRectangle<T>& sr, const Vec3<T>& p) {
    const Point2<double> uv = InvertSphericalRectangleLocal(sr, p);
    return {T(uv.u), T(uv.v)};
}

// Vector from o to the light corner that M maps (i, j) in {0,1}^2 to (any length).
template <class T>
Vec3d SphericalRectangleCornerVector(const SphericalRectangle<T>& sr, int i, int j) {
    double X, Y;
    if (sr.area_fallback) {
        X = sr.plane.x0 + i * sr.plane.wx;
        Y = sr.plane.y0 + j * sr.plane.wy;
    } else {
        SphericalRectangleToEdgeFrame(sr, i ? sr.x1 : sr.x0, j ? sr.y1 : sr.y0, &X, &Y);
    }
    return LocalVector(sr.plane, X, Y);
}

// Solid angle of the light seen from `origin` (0 where the setup is invalid), in double.
template <class T>
double SphericalRectangleSolidAngle(const Vec3<T>& origin, const RectLight<T>& light) {
    const SphericalRectangle<T> sr = MakeSphericalRectangle(origin, light);
    return sr.valid ? sr.omega : 0.0;
}

}  // namespace sphrect
