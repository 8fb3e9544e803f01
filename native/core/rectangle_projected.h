// Technique `rectangle_projected`: points on the light with density proportional to the
// cosine at the shading point, i.e. directions uniform in *projected* solid angle, after
// C. Peters, "BRDF Importance Sampling for Polygonal Lights" (ACM TOG 40(4), SIGGRAPH 2021).
// The derivation in short (our own formulation of the published idea; docs/rectangle_projected.md):
//
//  1. Clip the rectangle against the horizon of the normal n (n . w >= 0): a convex polygon of
//     up to 5 vertices.  Its edges are arcs of great circles.
//  2. Malley: project the directions orthographically onto the tangent plane of n (drop the
//     n-component).  A uniform point of the projected region, lifted back to the hemisphere,
//     is a direction with density cos(theta) / E, E = the region's area = the projected solid
//     angle (the irradiance of a unit-radiance light).
//  3. A great-circle arc from a to b, unit normal g = a x b / |a x b| and length gamma, seen
//     from the disk's centre (the projection of n): parametrised by its arc angle s,
//     w(s) = a cos s + (g x a) sin s, it sweeps the area  d/ds (1/2 |w_xy x w_xy'|) = 1/2 g_z,
//     a constant.  So the "sector" between the centre and the arc has the signed area
//     S = 1/2 gamma g_z (each term of Lambert's formula E = 1/2 sum_i gamma_i g_i . n), and
//     the arc angle at which a sector reaches a given area is linear in that area.
//  4. If n lies inside the polygon ("star" case: every g_z >= 0 once oriented) the region is
//     the union of the sectors: choose a sector by its area, s linearly, and the radius as
//     sqrt(v) of the boundary's (uniform in a sector of constant sweep rate).  Otherwise the
//     region is bounded, at each azimuth, by a far arc (g_z > 0) and a near arc (g_z < 0):
//     between consecutive vertex azimuths the area swept is k_F (s_F - s_F0) - k_N (s_N - s_N0)
//     (k = |g_z| / 2), inverted for s_F by safeguarded Newton steps (derivative
//     k_F (1 - r_N^2 / r_F^2)) from a Hermite guess, and r^2 is linear in v between r_N^2 and r_F^2.
//     (Cost: the setup takes one atan2 per edge and per interior breakpoint, a sample about two.)
//  5. The direction is intersected with the light's plane in the light's local frame.
//
// Robustness: E is computed from the vertices in the light's local frame (local_rect.h) with
// the arcs' cross products taken against the exact edge directions, so that E has a small
// relative error even for far or thin lights; the pdf of a sample is cos / E evaluated at the
// returned point, so it is always the pdf of the point returned and cos / pdf = E for every
// sample.  The sweep (3, 4) works with unit vectors in the shading frame, whose rounding
// (~eps absolute in the arc angles) is not small against E when the light covers a tiny
// projected solid angle (far, thin or grazing lights).  Where the estimated relative error of
// the sweep exceeds kProjectedMaxError the setup switches to `rectangle` (rectangle.h), which
// Sample, PDF and Invert all follow; so does a zero or non-finite normal.  There the light's
// extent in angle is tiny, so cos is nearly constant over it and `rectangle` nearly as good.
// A light wholly below the horizon is invalid.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "rectangle.h"

namespace sphrect {

// Largest accepted estimate of the sweep's relative error (in u); beyond it: `rectangle`.
constexpr double kProjectedMaxError = 1e-7;

// The sample's Newton steps (near/far sweep) stop where u is met within the square of this
// (relative to the piece's area): in float, whose output does not resolve 1e-12, often one step
// fewer than in double.
template <class T>
constexpr double kProjectedNewtonTolerance = sizeof(T) < sizeof(double) ? 1e-6 : 1e-8;

// atan2(y, x) as accurate as std::atan2 (a few ulp; tested) at a fraction of its cost: one
// division and a polynomial, inlined (the setup's independent calls overlap).  The reduction:
// atan(t) for t = min / max in [0, 1], and for t > tan(pi/8) as pi/4 + atan((t - 1) / (t + 1)),
// so that the polynomial (a least-squares fit on Chebyshev nodes, relative error 5e-18) covers
// |t| <= tan(pi/8).  Zeros, infinities and NaN go to std::atan2.
inline double ArcTan2(double y, double x) {
    const double ax = std::abs(x), ay = std::abs(y);
    const double hi = std::max(ax, ay), lo = std::min(ax, ay);
    constexpr double kMax = std::numeric_limits<double>::max();
    if (!(ax <= kMax && ay <= kMax) || hi == 0) return std::atan2(y, x);
    const bool reduce = lo > 0.41421356237309503 * hi;
    const double t = reduce ? (lo - hi) / (lo + hi) : lo / hi;  // (lo - hi: exact, Sterbenz)
    const double z = t * t, z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
    // atan(t) = t + t z P(z); P by Estrin's scheme.
    const double p01 = -0.3333333333333333027191 + 0.1999999999999565057718 * z;
    const double p23 = -0.1428571428469138061655 + 0.1111111101710032663754 * z;
    const double p45 = -0.09090904647695679521896 + 0.07692184699371777284229 * z;
    const double p67 = -0.06664531369805008849621 + 0.05858311810501153038721 * z;
    const double p89 = -0.05086254885823143129445 + 0.03925369632061856296117 * z;
    const double p = (p01 + p23 * z2) + (p45 + p67 * z2) * z4 + (p89 - 0.01920252926841228137928 * z2) * z8;
    // pi/4, pi/2 and pi as a double and the rest.
    constexpr double kPi4 = 0.78539816339744828, kPi4Low = 3.061616997868383e-17;
    double r = reduce ? kPi4 + (t + (t * z * p + kPi4Low)) : t + t * z * p;
    if (ay > ax) r = (2 * kPi4 - r) + 2 * kPi4Low;
    if (x < 0) r = (4 * kPi4 - r) + 4 * kPi4Low;
    return std::copysign(r, y);
}

// A great-circle arc directed so that it sweeps counter-clockwise about n (shading frame).
struct ProjectedArc {
    Vec3d a;                // start (unit)
    Vec3d t;                // unit tangent at a, g x a
    Vec3d g;                // unit normal of its great circle (either sign: only g's line is used)
    double arc_length = 0;  // gamma above (not the paper's gamma_i, the rectangle's angles)
    double sweep_rate = 0;  // |g_z| / 2, k above (area per unit arc angle)
};

// Point of the arc at arc angle s.
inline Vec3d ArcPoint(const ProjectedArc& arc, double s) { return arc.a * std::cos(s) + arc.t * std::sin(s); }

// Arc angle at which the arc reaches the azimuth of the (tangent-plane) direction (px, py):
// w(s) . m = 0 with m = (-py, px, 0) perpendicular to it, clamped to the arc.
inline double ArcAngleAtAzimuth(const ProjectedArc& arc, double px, double py) {
    const double am = -arc.a.x * py + arc.a.y * px, tm = -arc.t.x * py + arc.t.y * px;
    return ClampNaN(ArcTan2(-am, tm), 0, arc.arc_length);
}

// z^2 of the arc's great circle at the azimuth of (px, py), without a transcendental call: the
// point (rho p / |p|, z) with rho^2 + z^2 = 1 lies on it where g_xy . p rho / |p| + g_z z = 0.
// (Where the arc covers that azimuth above the horizon, that is the arc's point there.)
inline double ArcZ2AtAzimuth(const ProjectedArc& arc, double px, double py) {
    const double gp = arc.g.x * px + arc.g.y * py, q = gp * gp;
    const double den = q + arc.g.z * arc.g.z * (px * px + py * py);
    return den > 0 ? q / den : 1;
}

// One piece of the sweep: the area between the arcs `outer` (far) and `inner` (near, absent in
// the star case) over an azimuth range, in which `outer` runs over arc angles [s0, s1] and
// `inner` starts at arc angle r0.
struct ProjectedPiece {
    int outer = 0, inner = -1;  // indices into the setup's arcs
    double s0 = 0, s1 = 0, r0 = 0;
    double cdf = 0;  // area of the pieces before this one
    double area = 0;
    // d(area)/d(t) at the two ends, t = (s - s0) / (s1 - s0) (near/far pieces): the initial guess's.
    double slope0 = 0, slope1 = 0;
    Vec3d from, to;  // unit directions (shading frame) at the range's two ends (for Invert)
};

template <class T>
struct RectangleProjectedSetup {
    RectangleSetup<T> rect;  // the plane (rect.plane); the whole `rectangle` setup where it switches
    bool valid = false;
    bool use_rectangle = false;  // the switch (see above)
    Vec3d nl{}, tl{}, bl{};      // shading frame (n, and the tangents) in the light's local frame
    double E = 0;                // projected solid angle (Lambert's formula, the accurate one)
    double swept = 0;            // total area of the pieces (the sweep's own E, for u)
    double error_estimate = 0;   // relative error estimate of the sweep
    bool star = false;           // n inside the polygon
    int num_arcs = 0, num_pieces = 0;
    ProjectedArc arcs[5]{};
    ProjectedPiece pieces[5]{};
};

// The light's polygon clipped by the horizon n . w >= 0, in the light's local frame (x along
// exh, y along eyh, z = h along az, relative to the shading point), with for each edge i
// (vertex i to i + 1) the unit normal of its great circle and its arc length, both from
// cross products with exact edge directions.  Returns the vertex count (0: below the horizon).
struct ProjectedPolygon {
    Vec3d v[5];
    Vec3d g[5];
    double arc_length[5] = {};
    int n = 0;
};

// Any convex polygon of up to 4 vertices c (relative to the shading point, in any orthonormal
// frame that nl is also expressed in), edge i running from c_i to c_(i+1) along the unit
// direction dir_i with length len_i: the exact directions keep the arcs' cross products free of
// cancellation (rectangle_ltc.h passes the light's parallelogram in the LTC's cosine space).
inline ProjectedPolygon ClipPolygonToHorizon(const Vec3d* c, const Vec3d* dir, const double* len, int count,
                                             const Vec3d& nl) {
    double z[4];
    for (int i = 0; i < count; ++i) z[i] = Dot(nl, c[i]);
    ProjectedPolygon p;
    // Sutherland-Hodgman on z >= 0; each kept vertex records which edge follows it (-1: the horizon).
    int edge_after[5];
    for (int i = 0; i < count; ++i) {
        const int j = (i + 1) % count;
        if (z[i] >= 0) {
            p.v[p.n] = c[i];
            edge_after[p.n++] = i;
        }
        if ((z[i] >= 0) != (z[j] >= 0)) {  // the edge crosses the horizon
            // Along the edge from c_i: the offset where z reaches 0 (z is linear along it).
            const double f = z[i] / (z[i] - z[j]);
            p.v[p.n] = c[i] + dir[i] * (ClampNaN(f, 0, 1) * len[i]);
            edge_after[p.n++] = z[i] >= 0 ? -1 : i;  // leaving: the horizon follows
        }
    }
    if (p.n < 3) {
        p.n = 0;
        return p;
    }
    for (int i = 0; i < p.n; ++i) {
        const Vec3d& a = p.v[i];
        const Vec3d& b = p.v[(i + 1) % p.n];
        const int e = edge_after[i];
        if (e >= 0) {
            // b - a is along the exact direction dir[e]: a x b = a x (b - a) = (a x dir) ((b - a) . dir)
            // without cancellation.
            const Vec3d g = Cross(a, dir[e]);
            const double lg = Length(g);
            p.arc_length[i] = ArcTan2(lg * std::abs(Dot(b - a, dir[e])), Dot(a, b));
            p.g[i] = g * (1 / lg);
        } else {
            const Vec3d axb = Cross(a, b);
            p.arc_length[i] = ArcTan2(Length(axb), Dot(a, b));
            p.g[i] = Dot(axb, nl) >= 0 ? nl : -nl;  // the horizon's great circle
        }
    }
    return p;
}

inline ProjectedPolygon ClipToHorizon(double x0, double y0, double wx, double wy, double h, const Vec3d& nl) {
    const Vec3d c[4] = {{x0, y0, h}, {x0 + wx, y0, h}, {x0 + wx, y0 + wy, h}, {x0, y0 + wy, h}};
    const Vec3d dir[4] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};  // exact edge directions
    const double len[4] = {wx, wy, wx, wy};
    return ClipPolygonToHorizon(c, dir, len, 4, nl);
}

// Projected solid angle E = 1/2 sum_i gamma_i g_i . n of the clipped polygon (Lambert), and the
// sum of |terms| (for error estimates).  Signed: its sign is the polygon's orientation about n.
inline double LambertSum(const ProjectedPolygon& p, const Vec3d& nl, double* abs_sum = nullptr) {
    double e = 0, a = 0;
    for (int i = 0; i < p.n; ++i) {
        const double term = 0.5 * p.arc_length[i] * Dot(p.g[i], nl);
        e += term;
        a += std::abs(term);
    }
    if (abs_sum) *abs_sum = a;
    return e;
}

namespace projected_detail {

// Cross product of the tangent-plane parts.
inline double Cross2(const Vec3d& a, const Vec3d& b) { return a.x * b.y - a.y * b.x; }

// Builds the star-case or the near/far pieces.  `w` are the unit vertices and `g` the edge
// normals in the shading frame, oriented counter-clockwise about n.
template <class T>
void BuildPieces(RectangleProjectedSetup<T>& s, const Vec3d* w, const Vec3d* g, const double* arc_length, int n) {
    s.star = true;
    for (int i = 0; i < n; ++i) s.star = s.star && g[i].z >= 0;
    auto make_arc = [&](int i, bool reversed) {
        ProjectedArc arc;
        const Vec3d gi = reversed ? -g[i] : g[i];
        const Vec3d a = reversed ? w[(i + 1) % n] : w[i];
        arc.a = a;
        arc.t = Cross(gi, a);  // unit: g and a are unit and perpendicular (to rounding)
        arc.g = gi;
        arc.arc_length = arc_length[i];
        arc.sweep_rate = 0.5 * std::abs(g[i].z);
        return arc;
    };
    double cdf = 0;
    if (s.star) {
        for (int i = 0; i < n; ++i) {
            if (!(g[i].z > 0) || !(arc_length[i] > 0)) continue;
            const int ai = s.num_arcs++;
            s.arcs[ai] = make_arc(i, false);
            ProjectedPiece& pc = s.pieces[s.num_pieces++];
            pc.outer = ai;
            pc.s0 = 0;
            pc.s1 = arc_length[i];
            pc.area = s.arcs[ai].sweep_rate * arc_length[i];
            pc.cdf = cdf;
            pc.from = w[i];
            pc.to = w[(i + 1) % n];
            cdf += pc.area;
        }
        s.swept = cdf;
        return;
    }
    // Far arcs (g_z > 0) in polygon order run counter-clockwise; near arcs (g_z < 0), reversed
    // and taken in reverse polygon order, too.  Both chains start at the vertex of least
    // azimuth and end at the one of greatest.  (Arcs with g_z = 0 lie on a meridian: no area.)
    int far_idx[5], near_idx[5], nf = 0, nn = 0;
    int start = -1;  // first far edge: its predecessor is not far
    for (int i = 0; i < n; ++i)
        if (g[i].z > 0 && !(g[(i + n - 1) % n].z > 0)) start = i;
    if (start < 0) return;
    for (int k = 0; k < n; ++k) {
        const int i = (start + k) % n;
        if (g[i].z > 0) far_idx[nf++] = i;
    }
    for (int k = n - 1; k >= 0; --k) {
        const int i = (start + k) % n;
        if (g[i].z < 0) near_idx[nn++] = i;
    }
    if (nf == 0 || nn == 0) return;
    for (int k = 0; k < nf; ++k) s.arcs[k] = make_arc(far_idx[k], false);
    for (int k = 0; k < nn; ++k) s.arcs[nf + k] = make_arc(near_idx[k], true);
    s.num_arcs = nf + nn;
    // Merge the two chains' breakpoints (the ends of their arcs, i.e. vertices) in azimuth.  At a
    // breakpoint one arc ends (its arc angle there is its length) and the next starts (0); only the
    // other chain's arc angle there takes an atan2.
    int fi = 0, ni = 0;
    Vec3d from = s.arcs[0].a;
    double s_from = 0, r_from = 0;  // the current far and near arcs' angles at `from`
    // d(area)/d(s_F) = k_F (1 - r_N^2 / r_F^2) = k_F (z_N^2 - z_F^2) / (1 - z_F^2) at a direction's
    // azimuth, with z^2 = q / den as in ArcZ2AtAzimuth (1 - z_F^2 = g_Fz^2 |p|^2 / den_F): one division.
    auto rate = [](const ProjectedArc& F, const ProjectedArc& N, const Vec3d& d) {
        const double gf = F.g.x * d.x + F.g.y * d.y, gn = N.g.x * d.x + N.g.y * d.y, p2 = d.x * d.x + d.y * d.y;
        const double qf = gf * gf, qn = gn * gn, den_f = qf + F.g.z * F.g.z * p2, den_n = qn + N.g.z * N.g.z * p2;
        const double r = F.sweep_rate * (qn * den_f - qf * den_n) / (den_n * F.g.z * F.g.z * p2);
        return r > 0 ? r : 0.0;  // (and 0 for 0 / 0)
    };
    while (fi < nf && ni < nn && s.num_pieces < 5) {
        const ProjectedArc& F = s.arcs[fi];
        const ProjectedArc& N = s.arcs[nf + ni];
        const Vec3d& fend = w[(far_idx[fi] + 1) % n];  // F's end vertex
        const Vec3d& nend = w[near_idx[ni]];           // N's end vertex (reversed: edge i's start)
        const bool last = fi == nf - 1 && ni == nn - 1;
        const double c = Cross2(fend, nend);  // > 0: the far arc ends first
        const bool far_ends = last || c >= 0;
        const Vec3d& to = far_ends ? fend : nend;
        ProjectedPiece pc;
        pc.outer = fi;
        pc.inner = nf + ni;
        pc.s0 = s_from;
        pc.r0 = r_from;
        pc.s1 = far_ends ? F.arc_length : ArcAngleAtAzimuth(F, to.x, to.y);
        const double r1 = last || !far_ends ? N.arc_length : ArcAngleAtAzimuth(N, to.x, to.y);
        pc.area = std::max(0.0, F.sweep_rate * (pc.s1 - pc.s0) - N.sweep_rate * (r1 - pc.r0));
        pc.from = from;
        pc.to = to;
        if (pc.s1 > pc.s0) {
            pc.cdf = cdf;
            cdf += pc.area;
            pc.slope0 = rate(F, N, from) * (pc.s1 - pc.s0);
            pc.slope1 = rate(F, N, to) * (pc.s1 - pc.s0);
            s.pieces[s.num_pieces++] = pc;
        }
        if (last) break;
        if (c >= 0 && fi < nf - 1)
            ++fi;
        else if (c <= 0 && ni < nn - 1)
            ++ni;
        else if (fi < nf - 1)
            ++fi;
        else
            ++ni;
        // The chain that moved on starts its next arc at `to`; the other continues.
        s_from = fi != pc.outer ? 0.0 : pc.s1;
        r_from = nf + ni != pc.inner ? 0.0 : r1;
        from = to;
    }
    s.swept = cdf;
}

// Area of piece pc swept up to the outer arc's point wf = ArcPoint(F, sf).
inline double PieceArea(const ProjectedPiece& pc, const ProjectedArc& F, const ProjectedArc& N, double sf,
                        const Vec3d& wf) {
    return F.sweep_rate * (sf - pc.s0) - N.sweep_rate * (ArcAngleAtAzimuth(N, wf.x, wf.y) - pc.r0);
}

// The area swept by a near/far piece, in t = (s_F - s0) / (s1 - s0): the cubic with the piece's
// area and end slopes (Hermite), an approximation for the initial guess.  Returns it at t minus
// alpha, and its derivative.
inline double PieceCubic(const ProjectedPiece& pc, double t, double alpha, double* derivative) {
    const double t2 = t * t, t3 = t2 * t;
    *derivative = pc.area * (6 * t - 6 * t2) + pc.slope0 * (1 - 4 * t + 3 * t2) + pc.slope1 * (3 * t2 - 2 * t);
    return pc.area * (3 * t2 - 2 * t3) + pc.slope0 * (t - 2 * t2 + t3) + pc.slope1 * (t3 - t2) - alpha;
}

// Initial guess for the t at which a near/far piece has swept alpha: the quadratic with the
// piece's area and the smaller end slope (a slope of 0 at an apex, where the two arcs meet, gives
// the area's square-root behaviour there), then one Newton step on PieceCubic.
inline double PieceGuess(const ProjectedPiece& pc, double alpha) {
    if (!(pc.area > 0)) return 0;
    const bool at_start = pc.slope0 <= pc.slope1;
    const double d = ClampNaN(at_start ? pc.slope0 : pc.slope1, 0, pc.area), c = pc.area - d;
    const double b = at_start ? alpha : pc.area - alpha;  // swept from that end
    const double den = d + std::sqrt(d * d + 4 * c * b);
    const double q = den > 0 ? 2 * b / den : 0;  // d q + c q^2 = b, without cancellation
    const double t = ClampNaN(at_start ? q : 1 - q, 0, 1);
    double dh;
    const double h = PieceCubic(pc, t, alpha, &dh);
    return dh > 0 ? ClampNaN(t - h / dh, 0, 1) : t;
}

// Rotates the unit arc point w with tangent t (d w / d s) by a small angle step (|step| <= 1e-2):
// the Taylor series of cos and sin, whose next terms are below 1e-20.
inline void RotateOnArc(Vec3d* w, Vec3d* t, double step) {
    const double s2 = step * step;
    const double c = 1 - s2 * (0.5 - s2 * (1.0 / 24 - s2 * (1.0 / 720)));
    const double sn = step * (1 - s2 * (1.0 / 6 - s2 * (1.0 / 120 - s2 * (1.0 / 5040))));
    const Vec3d w0 = *w;
    *w = w0 * c + *t * sn;
    *t = *t * c - w0 * sn;
}

// A near/far piece's outer arc angle and the arc's point there.
struct NearFarSolution {
    double sf;
    Vec3d wf;
};

// The near/far piece's outer arc angle sf at which it has swept alpha, and the arc's point wf
// there; `resolution` is the sweep's rounding in area (its error estimate times its area).
template <class T>
NearFarSolution SolveNearFar(const ProjectedPiece& pc, const ProjectedArc& F, const ProjectedArc& N, double alpha,
                             double resolution) {
    // Safeguarded Newton for the outer arc angle sf with PieceArea(sf) = alpha, from PieceGuess's
    // start.  Each step one atan2 (the inner arc's angle there), and a sincos only for large steps
    // (small ones rotate wf by RotateOnArc).  It ends where the area is met within
    // kProjectedNewtonTolerance^2 of the piece's: by the residual, or after a step whose predicted
    // residual, |area''| step^2 / 2 (area'' from the last two derivatives), is that small.
    double lo = pc.s0, hi = pc.s1;
    double sf = lo + (hi - lo) * PieceGuess(pc, alpha);
    // (Or within the sweep's own rounding, `resolution`: where the residual is rounding, e.g. at an
    // apex, where the area's derivative vanishes, steps would shrink only linearly.)
    const double tol_area = kProjectedNewtonTolerance<T> * kProjectedNewtonTolerance<T> * pc.area + resolution;
    Vec3d wf, tf;  // the outer arc's point at sf and its tangent
    auto place = [&](double s) {
        const double c = std::cos(s), sn = std::sin(s);
        wf = F.a * c + F.t * sn;
        tf = F.t * c - F.a * sn;
    };
    place(sf);
    double prev_s = 0, prev_dg = std::numeric_limits<double>::quiet_NaN();
    for (int it = 0; it < 50; ++it) {
        const double g = PieceArea(pc, F, N, sf, wf) - alpha;
        if (std::abs(g) <= tol_area) break;
        (g < 0 ? lo : hi) = sf;
        // d(area)/d(sf) = k_F (1 - r_N^2 / r_F^2) = k_F (z_N^2 - z_F^2) / r_F^2, with z_N^2 = q / den
        // as in ArcZ2AtAzimuth (one division).
        const double gp = N.g.x * wf.x + N.g.y * wf.y, q = gp * gp, rf2 = wf.x * wf.x + wf.y * wf.y;
        const double den = q + N.g.z * N.g.z * rf2;
        const double dg = F.sweep_rate * (q - wf.z * wf.z * den) / (den * rf2);
        const double step = -g / dg, next = sf + step;
        // The predicted residual |area''| step^2 / 2 against tol_area (area'' by the last two slopes).
        const bool small = 0.5 * std::abs(dg - prev_dg) * step * step <= tol_area * std::abs(sf - prev_s);
        prev_s = sf;
        prev_dg = dg;
        if (next == sf) break;  // a step below sf's resolution
        if (next > lo && next < hi) {
            sf = next;
            if (std::abs(step) <= 1e-2)
                RotateOnArc(&wf, &tf, step);
            else
                place(sf);
            if (small) break;  // converged: that was the last step
            continue;
        }
        // Out of the bracket: bisection.
        if (hi - lo <= 1e-16 * (pc.s1 - pc.s0)) break;
        sf = 0.5 * (lo + hi);
        place(sf);
    }
    return {sf, wf};
}

}  // namespace projected_detail

// The sweep (steps 3, 4) of a polygon clipped to the horizon of s.nl, in the frame that poly and
// s.nl, s.tl, s.bl share: sets s.E, the pieces and s.error_estimate.  False where E is 0 or not
// finite (then the pieces are unset).  The caller decides on the switch (error_estimate).
template <class T>
bool BuildProjectedSweep(RectangleProjectedSetup<T>& s, const ProjectedPolygon& poly) {
    double abs_sum = 0;
    const double signed_e = LambertSum(poly, s.nl, &abs_sum);
    s.E = std::abs(signed_e);
    if (!(s.E > 0) || !std::isfinite(s.E)) return false;
    // To the shading frame, oriented counter-clockwise about n.
    Vec3d w[5], g[5];
    double arc_length[5];
    const int m = poly.n;
    const bool flip = signed_e < 0;
    auto to_shading = [&](const Vec3d& v) { return Vec3d(Dot(v, s.tl), Dot(v, s.bl), Dot(v, s.nl)); };
    for (int k = 0; k < m; ++k) {
        // Reversing the polygon: vertex k is old vertex m-1-k, edge k (k -> k+1) is old edge m-2-k.
        const int vi = flip ? m - 1 - k : k, ei = flip ? (2 * m - 2 - k) % m : k;
        const Vec3d d = to_shading(poly.v[vi]);
        w[k] = d * (1 / Length(d));
        g[k] = to_shading(flip ? -poly.g[ei] : poly.g[ei]);
        arc_length[k] = poly.arc_length[ei];
    }
    projected_detail::BuildPieces(s, w, g, arc_length, m);
    // The sweep's error against E: ~eps in each arc angle (unit vectors in the shading frame) times
    // its sweep_rate, plus each rate's own rounding (that of the dot product g . n, eps times the sum
    // of its terms' magnitudes) times the arc's length, plus the rounding of Lambert's sum.
    constexpr double eps = std::numeric_limits<double>::epsilon();
    double err = abs_sum;
    for (int k = 0; k < m; ++k) {
        const Vec3d& gk = poly.g[k];
        const double dot_terms = std::abs(gk.x * s.nl.x) + std::abs(gk.y * s.nl.y) + std::abs(gk.z * s.nl.z);
        err += 0.5 * std::abs(Dot(gk, s.nl)) + poly.arc_length[k] * dot_terms;
    }
    s.error_estimate = 8 * eps * err / s.E;
    return true;
}

template <class T>
RectangleProjectedSetup<T> MakeRectangleProjectedSetup(const Vec3<T>& origin, const Vec3<T>& normal,
                                                       const RectLightFrame<T>& frame) {
    // The plane alone (built in place); the `rectangle` setup is built only where the setup
    // switches to it.
    RectangleProjectedSetup<T> s{{MakeLocalRect(origin, frame)}};
    const LocalRect<T>& p = s.rect.plane;
    if (!p.valid) return s;
    // (Every path returns `s` itself, so that it is built in place: the setup is large.)
    auto switch_to_rectangle = [&] {
        s.rect = MakeRectangleSetup(origin, frame);
        s.use_rectangle = true;
        s.valid = s.rect.valid;
    };
    const Vec3d n(normal);
    const double ln = Length(n);
    if (!(ln > 0) || !std::isfinite(ln)) {  // no usable normal
        switch_to_rectangle();
        return s;
    }
    s.nl = Vec3d(Dot(n, p.exh), Dot(n, p.eyh), Dot(n, p.az)) / ln;
    BranchlessTangents(s.nl, s.tl, s.bl);
    const ProjectedPolygon poly = ClipToHorizon(p.x0, p.y0, p.wx, p.wy, p.h, s.nl);
    if (poly.n == 0) return s;  // below the horizon: invalid
    if (!BuildProjectedSweep(s, poly)) return s;
    if (!(s.error_estimate <= kProjectedMaxError) || !(s.swept > 0) || s.num_pieces == 0)
        switch_to_rectangle();
    else
        s.valid = true;
    return s;
}

template <class T>
RectangleProjectedSetup<T> MakeRectangleProjectedSetup(const Vec3<T>& origin, const Vec3<T>& normal,
                                                       const RectLight<T>& light) {
    return MakeRectangleProjectedSetup(origin, normal, MakeRectLightFrame(light));
}

// Solid-angle pdf at the local in-plane point (X, Y): cos / E, and 0 where cos < kProjectedMinCos.
// Points that close to the horizon carry no resolvable cosine (the direction's own rounding is
// larger), so such a sample is returned invalid rather than with a ratio of rounding noise; the
// samples dropped so have probability ~kProjectedMinCos^2 (the density is proportional to cos on
// a band of width ~cos), a bias far below any test's resolution.
constexpr double kProjectedMinCos = 1e-7;

// (dist: |(X, Y, h)| where the caller has it.)
template <class T>
T RectangleProjectedPDFLocal(const RectangleProjectedSetup<T>& s, double X, double Y, double dist = 0) {
    const Vec3d v(X, Y, s.rect.plane.h);
    const double c = Dot(v, s.nl) / (dist > 0 ? dist : Length(v));
    const T pdf = T(c / s.E);
    return c >= kProjectedMinCos && std::isfinite(pdf) ? pdf : T(0);
}

// The map (u, v) -> unit direction in the shading frame (valid setups without the switch).
template <class T>
Vec3d RectangleProjectedDirection(const RectangleProjectedSetup<T>& s, double u, double v) {
    using namespace projected_detail;
    const double target = ClampNaN(u, 0, 1) * s.swept;
    int j = 0;
    while (j + 1 < s.num_pieces && s.pieces[j + 1].cdf <= target) ++j;
    const ProjectedPiece& pc = s.pieces[j];
    const ProjectedArc& F = s.arcs[pc.outer];
    const double alpha = ClampNaN(target - pc.cdf, 0, pc.area);
    v = ClampNaN(v, 0, 1);
    if (pc.inner < 0) {  // star: the arc angle is linear in the area, r = sqrt(v) r_F
        const double sf = pc.area > 0 ? ClampNaN(pc.s0 + (pc.s1 - pc.s0) * (alpha / pc.area), pc.s0, pc.s1) : pc.s0;
        const Vec3d wf = ArcPoint(F, sf);
        const double q = std::sqrt(v);
        // z^2 = 1 - v r_F^2 = (1 - v) + v z_F^2.
        return Vec3d(wf.x * q, wf.y * q, std::sqrt((1 - v) + v * wf.z * wf.z));
    }
    const ProjectedArc& N = s.arcs[pc.inner];
    const Vec3d wf = SolveNearFar<T>(pc, F, N, alpha, s.error_estimate * s.swept).wf;
    const double zn2 = ArcZ2AtAzimuth(N, wf.x, wf.y);
    // r^2 linear in v between the arcs: z^2 = z_N^2 - v (z_N^2 - z_F^2).
    const double zf2 = wf.z * wf.z;
    const double z2 = std::max(0.0, zn2 - v * (zn2 - zf2));
    const double rf = std::sqrt(wf.x * wf.x + wf.y * wf.y), r = std::sqrt(std::max(0.0, 1 - z2));
    const double q = rf > 0 ? r / rf : 0;
    return Vec3d(wf.x * q, wf.y * q, std::sqrt(z2));
}

template <class T>
LightSample<T> SampleRectangleProjectedAt(const RectangleProjectedSetup<T>& s, double u, double v) {
    if (!s.valid) return {};
    if (s.use_rectangle) return SampleRectangleAt(s.rect, u, v);
    const LocalRect<T>& p = s.rect.plane;
    const Vec3d d = RectangleProjectedDirection(s, u, v);
    const Vec3d dl = s.tl * d.x + s.bl * d.y + s.nl * d.z;  // to the light's local frame
    // The ray from o meets the plane z = h at dl * (h / dl.z).
    const double f = p.h / dl.z;
    double X = dl.x * f, Y = dl.y * f;
    ClampLocalToLight(p, X, Y);
    const double dist = Length(Vec3d(X, Y, p.h));
    return LightSampleFromLocal(p, X, Y, RectangleProjectedPDFLocal(s, X, Y, dist), dist);
}

template <class T>
LightSample<T> SampleRectangleProjected(const RectangleProjectedSetup<T>& s, Point2<T> uv) {
    return SampleRectangleProjectedAt(s, double(uv.u), double(uv.v));
}

// Solid-angle pdf of choosing p (a point on the light): cos / E, or the switch's.
template <class T>
T RectangleProjectedPDF(const RectangleProjectedSetup<T>& s, const Vec3<T>& p) {
    if (!s.valid) return 0;
    if (s.use_rectangle) return RectanglePDF(s.rect, p);
    const Point2<double> e = EdgeOffsets(s.rect.plane, p);
    double X = s.rect.plane.x0 + e.u, Y = s.rect.plane.y0 + e.v;
    ClampLocalToLight(s.rect.plane, X, Y);
    return RectangleProjectedPDFLocal(s, X, Y);
}

// The inverse map: point on the light -> (u, v) in [0,1]^2 (points below the horizon: (0, 0)).
template <class T>
Point2<double> InvertRectangleProjected(const RectangleProjectedSetup<T>& s, const Vec3<T>& point) {
    using namespace projected_detail;
    if (!s.valid) return {};
    if (s.use_rectangle) return InvertRectangle(s.rect, point);
    const LocalRect<T>& p = s.rect.plane;
    const Point2<double> e = EdgeOffsets(p, point);
    const Vec3d vl(p.x0 + e.u, p.y0 + e.v, p.h);
    const Vec3d d = Normalize(Vec3d(Dot(vl, s.tl), Dot(vl, s.bl), Dot(vl, s.nl)));
    if (!(d.z > 0)) return {};
    // The piece whose azimuth range holds d (the best-inside one, against rounding).
    int best = 0;
    double best_margin = -std::numeric_limits<double>::infinity();
    for (int j = 0; j < s.num_pieces; ++j) {
        const ProjectedPiece& pc = s.pieces[j];
        const double margin = std::min(Cross2(pc.from, d) / Length(Vec3d(pc.from.x, pc.from.y, 0)),
                                       Cross2(d, pc.to) / Length(Vec3d(pc.to.x, pc.to.y, 0)));
        if (margin > best_margin) {
            best_margin = margin;
            best = j;
        }
    }
    const ProjectedPiece& pc = s.pieces[best];
    const ProjectedArc& F = s.arcs[pc.outer];
    const double sf = ClampNaN(ArcAngleAtAzimuth(F, d.x, d.y), pc.s0, pc.s1);
    const Vec3d wf = ArcPoint(F, sf);
    double area, v;
    const double dz2 = d.z * d.z;
    if (pc.inner < 0) {
        area = F.sweep_rate * (sf - pc.s0);
        v = (d.x * d.x + d.y * d.y) / (wf.x * wf.x + wf.y * wf.y);
    } else {
        const ProjectedArc& N = s.arcs[pc.inner];
        area = PieceArea(pc, F, N, sf, wf);
        const double zn2 = ArcZ2AtAzimuth(N, wf.x, wf.y), zf2 = wf.z * wf.z;
        v = (zn2 - dz2) / (zn2 - zf2);
    }
    const double u = (pc.cdf + ClampNaN(area, 0, pc.area)) / s.swept;
    return {ClampNaN(u, 0, 1), ClampNaN(v, 0, 1)};
}

// Projected solid angle of the light seen from `origin` with normal `normal` (the part above
// the horizon), in double: the irradiance of a unit-radiance light.  0 where invalid.
template <class T>
double RectangleProjectedSolidAngle(const Vec3<T>& origin, const Vec3<T>& normal, const RectLight<T>& light) {
    const LocalRect<T> p = MakeLocalRect(origin, light);
    const Vec3d n(normal);
    const double ln = Length(n);
    if (!p.valid || !(ln > 0) || !std::isfinite(ln)) return 0;
    const Vec3d nl = Vec3d(Dot(n, p.exh), Dot(n, p.eyh), Dot(n, p.az)) / ln;
    const ProjectedPolygon poly = ClipToHorizon(p.x0, p.y0, p.wx, p.wy, p.h, nl);
    return poly.n ? std::abs(LambertSum(poly, nl)) : 0.0;
}

}  // namespace sphrect
