// Technique `rectangle_ltc`'s glossy part (its mixture with rectangle_projected: technique.h): points on the light with
// density proportional to a linearly transformed cosine (LTC; Heitz, Dupuy, Hill, Neubelt 2016) fitted to the isotropic
// GGX lobe at (alpha, wo), after C. Peters, "BRDF Importance Sampling for Polygonal Lights" (ACM TOG 40(4), SIGGRAPH
// 2021).  In short (docs/rectangle_ltc.md):
//
//  1. In the shading frame with wo in the x-z plane, the LTC is D(w) = D_o(w_o) |det M^-1| / |M^-1 w|^3 with
//     w_o = M^-1 w / |M^-1 w| and a clamped cosine D_o.  M = [[a, 0, b], [0, c, 0], [d, 0, 1]] comes from
//     the table scripts/fit_ltc.py fitted (ltc_ggx_table.h), interpolated bilinearly.
//  2. M^-1 maps the light's rectangle to a parallelogram (a linear map keeps planes and convexity).  It is
//     clipped by the cosine space's horizon and sampled uniformly in projected solid angle there, by the
//     sweep of rectangle_projected.h (ClipPolygonToHorizon, BuildProjectedSweep, RectangleProjectedDirection):
//     directions w_o with density max(0, w_o.z) / E_o, E_o the parallelogram's projected solid angle.
//  3. w = M w_o / |M w_o| is intersected with the light's plane.  Its solid-angle density is
//     pdf(w) = max(0, w_o.z) |det M^-1| / (E_o |M^-1 w|^3), evaluated at the returned point.
//
// The density's support is the LTC's (w_o.z > 0 in cosine space), not the BRDF's (w.z > 0): where the fitted
// LTC leaves part of the lobe out, a renderer needs another technique in MIS for it.
//
// Fallbacks to `rectangle_projected` (RectangleProjectedSetup, which may itself switch to `rectangle`): no
// usable normal or wo, wo on or below the horizon, alpha not positive and finite, a singular interpolated M, a
// light wholly outside the LTC's support (E_o = 0) and a sweep that cannot be resolved in cosine space (its
// error estimate beyond kProjectedMaxError: the light's projected solid angle there is tiny -- a far or thin
// light, over which the density is nearly uniform, or one away from a glossy lobe, near the cosine space's
// horizon, where the lobe contributes little).  The setup records which (LtcFallback).  A light wholly below
// the shading horizon (where the BRDF vanishes) is invalid, as for `rectangle_projected`.
#pragma once

#include <algorithm>
#include <cmath>

#include "ltc_ggx_table.h"
#include "rectangle_projected.h"

namespace sphrect {

// The glossy lobe a `rectangle_ltc` sampler follows at its shading point (technique.h): wo towards the viewer (the
// space of the origin and normal, any length), the GGX alpha, and the weights of the lobe and of the rest of the
// BSDF (any common scale).  weight 0: no lobe.
template <class T>
struct GlossyLobe {
    Vec3<T> wo{};
    T alpha = 0;
    T weight = 0;
    T rest_weight = 0;
};

// M = [[a, 0, b], [0, c, 0], [d, 0, 1]] in the frame with wo = (sin theta, 0, cos theta).
struct LtcMatrix {
    double a = 1, b = 0, c = 1, d = 0;
};

// The table's grid coordinates of (alpha, cos theta) in [0, kLtcGgxSize - 1]: sqrt(alpha) and
// sqrt(1 - cos theta) scaled, with the first alpha cell stretched over [kLtcGgxAlphaMin, alpha_1].
inline double LtcGgxAlphaCoordinate(double alpha) {
    const double n1 = kLtcGgxSize - 1, root_min = std::sqrt(kLtcGgxAlphaMin) * n1;
    const double x = std::sqrt(ClampNaN(alpha, kLtcGgxAlphaMin, 1)) * n1;
    return x < 1 ? (x - root_min) / (1 - root_min) : std::min(x, n1);
}
inline double LtcGgxCosCoordinate(double cos_theta) {
    const double n1 = kLtcGgxSize - 1;
    return std::min(std::sqrt(1 - ClampNaN(cos_theta, kLtcGgxCosMin, 1)) * n1, n1);
}

// The table cell of (alpha, cos theta) and the point's place in it, for bilinear interpolation.
struct LtcGgxCell {
    int i, j;       // the cell's first corner
    double fx, fy;  // in [0, 1] across it
    // The bilinear interpolation of one field of the table's entries.
    double Interpolate(double LtcGgxEntry::*field) const {
        auto at = [&](int di, int dj) { return kLtcGgxTable[(i + di) * kLtcGgxSize + j + dj].*field; };
        return (1 - fx) * ((1 - fy) * at(0, 0) + fy * at(0, 1)) + fx * ((1 - fy) * at(1, 0) + fy * at(1, 1));
    }
};

inline LtcGgxCell LtcGgxCellAt(double alpha, double cos_theta) {
    const double x = LtcGgxAlphaCoordinate(alpha), y = LtcGgxCosCoordinate(cos_theta);
    const int i = std::min(int(x), kLtcGgxSize - 2), j = std::min(int(y), kLtcGgxSize - 2);
    return {i, j, x - i, y - j};
}

// Bilinear interpolation of M's entries.  (Of M rather than of M^-1: a and c grow like alpha, so they are
// nearly linear in the grid's sqrt(alpha) coordinate, where M^-1's 1 / alpha would not be; M^-1 is then
// exact for the interpolated M, so sampling and pdf agree whatever the interpolation's error.)
inline LtcMatrix LookupLtcGgx(double alpha, double cos_theta) {
    const LtcGgxCell cell = LtcGgxCellAt(alpha, cos_theta);
    return {cell.Interpolate(&LtcGgxEntry::a), cell.Interpolate(&LtcGgxEntry::b), cell.Interpolate(&LtcGgxEntry::c),
            cell.Interpolate(&LtcGgxEntry::d)};
}

// The lobe's albedo (the table's second quantity), interpolated the same way.
inline double LookupLtcGgxAlbedo(double alpha, double cos_theta) {
    return LtcGgxCellAt(alpha, cos_theta).Interpolate(&LtcGgxEntry::albedo);
}

// M^-1 and |det M^-1| (the 2 x 2 block of x and z, and y alone).  `valid` false where M is singular.
struct LtcInverse {
    double ia = 1, ib = 0, ic = 1, id = 0, iz = 1;  // M^-1 = [[ia, 0, ib], [0, ic, 0], [id, 0, iz]]
    double det = 1;
    bool valid = false;
};

inline LtcInverse InvertLtc(const LtcMatrix& m) {
    LtcInverse r;
    const double det_xz = m.a - m.b * m.d;
    r.ia = 1 / det_xz;
    r.ib = -m.b / det_xz;
    r.id = -m.d / det_xz;
    r.iz = m.a / det_xz;
    r.ic = 1 / m.c;
    r.det = std::abs(r.ic / det_xz);
    r.valid = std::isfinite(r.ia) && std::isfinite(r.ib) && std::isfinite(r.id) && std::isfinite(r.iz) &&
              std::isfinite(r.ic) && r.det > 0 && std::isfinite(r.det);
    return r;
}

inline Vec3d ApplyLtc(const LtcMatrix& m, const Vec3d& v) {
    return {m.a * v.x + m.b * v.z, m.c * v.y, m.d * v.x + v.z};
}
inline Vec3d ApplyLtcInverse(const LtcInverse& r, const Vec3d& v) {
    return {r.ia * v.x + r.ib * v.z, r.ic * v.y, r.id * v.x + r.iz * v.z};
}

// Why a setup fell back to `rectangle_projected` (for tests and statistics).
enum class LtcFallback { kNone, kNoShadingInput, kWoBelowHorizon, kSingularMatrix, kOutsideSupport, kUnresolved };

template <class T>
struct RectangleLtcSetup {
    // Without the fallback: the sweep in cosine space (its nl, tl, bl: the cosine space's axes in the frame of
    // the light's parallelogram there) with the light's plane in proj.rect.plane.  With it: the `rectangle_projected`
    // setup itself.
    RectangleProjectedSetup<T> proj;
    bool valid = false;
    bool use_projected = false;  // the fallback (see above)
    LtcFallback fallback = LtcFallback::kNone;
    Vec3d nl{}, tl{}, bl{};  // shading frame in the light's local frame; tl along wo's tangential part
    LtcMatrix m;
    LtcInverse inv;
    double E = 0;  // projected solid angle of the light's parallelogram in cosine space (E_o)
};

// The LTC density of w (in the shading frame, any length): max(0, w_o.z) |det M^-1| / (pi |M^-1 w|^3), the
// unclipped lobe's (it integrates to 1 over the sphere).  Scale-free form of the same expression.
inline double LtcDensity(const LtcInverse& inv, const Vec3d& w) {
    const Vec3d u = ApplyLtcInverse(inv, w);
    const double lw2 = Dot(w, w), lu2 = Dot(u, u);
    return u.z > 0 ? u.z * lw2 * std::sqrt(lw2) * inv.det / (M_PI * lu2 * lu2) : 0.0;
}

// build_fallback false: a fallback only records its reason (use_projected set, valid false), for a caller that holds
// rectangle_projected's setup already (the technique's mixture, technique.h).
template <class T>
RectangleLtcSetup<T> MakeRectangleLtcSetup(const Vec3<T>& origin, const Vec3<T>& normal, const Vec3<T>& wo, T alpha,
                                           const RectLightFrame<T>& frame, bool build_fallback = true) {
    RectangleLtcSetup<T> s;
    s.proj.rect.plane = MakeLocalRect(origin, frame);
    const LocalRect<T>& p = s.proj.rect.plane;
    if (!p.valid) return s;
    auto fall_back = [&](LtcFallback why) {
        s.fallback = why;
        s.use_projected = true;
        if (!build_fallback) return;
        s.proj = MakeRectangleProjectedSetup(origin, normal, frame);
        s.valid = s.proj.valid;
    };
    const Vec3d n(normal), v(wo);
    const double ln = Length(n), lv = Length(v);
    if (!(ln > 0) || !std::isfinite(ln) || !(lv > 0) || !std::isfinite(lv) || !(alpha > 0) || !std::isfinite(alpha)) {
        fall_back(LtcFallback::kNoShadingInput);
        return s;
    }
    s.nl = Vec3d(Dot(n, p.exh), Dot(n, p.eyh), Dot(n, p.az)) / ln;
    const Vec3d vl = Vec3d(Dot(v, p.exh), Dot(v, p.eyh), Dot(v, p.az)) / lv;
    const double cos_theta = Dot(vl, s.nl);
    if (!(cos_theta > 0)) {  // wo on or below the horizon
        fall_back(LtcFallback::kWoBelowHorizon);
        return s;
    }
    // tl: wo's part along the tangent plane; at normal incidence (none) any tangent does (the LTC is then
    // rotationally symmetric, b = d = 0 to the fit's accuracy).
    const Vec3d tangential = vl - s.nl * cos_theta;
    const double lt = Length(tangential);
    if (lt > 1e-12) {
        s.tl = tangential / lt;
        s.bl = Normalize(Cross(s.nl, s.tl));
    } else {
        BranchlessTangents(s.nl, s.tl, s.bl);
    }
    // The light's corners relative to o in the shading frame; a light wholly below the horizon is invalid.
    auto to_shading = [&](const Vec3d& q) { return Vec3d(Dot(q, s.tl), Dot(q, s.bl), Dot(q, s.nl)); };
    const Vec3d c0 = to_shading(Vec3d(p.x0, p.y0, p.h));
    const Vec3d ex = to_shading(Vec3d(1, 0, 0)), ey = to_shading(Vec3d(0, 1, 0));
    {
        const double z0 = c0.z, zx = ex.z * p.wx, zy = ey.z * p.wy;
        if (!(z0 > 0 || z0 + zx > 0 || z0 + zx + zy > 0 || z0 + zy > 0)) return s;
    }
    s.m = LookupLtcGgx(double(alpha), cos_theta);
    s.inv = InvertLtc(s.m);
    if (!s.inv.valid) {
        fall_back(LtcFallback::kSingularMatrix);
        return s;
    }
    // The parallelogram in cosine space, in an orthonormal frame (U, V, W) of its own plane (U along the first
    // edge, W normal to the plane), as rectangle_projected.h keeps the rectangle in the light's local frame:
    // every vertex's W coordinate is then h times one number, and the distance of the plane from o keeps its
    // relative accuracy when o is nearly in it (in cosine-space coordinates the vertices' rounding, eps
    // |vertex|, would be that distance's when it is 1e-9 of the light's size).  The edges run along the exact
    // directions (1, 0, 0) and (cos, sin, 0).  The cosine space's axes are expressed in (U, V, W) instead.
    const Vec3d tx = ApplyLtcInverse(s.inv, ex), ty = ApplyLtcInverse(s.inv, ey);
    const Vec3d tz = ApplyLtcInverse(s.inv, to_shading(Vec3d(0, 0, 1)));
    const double ltx = Length(tx);
    const Vec3d U = tx / ltx, W = Normalize(Cross(tx, ty)), V = Cross(W, U);
    const double ty_u = Dot(ty, U), ty_v = Dot(ty, V), lty = std::sqrt(ty_u * ty_u + ty_v * ty_v);
    Vec3d c[4];
    const Vec3d dir[4] = {{1, 0, 0}, {ty_u / lty, ty_v / lty, 0}, {-1, 0, 0}, {-ty_u / lty, -ty_v / lty, 0}};
    const double len[4] = {ltx * p.wx, lty * p.wy, ltx * p.wx, lty * p.wy};
    c[0] = Vec3d(p.x0 * ltx + p.y0 * ty_u + p.h * Dot(tz, U), p.y0 * ty_v + p.h * Dot(tz, V), p.h * Dot(tz, W));
    c[1] = c[0] + dir[0] * len[0];
    c[2] = c[1] + dir[1] * len[1];
    c[3] = c[0] + dir[1] * len[1];
    RectangleProjectedSetup<T>& sweep = s.proj;
    sweep.nl = Vec3d(U.z, V.z, W.z);
    sweep.tl = Vec3d(U.x, V.x, W.x);
    sweep.bl = Vec3d(U.y, V.y, W.y);
    const ProjectedPolygon poly = ClipPolygonToHorizon(c, dir, len, 4, sweep.nl);
    if (poly.n == 0 || !BuildProjectedSweep(sweep, poly)) {
        fall_back(LtcFallback::kOutsideSupport);
        return s;
    }
    if (!(sweep.error_estimate <= kProjectedMaxError) || !(sweep.swept > 0) || sweep.num_pieces == 0) {
        fall_back(LtcFallback::kUnresolved);
        return s;
    }
    sweep.valid = true;
    s.E = sweep.E;
    s.valid = true;
    return s;
}

template <class T>
RectangleLtcSetup<T> MakeRectangleLtcSetup(const Vec3<T>& origin, const Vec3<T>& normal, const Vec3<T>& wo, T alpha,
                                           const RectLight<T>& light) {
    return MakeRectangleLtcSetup(origin, normal, wo, alpha, MakeRectLightFrame(light));
}

// Solid-angle pdf at the local in-plane point (X, Y) (without the fallback): max(0, w_o.z) |det M^-1| /
// (E_o |M^-1 w|^3), 0 where w_o.z < kProjectedMinCos (as rectangle_projected.h: no resolvable cosine there).
template <class T>
T RectangleLtcPDFLocal(const RectangleLtcSetup<T>& s, double X, double Y) {
    const Vec3d vl(X, Y, s.proj.rect.plane.h);
    const Vec3d w(Dot(vl, s.tl), Dot(vl, s.bl), Dot(vl, s.nl));
    const Vec3d u = ApplyLtcInverse(s.inv, w);
    const double lw2 = Dot(w, w), lu2 = Dot(u, u), lu = std::sqrt(lu2);
    if (!(u.z >= kProjectedMinCos * lu)) return T(0);
    // w_o.z / |M^-1 w / |w||^3 = (u.z / |u|) (|w| / |u|)^3.
    const T pdf = T((u.z / lu) * (lw2 * std::sqrt(lw2) / (lu2 * lu)) * s.inv.det / s.E);
    return std::isfinite(pdf) ? pdf : T(0);
}

template <class T>
LightSample<T> SampleRectangleLtcAt(const RectangleLtcSetup<T>& s, double u, double v) {
    if (!s.valid) return {};
    if (s.use_projected) return SampleRectangleProjectedAt(s.proj, u, v);
    const LocalRect<T>& p = s.proj.rect.plane;
    const Vec3d w = ApplyLtc(s.m, RectangleProjectedDirection(s.proj, u, v));  // shading frame, not unit
    const Vec3d dl = s.tl * w.x + s.bl * w.y + s.nl * w.z;                     // to the light's local frame
    const double f = p.h / dl.z;
    double X = dl.x * f, Y = dl.y * f;
    if (!(dl.z > 0)) X = Y = NAN;  // (a rounding-level miss of the plane: onto the corner, pdf 0)
    LightSample<T> ls = LightSampleFromLocal(p, X, Y, T(0));
    // The pdf at the point as returned (rounded to T): a glossy lobe's density changes by far more than the
    // point's rounding over it.
    if (dl.z > 0) ls.pdf = RectangleLtcPDF(s, ls.point);
    return ls;
}

template <class T>
LightSample<T> SampleRectangleLtc(const RectangleLtcSetup<T>& s, Point2<T> uv) {
    return SampleRectangleLtcAt(s, double(uv.u), double(uv.v));
}

// Solid-angle pdf of choosing p (a point on the light), or the fallback's.
template <class T>
T RectangleLtcPDF(const RectangleLtcSetup<T>& s, const Vec3<T>& point) {
    if (!s.valid) return 0;
    if (s.use_projected) return RectangleProjectedPDF(s.proj, point);
    const LocalRect<T>& p = s.proj.rect.plane;
    const Point2<double> e = EdgeOffsets(p, point);
    double X = p.x0 + e.u, Y = p.y0 + e.v;
    ClampLocalToLight(p, X, Y);
    return RectangleLtcPDFLocal(s, X, Y);
}

}  // namespace sphrect
