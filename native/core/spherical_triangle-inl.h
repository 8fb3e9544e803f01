// spherical_triangle.h in Highway lanes of double, for the batched kernels (triangle_batch.cpp: emissive triangles;
// triangles_batch.cpp: technique `triangles`): the spherical triangle from a vertex and two edges
// (MakeSphericalTriangleFromEdges) and Arvo's map as barycentrics (SampleSphericalTriangleBarycentrics), the same
// formulas, branch-free; (T1)-(T3) are that file's steps.  A "-inl.h" header, re-included once per instruction set by
// foreach_target.h (hence the toggled guard).
#if defined(SPHRECT_CORE_SPHERICAL_TRIANGLE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SPHRECT_CORE_SPHERICAL_TRIANGLE_INL_H_
#undef SPHRECT_CORE_SPHERICAL_TRIANGLE_INL_H_
#else
#define SPHRECT_CORE_SPHERICAL_TRIANGLE_INL_H_
#endif

#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include "core/simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace sphrect {
namespace HWY_NAMESPACE {

// TanHalfAngle of spherical_triangle.h: tan(w/2) from |x cross y|, x . y and |x||y|, in the form that does not cancel.
HWY_INLINE VD TanHalfAngleV(VD cross, VD dot, VD lengths) {
    return hn::IfThenElse(dot >= hn::Zero(DD()), hn::Div(cross, hn::Add(lengths, dot)),
                          hn::Div(hn::Sub(lengths, dot), cross));
}

// SphericalTriangle's fields the map reads, per lane.
struct SphericalTriangleV {
    V3 a, eb, ec;
    VD la, lb, area, area_error, cos_alpha, sin_alpha, tan_half_c, a_cross_ec, a_dot_ec, tan_half_b;
    MD angle_ok;  // the angle at A is defined (a lane without it takes the scalar path)
};

// MakeSphericalTriangleFromEdges: vertex a, edges eb = b - a, ec = c - a, the vertex lengths, and the triple product
// |a . (eb x ec)| (callers with the edges' cross product at hand pass it).
HWY_INLINE SphericalTriangleV MakeSphericalTriangleV(DD d, const V3& a, const V3& eb, const V3& ec, VD la, VD lb, VD lc,
                                                     VD triple) {
    constexpr double eps = 1.1102230246251565e-16;  // (spherical_triangle.h's area_error)
    const VD two = hn::Set(d, 2.0), eps8 = hn::Set(d, 8 * eps);
    SphericalTriangleV t;
    t.a = a;
    t.eb = eb;
    t.ec = ec;
    t.la = la;
    t.lb = lb;
    const V3 b = Add3(a, eb), c = Add3(a, ec);
    const VD ab = Dot3(a, b), ac = Dot3(a, c), bc = Dot3(b, c);
    // SphericalTriangleDenominator: |a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|.
    const VD den =
        hn::Add(hn::Add(hn::Mul(hn::Mul(la, lb), lc), hn::Mul(ab, lc)), hn::Add(hn::Mul(ac, lb), hn::Mul(bc, la)));
    t.area = hn::Mul(two, Atan2NonNegative(d, triple, den));
    t.area_error = hn::Add(hn::Div(hn::Mul(hn::Mul(two, triple), hn::Mul(eps8, hn::Mul(hn::Mul(la, lb), lc))),
                                   hn::MulAdd(triple, triple, hn::Mul(den, den))),
                           hn::Mul(eps8, t.area));
    const V3 nab = Cross3(a, eb), nac = Cross3(a, ec);
    const VD y = hn::Mul(la, triple), x = Dot3(nab, nac), r = hn::Sqrt(hn::MulAdd(x, x, hn::Mul(y, y)));
    t.angle_ok = hn::And(r > hn::Zero(d), IsFiniteV(d, r));
    t.cos_alpha = hn::Div(x, r);
    t.sin_alpha = hn::Div(y, r);
    t.tan_half_c = TanHalfAngleV(Length3(nab), ab, hn::Mul(la, lb));
    t.a_cross_ec = Length3(nac);
    t.a_dot_ec = Dot3(a, ec);
    t.tan_half_b = TanHalfAngleV(t.a_cross_ec, ac, hn::Mul(la, lc));
    return t;
}

// Lanes of t where `mask`, of e elsewhere (the map's triangle, chosen per lane).
HWY_INLINE SphericalTriangleV SelectTriangleV(MD mask, const SphericalTriangleV& t, const SphericalTriangleV& e) {
    auto pick = [&](VD x, VD y) { return hn::IfThenElse(mask, x, y); };
    auto pick3 = [&](const V3& x, const V3& y) { return V3{pick(x.x, y.x), pick(x.y, y.y), pick(x.z, y.z)}; };
    SphericalTriangleV r;
    r.a = pick3(t.a, e.a);
    r.eb = pick3(t.eb, e.eb);
    r.ec = pick3(t.ec, e.ec);
    r.la = pick(t.la, e.la);
    r.lb = pick(t.lb, e.lb);
    r.area = pick(t.area, e.area);
    r.area_error = pick(t.area_error, e.area_error);
    r.cos_alpha = pick(t.cos_alpha, e.cos_alpha);
    r.sin_alpha = pick(t.sin_alpha, e.sin_alpha);
    r.tan_half_c = pick(t.tan_half_c, e.tan_half_c);
    r.a_cross_ec = pick(t.a_cross_ec, e.a_cross_ec);
    r.a_dot_ec = pick(t.a_dot_ec, e.a_dot_ec);
    r.tan_half_b = pick(t.tan_half_b, e.tan_half_b);
    r.angle_ok = hn::Or(hn::And(mask, t.angle_ok), hn::AndNot(mask, e.angle_ok));
    return r;
}

// SampleSphericalTriangleBarycentrics: M(u, v) as barycentrics (beta, gamma) of the planar triangle, the point
// a + beta eb + gamma ec.
HWY_INLINE void SampleSphericalTriangleBarycentricsV(DD d, const SphericalTriangleV& t, VD u, VD v, VD& beta,
                                                     VD& gamma) {
    const VD zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
    // (T1) the sub-triangle of area u Omega.
    const VD half = hn::Mul(hn::Mul(hn::Set(d, 0.5), u), t.area);
    const VD sh = hn::Sin(d, half), ch = hn::Cos(d, half);
    const VD sin_rest = hn::Sub(hn::Mul(t.sin_alpha, ch), hn::Mul(t.cos_alpha, sh));
    const VD tb = hn::Div(sh, hn::Mul(sin_rest, t.tan_half_c));
    // (T2) C' on the edge ac.
    const VD tc_inside = ClampNaNV(
        hn::Div(hn::Mul(hn::Mul(hn::Mul(two, t.la), t.la), tb),
                hn::Sub(hn::Mul(t.a_cross_ec, hn::Sub(one, hn::Mul(tb, tb))), hn::Mul(hn::Mul(two, t.a_dot_ec), tb))),
        zero, one);
    const VD tc = hn::IfThenElse(hn::And(sin_rest > zero, tb < t.tan_half_b), tc_inside, one);
    // (T3) P on the arc B C'.
    const V3 b = Add3(t.a, t.eb);
    const V3 f = Sub3(Scale3(t.ec, tc), t.eb), cp = Add3(t.a, Scale3(t.ec, tc));
    const VD g = Length3(Cross3(b, f)), hb = Dot3(b, f), k = Dot3(b, cp), m = hn::Mul(t.lb, Length3(cp));
    const MD k_pos = k >= zero;
    const VD two_m = hn::Mul(two, m), g2 = hn::Mul(g, g);
    const VD m_plus = hn::Add(m, k), m_minus = hn::Sub(m, k);
    const VD c1 = hn::IfThenElse(k_pos, hn::Div(m_plus, two_m), hn::Div(g2, hn::Mul(two_m, m_minus)));
    const VD s1 = hn::IfThenElse(k_pos, hn::Div(g2, hn::Mul(two_m, m_plus)), hn::Div(m_minus, two_m));
    const VD sh2 = hn::Mul(v, s1), ch2 = hn::MulAdd(v, c1, hn::Sub(one, v));
    const VD sin_phi = hn::Mul(two, hn::Sqrt(hn::Mul(sh2, ch2))), cos_phi = hn::Sub(ch2, sh2);
    const VD den = hn::Sub(hn::Mul(g, cos_phi), hn::Mul(hb, sin_phi));
    const VD s = hn::IfThenElse(den > zero, ClampNaNV(hn::Div(hn::Mul(hn::Mul(t.lb, t.lb), sin_phi), den), zero, one),
                                hn::IfThenElse(sin_phi > zero, one, zero));
    beta = hn::Sub(one, s);
    gamma = hn::Mul(s, tc);
}

}  // namespace HWY_NAMESPACE
}  // namespace sphrect
HWY_AFTER_NAMESPACE();

#endif  // SPHRECT_CORE_SPHERICAL_TRIANGLE_INL_H_
