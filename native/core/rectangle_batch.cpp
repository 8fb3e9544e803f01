// The batched rectangle technique (rectangle_batch.h): rectangle.h's setup and map, lane by lane
// in Highway vectors of double.  Variable names follow rectangle.h (and through it the paper's,
// docs/rectangle_map.md); the equation numbers are that document's.
//
// Compiled once per instruction set Highway targets (foreach_target.h re-includes this file),
// the best one the machine supports chosen at run time (HWY_DYNAMIC_DISPATCH).
#include "core/rectangle_batch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/rectangle_batch.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// (foreach_target.h first, then highway.h: Highway's dispatch idiom.)
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include "core/simd_math-inl.h"

#include <algorithm>
#include <limits>

#include "core/rectangle.h"
#include "core/rectangle_cosine.h"

HWY_BEFORE_NAMESPACE();
namespace sphrect {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// DiffB of rectangle.h, eq. (15) where ya, yb have the same sign, as one quotient.
HWY_INLINE VD DiffBV(DD d, VD ya, VD yb, VD ra, VD rb, VD d2, VD dy) {
    const MD same = hn::Mul(ya, yb) > hn::Zero(d);
    const VD rab = hn::Mul(ra, rb);
    const VD num =
        hn::IfThenElse(same, hn::Mul(hn::Mul(d2, dy), hn::Add(yb, ya)), hn::Sub(hn::Mul(yb, ra), hn::Mul(ya, rb)));
    const VD den = hn::IfThenElse(same, hn::Mul(rab, hn::Add(hn::Mul(yb, ra), hn::Mul(ya, rb))), rab);
    return hn::Div(num, den);
}

// The half-angle factors of X x Y (both in one quadrant, a0 >= 0) into (re, im):
// AddQuadrantRectSolidAngle's two triangles, eq. (3)-(4).  An empty piece (w = 0) adds factor 1.
HWY_INLINE void AddQuadrantV(VD x0, VD x1, VD wx, VD y0, VD y1, VD wy, VD h, VD h2, VD& re, VD& im) {
    const VD x00 = hn::Mul(x0, x0), x11 = hn::Mul(x1, x1), y00 = hn::Mul(y0, y0), y11 = hn::Mul(y1, y1);
    const VD x01 = hn::Mul(x0, x1), y01 = hn::Mul(y0, y1);
    const VD l00 = hn::Sqrt(hn::Add(hn::Add(x00, y00), h2)), l10 = hn::Sqrt(hn::Add(hn::Add(x11, y00), h2));
    const VD l11 = hn::Sqrt(hn::Add(hn::Add(x11, y11), h2)), l01 = hn::Sqrt(hn::Add(hn::Add(x00, y11), h2));
    const VD num = hn::Mul(hn::Mul(h, wx), wy);
    const VD d_x01_y00 = hn::Add(hn::Add(x01, y00), h2), d_x01_y01 = hn::Add(hn::Add(x01, y01), h2);
    const VD den1 = hn::Add(hn::Add(hn::Mul(hn::Mul(l00, l10), l11), hn::Mul(d_x01_y00, l11)),
                            hn::Add(hn::Mul(d_x01_y01, l10), hn::Mul(hn::Add(hn::Add(x11, y01), h2), l00)));
    const VD den2 =
        hn::Add(hn::Add(hn::Mul(hn::Mul(l00, l11), l01), hn::Mul(d_x01_y01, l01)),
                hn::Add(hn::Mul(hn::Add(hn::Add(x00, y01), h2), l11), hn::Mul(hn::Add(hn::Add(x01, y11), h2), l00)));
    auto add = [&](VD t) {  // HalfAngleSum::Add
        const VD r = hn::NegMulAdd(im, t, re), i = hn::MulAdd(re, t, im);
        re = r;
        im = i;
    };
    add(hn::Div(num, den1));
    add(hn::Div(num, den2));
}

// RectSolidAngleLocal of [x0, x1] x [c0, c1] (x0 >= 0, c1 > 0): Y split at 0 into at most two
// quadrant pieces, the second empty where c0 >= 0.
HWY_INLINE VD StripSolidAngleV(DD d, VD x0, VD x1, VD wx, VD c0, VD c1, VD wc, VD h, VD h2) {
    const VD zero = hn::Zero(d);
    const MD straddles = c0 < zero;
    VD re = hn::Set(d, 1.0), im = zero;
    // Piece 1: [c0, c1] itself, or [0, -c0] (the mirrored part below 0); piece 2: [0, c1] or empty.
    const VD p1_0 = hn::IfThenZeroElse(straddles, c0), p1_1 = hn::IfThenElse(straddles, hn::Neg(c0), c1);
    const VD p1_w = hn::IfThenElse(straddles, hn::Neg(c0), wc);
    AddQuadrantV(x0, x1, wx, p1_0, p1_1, p1_w, h, h2, re, im);
    AddQuadrantV(x0, x1, wx, zero, hn::IfThenElseZero(straddles, c1), hn::IfThenElseZero(straddles, c1), h, h2, re, im);
    return hn::Mul(hn::Set(d, 2.0), Atan2NonNegative(d, hn::Max(im, zero), re));
}

// The lanes' setups (what RectangleMapLocal reads) and which lanes the vector code handles.
struct SetupV {
    VD T0, omega, neg_b0, b1, b1_plus_b0, b1_minus_b0, s0, s1, x0, x1, y0, y1, h, wy;
    MD swap, flip_x, flip_y, y_beside;
    VD px0, py0, az_sign;  // the plane: corner's in-plane coordinates, side of n the light is on
    MD vector_ok;
};

HWY_INLINE SetupV MakeSetupV(DD d, const RectLightFrame<float>& f, VD ox, VD oy, VD oz) {
    const VD zero = hn::Zero(d), one = hn::Set(d, 1.0);
    SetupV s;
    // MakeLocalRect: the light's plane around o.
    const VD dx = hn::Sub(hn::Set(d, f.corner.x), ox), dy = hn::Sub(hn::Set(d, f.corner.y), oy),
             dz = hn::Sub(hn::Set(d, f.corner.z), oz);
    auto dot = [&](const Vec3d& e) {
        return hn::Add(hn::Add(hn::Mul(dx, hn::Set(d, e.x)), hn::Mul(dy, hn::Set(d, e.y))),
                       hn::Mul(dz, hn::Set(d, e.z)));
    };
    const VD z = dot(f.n);
    s.px0 = dot(f.exh);
    s.py0 = dot(f.eyh);
    s.az_sign = hn::IfThenElse(z < zero, hn::Set(d, -1.0), one);
    const VD h = s.h = hn::Abs(z);
    const VD inf = hn::Set(d, std::numeric_limits<double>::infinity());
    MD ok = hn::And(h > zero, hn::And(hn::Abs(ox) < inf, hn::And(hn::Abs(oy) < inf, hn::Abs(oz) < inf)));
    if (!f.light.two_sided) ok = hn::And(ok, z < zero);
    const VD wx = hn::Set(d, f.wx), wy = hn::Set(d, f.wy);
    // The frame (13).
    const VD X0 = s.px0, X1 = hn::Add(s.px0, wx), Y0 = s.py0, Y1 = hn::Add(s.py0, wy);
    const VD gap_y = hn::Max(hn::Max(zero, Y0), hn::Neg(Y1)), gap_x = hn::Max(hn::Max(zero, X0), hn::Neg(X1));
    s.swap = hn::Mul(gap_y, wx) < hn::Mul(gap_x, wy);
    VD a0 = hn::IfThenElse(s.swap, Y0, X0), a1 = hn::IfThenElse(s.swap, Y1, X1);
    VD c0 = hn::IfThenElse(s.swap, X0, Y0), c1 = hn::IfThenElse(s.swap, X1, Y1);
    s.flip_x = a1 < zero;
    s.flip_y = c1 < zero;
    const VD na0 = hn::Neg(a0), nc0 = hn::Neg(c0);
    a0 = hn::IfThenElse(s.flip_x, hn::Neg(a1), a0);
    a1 = hn::IfThenElse(s.flip_x, na0, a1);
    c0 = hn::IfThenElse(s.flip_y, hn::Neg(c1), c0);
    c1 = hn::IfThenElse(s.flip_y, nc0, c1);
    s.x0 = a0;
    s.x1 = a1;
    s.y0 = c0;
    s.y1 = c1;
    const VD wa = hn::IfThenElse(s.swap, wy, wx), wc = s.wy = hn::IfThenElse(s.swap, wx, wy);
    const VD h2 = hn::Mul(h, h);
    // Omega (6) and T0 (9) from two strips: a0 < 0: P = [0, -a0], Q = [0, a1], Omega = P + Q, T0 = -P;
    // otherwise P = [0, a0], Q = [a0, a1], Omega = Q, T0 = P.
    const MD foot_in = a0 < zero;
    const VD p1 = hn::Abs(a0);
    const VD P = StripSolidAngleV(d, zero, p1, p1, c0, c1, wc, h, h2);
    const VD q0 = hn::IfThenZeroElse(foot_in, a0), qw = hn::IfThenElse(foot_in, a1, wa);
    const VD Q = StripSolidAngleV(d, q0, a1, qw, c0, c1, wc, h, h2);
    s.omega = hn::IfThenElse(foot_in, hn::Add(P, Q), Q);
    s.T0 = hn::IfThenElse(foot_in, hn::Neg(P), P);
    // (1 / Omega must be a finite float, as the scalar setup requires: lanes near that limit take it.)
    ok = hn::And(ok, s.omega > hn::Set(d, 1e-38));

    const VD rc0 = hn::Sqrt(hn::MulAdd(c0, c0, h2)), rc1 = hn::Sqrt(hn::MulAdd(c1, c1, h2));
    const VD ra0 = hn::Sqrt(hn::MulAdd(a0, a0, h2)), ra1 = hn::Sqrt(hn::MulAdd(a1, a1, h2));
    s.neg_b0 = hn::Div(c0, rc0);
    s.b1 = hn::Div(c1, rc1);
    s.b1_plus_b0 = DiffBV(d, c0, c1, rc0, rc1, h2, wc);
    s.b1_minus_b0 =
        hn::IfThenElse(c0 < zero, DiffBV(d, hn::Neg(c0), c1, rc0, rc1, h2, hn::Add(c1, c0)), hn::Add(s.b1, s.neg_b0));
    s.s0 = hn::Div(a0, ra0);
    s.s1 = hn::Div(a1, ra1);
    s.y_beside = c0 > zero;

    // The error estimate (19) with its x-part bounded: |F'(s) s| <= b1 / sqrt(1 - b1^2) + |b0| / sqrt(1 - b0^2)
    // = (|y0| + y1) / h, since each q_i >= sqrt(1 - b_i^2) and |s| <= 1.  A lane whose bound calls for the polish
    // takes the scalar path, which decides on the estimate itself (such lanes are nearly in the light's plane).
    const VD eps = hn::Set(d, std::numeric_limits<double>::epsilon());
    const VD slope_bound = hn::Div(hn::Add(hn::Abs(c0), c1), h);
    const VD ex = hn::Div(hn::Mul(eps, hn::Add(hn::Add(hn::Abs(s.T0), s.omega), slope_bound)), s.omega);
    const VD dmax = hn::Max(ra0, ra1), dmax2 = hn::Mul(dmax, dmax);
    const VD r0 = hn::Sqrt(hn::MulAdd(c0, c0, dmax2)), r1 = hn::Sqrt(hn::MulAdd(c1, c1, dmax2));
    const VD one_minus_b = hn::Div(dmax2, hn::Mul(r0, hn::Add(r0, c0)));  // OneMinusB(c0, r0, dmax2)
    const VD ey = hn::IfThenElse(s.y_beside, hn::Div(hn::Mul(eps, one_minus_b), DiffBV(d, c0, c1, r0, r1, dmax2, wc)),
                                 hn::Mul(hn::Set(d, 2.0), eps));
    // The vector lanes: neither the polish nor the fallback (with a margin of 2 on the estimate).
    ok = hn::And(ok, hn::Mul(hn::Set(d, 2.0), ex) <= hn::Set(d, kRectanglePolishAbove));
    ok = hn::And(ok, hn::Mul(hn::Set(d, 2.0), hn::Add(ex, ey)) <= hn::Set(d, kRectangleMaxError));
    s.vector_ok = ok;
    return s;
}

// RectangleMapLocal without the polish, then RectangleToEdgeFrame: the in-plane coordinates (X, Y)
// along the light's edges and the distance |(X, Y, h)|.
HWY_INLINE void MapV(DD d, const SetupV& s, VD u, VD v, VD& X, VD& Y, VD& dist) {
    const VD zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
    const VD Tu = hn::MulAdd(u, s.omega, s.T0);
    const VD sT = hn::Sin(d, Tu), cT = hn::Cos(d, Tu);
    const VD sT2 = hn::Mul(sT, sT);
    const VD omc = hn::IfThenElse(cT > zero, hn::Div(sT2, hn::Add(one, cT)), hn::Sub(one, cT));
    const VD opc = hn::IfThenElse(cT < zero, hn::Div(sT2, hn::Sub(one, cT)), hn::Add(one, cT));
    const VD two_b0b1 = hn::Mul(two, hn::Mul(s.neg_b0, s.b1));
    const VD R2 = hn::IfThenElse(s.neg_b0 >= zero, hn::MulAdd(two_b0b1, omc, hn::Mul(s.b1_plus_b0, s.b1_plus_b0)),
                                 hn::NegMulAdd(two_b0b1, opc, hn::Mul(s.b1_minus_b0, s.b1_minus_b0)));
    const VD sn = ClampNaNV(hn::Div(sT, hn::Sqrt(R2)), s.s0, s.s1);
    const VD x =
        ClampNaNV(hn::Div(hn::Mul(s.h, sn), hn::Sqrt(hn::Mul(hn::Sub(one, sn), hn::Add(one, sn)))), s.x0, s.x1);
    // y-step (14)-(16).
    const VD d2 = hn::MulAdd(x, x, hn::Mul(s.h, s.h)), dd = hn::Sqrt(d2);
    const VD r0 = hn::Sqrt(hn::MulAdd(s.y0, s.y0, d2)), r1 = hn::Sqrt(hn::MulAdd(s.y1, s.y1, d2));
    const VD omh_beside =
        hn::NegMulAdd(v, DiffBV(d, s.y0, s.y1, r0, r1, d2, s.wy), hn::Div(d2, hn::Mul(r0, hn::Add(r0, s.y0))));
    const VD hy0 = hn::Div(s.y0, r0);
    const VD hy_across = hn::MulAdd(v, hn::Sub(hn::Div(s.y1, r1), hy0), hy0);
    const VD hy = hn::IfThenElse(s.y_beside, hn::Sub(one, omh_beside), hy_across);
    const VD omh = hn::IfThenElse(s.y_beside, omh_beside, hn::Sub(one, hy_across));
    const VD c = hn::Sqrt(hn::Mul(omh, hn::Add(one, hy)));
    const VD y = hn::Div(hn::Mul(hy, dd), c);
    const VD py = ClampNaNV(y, s.y0, s.y1);
    dist = hn::IfThenElse(py == y, hn::Div(dd, c), hn::Sqrt(hn::MulAdd(py, py, d2)));
    const VD a = hn::IfThenElse(s.flip_x, hn::Neg(x), x), b = hn::IfThenElse(s.flip_y, hn::Neg(py), py);
    X = hn::IfThenElse(s.swap, b, a);
    Y = hn::IfThenElse(s.swap, a, b);
}

// rectangle_cosine's corner weights (rectangle_cosine.h): the clamped cosines between the normal (nx, ny, nz) and the
// vectors to the corners M(i, j) of the lanes' setups, w[i + 2 j]; lanes without a usable normal or with every weight
// 0 leave `ok` (the scalar path decides them).
HWY_INLINE void CornerWeightsV(DD d, const RectLightFrame<float>& f, const SetupV& s, VD nx, VD ny, VD nz, VD* w,
                               MD& ok) {
    const VD zero = hn::Zero(d), inf = hn::Set(d, std::numeric_limits<double>::infinity());
    const VD ln = hn::Sqrt(hn::MulAdd(nx, nx, hn::MulAdd(ny, ny, hn::Mul(nz, nz))));
    ok = hn::And(ok, hn::And(ln > zero, ln < inf));
    const VD az_h = hn::Mul(s.az_sign, s.h);
    VD sum = zero;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const VD x = i ? s.x1 : s.x0, y = j ? s.y1 : s.y0;
            const VD a = hn::IfThenElse(s.flip_x, hn::Neg(x), x), b = hn::IfThenElse(s.flip_y, hn::Neg(y), y);
            const VD X = hn::IfThenElse(s.swap, b, a), Y = hn::IfThenElse(s.swap, a, b);
            auto component = [&](double ex, double ey, double n) {  // of LocalVector(plane, X, Y)
                return hn::MulAdd(hn::Set(d, ex), X, hn::MulAdd(hn::Set(d, ey), Y, hn::Mul(hn::Set(d, n), az_h)));
            };
            const VD cx = component(f.exh.x, f.eyh.x, f.n.x), cy = component(f.exh.y, f.eyh.y, f.n.y),
                     cz = component(f.exh.z, f.eyh.z, f.n.z);
            const VD length = hn::Sqrt(hn::MulAdd(cx, cx, hn::MulAdd(cy, cy, hn::Mul(cz, cz))));
            const VD cosine = hn::Div(hn::MulAdd(nx, cx, hn::MulAdd(ny, cy, hn::Mul(nz, cz))), hn::Mul(ln, length));
            w[i + 2 * j] = hn::IfThenElse(cosine > zero, cosine, zero);  // (NaN -> 0)
            sum = hn::Add(sum, w[i + 2 * j]);
        }
    ok = hn::And(ok, sum > zero);
}

// SampleLinear of bilinear.h: x in [0, 1] with density proportional to (1 - x) a + x b.
HWY_INLINE VD SampleLinearV(DD d, VD xi, VD a, VD b) {
    const VD one = hn::Set(d, 1.0);
    const VD root = hn::Sqrt(hn::Add(hn::Mul(hn::Mul(hn::Sub(one, xi), a), a), hn::Mul(hn::Mul(xi, b), b)));
    const VD x = ClampNaNV(hn::Div(hn::Mul(xi, hn::Add(a, b)), hn::Add(a, root)), hn::Zero(d), one);
    return hn::IfThenElse(a == b, xi, x);
}

// SampleBilinear and BilinearPDF of bilinear.h on the lanes' weights: (u, v) warped in place, its density returned.
HWY_INLINE VD WarpBilinearV(DD d, const VD* w, VD& u, VD& v) {
    const VD one = hn::Set(d, 1.0);
    u = SampleLinearV(d, u, hn::Add(w[0], w[2]), hn::Add(w[1], w[3]));
    const VD nu = hn::Sub(one, u);
    v = SampleLinearV(d, v, hn::Add(hn::Mul(nu, w[0]), hn::Mul(u, w[1])), hn::Add(hn::Mul(nu, w[2]), hn::Mul(u, w[3])));
    const VD nv = hn::Sub(one, v);
    const VD sum = hn::Add(hn::Add(hn::Add(w[0], w[1]), w[2]), w[3]);
    const VD mix = hn::Add(hn::Add(hn::Mul(hn::Mul(nu, nv), w[0]), hn::Mul(hn::Mul(u, nv), w[1])),
                           hn::Add(hn::Mul(hn::Mul(nu, v), w[2]), hn::Mul(hn::Mul(u, v), w[3])));
    return hn::Div(hn::Mul(hn::Set(d, 4.0), mix), sum);
}

// `rectangle` (normals null) or `rectangle_cosine` (the points' normals) over the batch.
size_t SampleRectangleBatchImpl(const RectLightFrame<float>& f, const Vec3f* origins, const Vec3f* normals, size_t n,
                                const Point2<float>* uv, int m, LightSample<float>* out) {
    const DD d;
    constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    const size_t N = hn::Lanes(d);
    HWY_ALIGN double out_X[kMaxLanes], out_Y[kMaxLanes], out_dist[kMaxLanes], out_pdf[kMaxLanes];
    HWY_ALIGN double vector_lane[kMaxLanes], out_warp_pdf[kMaxLanes];
    HWY_ALIGN double plane_x0[kMaxLanes], plane_y0[kMaxLanes], plane_h[kMaxLanes], plane_az[kMaxLanes];
    HWY_ALIGN uint8_t lane_ok[kMaxLanes] = {};
    if (!f.valid) {  // every sample of a degenerate light has pdf 0
        std::fill(out, out + n * size_t(m), LightSample<float>{});
        return 0;
    }
    size_t vector_points = 0;
    const Vec3d corner(f.light.corner), edge_x(f.light.ex), edge_y(f.light.ey);
    for (size_t first = 0; first < n; first += N) {
        const size_t count = std::min(N, n - first);
        const V3 o = LoadPointLanes(d, origins, first, count);
        SetupV s = MakeSetupV(d, f, o.x, o.y, o.z);
        VD weights[4];
        if (normals) {
            const V3 nn = LoadPointLanes(d, normals, first, count);
            CornerWeightsV(d, f, s, nn.x, nn.y, nn.z, weights, s.vector_ok);
        }
        // (Non-finite origins make the comparisons false: those lanes are not vector lanes.)
        hn::Store(hn::IfThenElseZero(s.vector_ok, hn::Set(d, 1.0)), d, vector_lane);
        bool any_vector = false;
        for (size_t i = 0; i < N; ++i) any_vector |= (lane_ok[i] = vector_lane[i] > 0);
        for (size_t i = 0; i < count; ++i) vector_points += lane_ok[i];
        hn::Store(s.px0, d, plane_x0);
        hn::Store(s.py0, d, plane_y0);
        hn::Store(s.h, d, plane_h);
        hn::Store(s.az_sign, d, plane_az);
        const VD pdf = hn::Div(hn::Set(d, 1.0), s.omega);
        for (int k = 0; k < m; ++k) {
            if (any_vector) {
                VD X, Y, dist, u, v;
                LoadSampleLanes(d, uv, first, count, m, k, u, v);
                hn::Store(normals ? WarpBilinearV(d, weights, u, v) : hn::Set(d, 1.0), d, out_warp_pdf);
                MapV(d, s, u, v, X, Y, dist);
                hn::Store(X, d, out_X);
                hn::Store(Y, d, out_Y);
                hn::Store(dist, d, out_dist);
                hn::Store(pdf, d, out_pdf);
            }
            for (size_t i = 0; i < count; ++i) {
                const size_t j = (first + i) * size_t(m) + size_t(k);
                if (!lane_ok[i]) {  // the scalar reference
                    const Vec3f& o = origins[first + i];
                    out[j] = normals ? SampleRectangleCosine(MakeRectangleCosineSetup(o, normals[first + i], f), uv[j])
                                     : SampleRectangle(MakeRectangleSetup(o, f), uv[j]);
                    continue;
                }
                // LightSampleFromLocal of local_rect.h: clamped onto the light, the point from the corner and the
                // edges, the direction from the local coordinates.
                const double X = ClampNaN(out_X[i], plane_x0[i], plane_x0[i] + f.wx);
                const double Y = ClampNaN(out_Y[i], plane_y0[i], plane_y0[i] + f.wy);
                const double a = std::min((X - plane_x0[i]) / f.wx, 1.0), b = std::min((Y - plane_y0[i]) / f.wy, 1.0);
                LightSample<float>& ls = out[j];
                ls.point = Vec3f(corner + edge_x * a + edge_y * b);
                const Vec3d dir = f.exh * X + f.eyh * Y + f.n * (plane_az[i] * plane_h[i]);
                double dist = out_dist[i];
                if (!(dist > 0) || !std::isfinite(dist)) dist = Length(dir);
                ls.dist = float(dist);
                ls.dir = Vec3f(dir / dist);
                // (The cosine's pdf as SampleRectangleCosine: the warp's density times the float 1 / Omega.)
                ls.pdf = float(out_pdf[i]);
                if (normals) {
                    ls.pdf = float(out_warp_pdf[i] * double(ls.pdf));
                    if (!std::isfinite(ls.pdf)) ls.pdf = 0;
                }
            }
        }
    }
    return vector_points;
}

const char* TargetNameImpl() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace sphrect
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sphrect {

HWY_EXPORT(SampleRectangleBatchImpl);
HWY_EXPORT(TargetNameImpl);

size_t SampleRectangleBatch(const RectLightFrame<float>& frame, const Vec3f* origins, size_t n, const Point2<float>* uv,
                            int m, LightSample<float>* out) {
    if (n == 0 || m <= 0) return 0;
    return HWY_DYNAMIC_DISPATCH(SampleRectangleBatchImpl)(frame, origins, nullptr, n, uv, m, out);
}

size_t SampleRectangleCosineBatch(const RectLightFrame<float>& frame, const Vec3f* origins, const Vec3f* normals,
                                  size_t n, const Point2<float>* uv, int m, LightSample<float>* out) {
    if (n == 0 || m <= 0) return 0;
    return HWY_DYNAMIC_DISPATCH(SampleRectangleBatchImpl)(frame, origins, normals, n, uv, m, out);
}

const char* RectangleBatchTarget() { return HWY_DYNAMIC_DISPATCH(TargetNameImpl)(); }

}  // namespace sphrect
#endif
