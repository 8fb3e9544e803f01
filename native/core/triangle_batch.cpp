// The batched triangle emitter (triangle_batch.h): triangle_emitter.h's setup and spherical_triangle.h's map, lane by
// lane in Highway vectors of double, each lane its own triangle.  Variable names follow those files (and through them
// Arvo's, docs/triangles_baseline.md); (T1)-(T3) are spherical_triangle.h's steps.
#include "core/triangle_batch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/triangle_batch.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// (foreach_target.h first, then highway.h: Highway's dispatch idiom.)
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include <algorithm>
#include <limits>

#include "core/simd_math-inl.h"
#include "core/spherical_triangle-inl.h"
#include "core/triangle_emitter.h"

HWY_BEFORE_NAMESPACE();
namespace sphrect {
namespace HWY_NAMESPACE {

size_t SampleTriangleEmitterBatchImpl(const TriangleEmitter* triangles, const Vec3f* origins, size_t n,
                                      const Point2<float>* uv, LightSample<float>* out) {
    const DD d;
    constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    const size_t N = hn::Lanes(d);
    // Per lane: the point, the triangle (v0, e1, e2) and (u, v) in; the direction w, t and 1 / Omega out.
    HWY_ALIGN double in[14][kMaxLanes];
    HWY_ALIGN double w_out[3][kMaxLanes], t_out[kMaxLanes], pdf_out[kMaxLanes], ok_out[kMaxLanes];
    const VD zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
    size_t vector_requests = 0;
    for (size_t first = 0; first < n; first += N) {
        const size_t count = std::min(N, n - first);
        for (size_t i = 0; i < N; ++i) {  // (a short batch repeats its last request)
            const size_t r = first + std::min(i, count - 1);
            const Vec3f* v[4] = {&origins[r], &triangles[r].v0, &triangles[r].e1, &triangles[r].e2};
            for (int k = 0; k < 4; ++k) {
                in[3 * k][i] = v[k]->x;
                in[3 * k + 1][i] = v[k]->y;
                in[3 * k + 2][i] = v[k]->z;
            }
            in[12][i] = uv[r].u;
            in[13][i] = uv[r].v;
        }
        auto load3 = [&](int k) {
            return V3{hn::Load(d, in[3 * k]), hn::Load(d, in[3 * k + 1]), hn::Load(d, in[3 * k + 2])};
        };
        const V3 o = load3(0), v0 = load3(1), e1 = load3(2), e2 = load3(3);
        // The setup (MakeTriangleSolidAngleSetup).
        const V3 a = Sub3(v0, o), b = Add3(a, e1), c = Add3(a, e2);
        const V3 normal = Cross3(e1, e2);
        const VD ln = Length3(normal);
        const V3 nv = Scale3(normal, hn::Div(one, ln));
        const VD h = Dot3(nv, a);
        MD ok = hn::And(hn::Abs(h) > zero, hn::And(ln > zero, IsFiniteV(d, ln)));
        ok = hn::And(ok, hn::And(IsFiniteV(d, Dot3(a, a)), IsFiniteV(d, Dot3(e1, e1) + Dot3(e2, e2))));
        // The spherical triangle (MakeSphericalTriangleFromEdges).
        const VD la = Length3(a), lb = Length3(b), lc = Length3(c);
        const SphericalTriangleV tri = MakeSphericalTriangleV(d, a, e1, e2, la, lb, lc, hn::Abs(Dot3(a, normal)));
        // (Where the estimate nears kTrianglesStableAreaAbove the scalar path recomputes the area in the plane.)
        ok = hn::And(ok, hn::Mul(two, tri.area_error) <= hn::Mul(hn::Set(d, kTrianglesStableAreaAbove), tri.area));
        ok = hn::And(ok, hn::And(tri.area > hn::Set(d, 1e-38), IsFiniteV(d, tri.area)));
        ok = hn::And(ok, tri.angle_ok);
        const VD area = tri.area;
        // The map (SampleSphericalTriangleBarycentrics).
        VD beta, gamma;
        SampleSphericalTriangleBarycentricsV(d, tri, hn::Load(d, in[12]), hn::Load(d, in[13]), beta, gamma);
        // SampleSphericalTriangle: the direction through a + beta eb + gamma ec (A where that is 0 or not finite).
        const V3 p = Add3(a, Add3(Scale3(e1, beta), Scale3(e2, gamma)));
        const VD lp = Length3(p);
        const MD lp_ok = hn::And(lp > zero, IsFiniteV(d, lp));
        const V3 w = {hn::IfThenElse(lp_ok, hn::Div(p.x, lp), hn::Div(a.x, la)),
                      hn::IfThenElse(lp_ok, hn::Div(p.y, lp), hn::Div(a.y, la)),
                      hn::IfThenElse(lp_ok, hn::Div(p.z, lp), hn::Div(a.z, la))};
        // SampleTriangleSolidAngle: the hit of o + t w on the triangle's plane.
        hn::Store(hn::Div(h, Dot3(nv, w)), d, t_out);
        hn::Store(w.x, d, w_out[0]);
        hn::Store(w.y, d, w_out[1]);
        hn::Store(w.z, d, w_out[2]);
        hn::Store(hn::Div(one, area), d, pdf_out);
        hn::Store(hn::IfThenElseZero(ok, one), d, ok_out);
        for (size_t i = 0; i < count; ++i) {
            const size_t j = first + i;
            if (!(ok_out[i] > 0)) {  // the scalar reference
                const TriangleEmitter& emitter = triangles[j];
                out[j] = SampleTriangleSolidAngle(
                    MakeTriangleSolidAngleSetup(emitter.v0, emitter.e1, emitter.e2, origins[j]), origins[j], uv[j]);
                continue;
            }
            ++vector_requests;
            LightSample<float>& ls = out[j];
            const double t = t_out[i];
            const float pdf = float(pdf_out[i]);
            if (!(t > 0) || !std::isfinite(t) || !(pdf > 0) || !std::isfinite(pdf)) {
                ls = {};
                continue;
            }
            const Vec3d wd(w_out[0][i], w_out[1][i], w_out[2][i]);
            ls.point = origins[j] + Vec3f(wd * t);
            ls.dist = float(t);
            ls.dir = Vec3f(wd);
            ls.pdf = ls.dist > 0 && std::isfinite(ls.dist) ? pdf : 0.0f;
        }
    }
    return vector_requests;
}

}  // namespace HWY_NAMESPACE
}  // namespace sphrect
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sphrect {

HWY_EXPORT(SampleTriangleEmitterBatchImpl);

size_t SampleTriangleEmitterBatch(const TriangleEmitter* triangles, const Vec3f* origins, size_t n,
                                  const Point2<float>* uv, LightSample<float>* out) {
    if (n == 0) return 0;
    return HWY_DYNAMIC_DISPATCH(SampleTriangleEmitterBatchImpl)(triangles, origins, n, uv, out);
}

}  // namespace sphrect
#endif
