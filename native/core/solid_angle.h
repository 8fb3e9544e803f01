// Solid angles without cancellation: of a triangle (Van Oosterom & Strackee) and of an
// axis-aligned rectangle in the plane z = h seen from the origin, split at the foot of the
// origin.  Shared by `triangles` and `rectangle`; the derivation is docs/rectangle_map.md,
// section 2, whose equation numbers the comments cite.
#pragma once

#include <algorithm>
#include <cmath>

#include "vec3.h"

namespace sphrect {

// Solid angle of the triangle abc (vectors from the viewpoint, any length; la, lb, lc their
// lengths), eq. (3): tan(W/2) = |a.(b x c)| / (abc + (a.b)c + (a.c)b + (b.c)a).
inline double SphericalTriangleSolidAngle(const Vec3d& a, const Vec3d& b, const Vec3d& c, double la, double lb,
                                          double lc) {
    const double num = std::abs(Dot(a, Cross(b, c)));
    const double den = la * lb * lc + Dot(a, b) * lc + Dot(a, c) * lb + Dot(b, c) * la;
    return 2 * std::atan2(num, den);
}

// The denominator of eq. (3), for callers that take the triple product from the triangle's
// edges, |a.((b - a) x (c - a))|, which does not cancel for a distant triangle:
// W = 2 atan2(|triple|, denominator).
inline double SphericalTriangleDenominator(const Vec3d& a, const Vec3d& b, const Vec3d& c, double la, double lb,
                                           double lc) {
    return la * lb * lc + Dot(a, b) * lc + Dot(a, c) * lb + Dot(b, c) * la;
}

// An interval [a0, a1] with its width w = a1 - a0 carried exactly: both the endpoints
// and the width matter, and neither can be recomputed from the others (a light 1e6
// sizes away loses its width in a1 - a0; a foot of o 1e-9 from a1 loses a1 in a0 + w).
struct Interval {
    double a0, a1, w;
};

// Half solid angles added as arguments of a complex product, eq. (6): each spherical triangle
// (or corner piece) contributes the factor 1 + i tan(W_k / 2), and W = 2 arg(prod).  Every
// factor has 0 <= tan(W_k / 2) <= 1, so the product stays between 1 and 16 in magnitude.
// Precision: the imaginary part is a sum of non-negative terms while the real part is
// positive, i.e. while W < pi, so a small W keeps a relative error of a few ulps; the real
// part can cancel, but only near W = pi, where the few-ulp normwise error of the product is
// also a few ulps of W.
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

// Adds the solid angle of X x Y in the plane z = h > 0 seen from the origin, for a0 >= 0 in
// both: eq. (3) on the triangles (00,10,11), (00,11,01).  In one quadrant every dot product is
// >= h^2 > 0, so the denominators are sums of positive terms, and the triple product is
// exactly h wx wy, eq. (4): a relative error of a few ulps.
inline void AddQuadrantRectSolidAngle(const Interval& X, const Interval& Y, double h, HalfAngleSum& sum) {
    const double x0 = X.a0, x1 = X.a1, y0 = Y.a0, y1 = Y.a1, h2 = h * h;
    if (x0 == 0 && y0 == 0) {
        // A corner at the foot of o, eq. (5): tan(W/2) = w l / (h r + |(h r, w l)|).
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
        if (I.a0 >= 0) {
            out[0] = I;
            return 1;
        }
        if (I.a1 <= 0) {
            out[0] = {-I.a1, -I.a0, I.w};
            return 1;
        }
        out[0] = {0, -I.a0, -I.a0};
        out[1] = {0, I.a1, I.a1};
        return 2;
    };
    const int nx = pieces(X, xs), ny = pieces(Y, ys);
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) AddQuadrantRectSolidAngle(xs[i], ys[j], h, sum);
}

// Solid angle of the triangle with in-plane corners (x[i], y[i]) in the plane z = h > 0 seen
// from the origin, for a triangle seen nearly edge-on, where Van Oosterom & Strackee on the
// whole triangle cancels (its denominator ~ 0 with the triple product ~ h): clipped at x = 0
// and y = 0 (Sutherland-Hodgman) into pieces in one quadrant each, mirrored into the first and
// fanned into triangles, whose dot products are all >= h^2 > 0, eq. (3)-(4) as in
// AddQuadrantRectSolidAngle.  A clip point is computed from the same two corners for both
// sides of its line, so the pieces tile the triangle.
inline double PlanarTriangleSolidAngleLocal(const double x[3], const double y[3], double h) {
    struct P2 {
        double x, y;
    };
    // Keeps the part of `in` with s * (axis coordinate) >= 0.
    auto clip = [](const P2* in, int n, int axis, double s, P2* out) {
        int m = 0;
        auto c = [&](const P2& p) { return s * (axis == 0 ? p.x : p.y); };
        for (int i = 0; i < n; ++i) {
            const P2 &p = in[i], &q = in[(i + 1) % n];
            const double cp = c(p), cq = c(q);
            if (cp >= 0) out[m++] = p;
            if ((cp < 0) != (cq < 0) && cp != 0 && cq != 0) {
                // The crossing from the corner with the smaller coordinate, so both sides agree.
                const P2 &lo = (axis == 0 ? p.x < q.x : p.y < q.y) ? p : q, &hi = &lo == &p ? q : p;
                const double t = axis == 0 ? -lo.x / (hi.x - lo.x) : -lo.y / (hi.y - lo.y);
                out[m++] = axis == 0 ? P2{0, lo.y + t * (hi.y - lo.y)} : P2{lo.x + t * (hi.x - lo.x), 0};
            }
        }
        return m;
    };
    const P2 tri[3] = {{x[0], y[0]}, {x[1], y[1]}, {x[2], y[2]}};
    const double h2 = h * h;
    HalfAngleSum sum;
    for (double sx : {1.0, -1.0}) {
        P2 half[4], piece[5];
        const int nh = clip(tri, 3, 0, sx, half);
        for (double sy : {1.0, -1.0}) {
            const int n = clip(half, nh, 1, sy, piece);
            if (n < 3) continue;
            for (int i = 0; i < n; ++i) piece[i] = {std::abs(piece[i].x), std::abs(piece[i].y)};
            auto len = [&](const P2& p) { return std::sqrt(p.x * p.x + p.y * p.y + h2); };
            auto dot = [&](const P2& p, const P2& q) { return p.x * q.x + p.y * q.y + h2; };
            const P2& a = piece[0];
            const double la = len(a);
            for (int i = 1; i + 1 < n; ++i) {
                const P2 &b = piece[i], &c = piece[i + 1];
                const double lb = len(b), lc = len(c);
                const double num = h * std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
                const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
                sum.Add(num / den);
            }
        }
    }
    return sum.SolidAngle();
}

inline double RectSolidAngleLocal(const Interval& X, const Interval& Y, double h) {
    HalfAngleSum sum;
    AddRectSolidAngleLocal(X, Y, h, sum);
    return sum.SolidAngle();
}

}  // namespace sphrect
