// The batched `triangles` technique (triangles_batch.h): triangles.h's setup and map, lane by lane in Highway vectors
// of double; the spherical triangles and Arvo's map are spherical_triangle-inl.h's (spherical_triangle.h's formulas).
// Compiled once per instruction set (foreach_target.h re-includes this file), the best one chosen at run time.
#include "core/triangles_batch.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/triangles_batch.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// (foreach_target.h first, then highway.h: Highway's dispatch idiom.)
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

#include <algorithm>
#include <limits>

#include "core/simd_math-inl.h"
#include "core/spherical_triangle-inl.h"
#include "core/triangles.h"

HWY_BEFORE_NAMESPACE();
namespace sphrect {
namespace HWY_NAMESPACE {

// A solid angle at least this large (sr) leaves 1 / Omega far inside float's range and the rectangle's own stable
// solid angle, which the scalar setup also checks, positive: smaller ones take the scalar path.
constexpr double kTrianglesBatchMinSolidAngle = 1e-30;

size_t SampleTrianglesBatchImpl(const RectLightFrame<float>& f, const Vec3f* origins, size_t n, const Point2<float>* uv,
                                int m, LightSample<float>* out) {
    const DD d;
    constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    const size_t N = hn::Lanes(d);
    HWY_ALIGN double plane_x0[kMaxLanes], plane_y0[kMaxLanes], plane_z[kMaxLanes], pdf_out[kMaxLanes];
    HWY_ALIGN double out_a[kMaxLanes], out_b[kMaxLanes], vector_lane[kMaxLanes];
    if (!f.valid) {  // every sample of a degenerate light has pdf 0
        std::fill(out, out + n * size_t(m), LightSample<float>{});
        return 0;
    }
    const VD zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
    const VD wx = hn::Set(d, f.wx), wy = hn::Set(d, f.wy);
    const Vec3d corner(f.light.corner), edge_x(f.light.ex), edge_y(f.light.ey);
    size_t vector_points = 0;
    for (size_t first = 0; first < n; first += N) {
        const size_t count = std::min(N, n - first);
        const V3 o = LoadPointLanes(d, origins, first, count);
        const VD ox = o.x, oy = o.y, oz = o.z;
        // MakeLocalRect: the light's plane around o, signed height z (h = |z|), corner at (x0, y0).
        const VD dx = hn::Sub(hn::Set(d, f.corner.x), ox), dy = hn::Sub(hn::Set(d, f.corner.y), oy),
                 dz = hn::Sub(hn::Set(d, f.corner.z), oz);
        auto dot = [&](const Vec3d& e) {
            return hn::Add(hn::Add(hn::Mul(dx, hn::Set(d, e.x)), hn::Mul(dy, hn::Set(d, e.y))),
                           hn::Mul(dz, hn::Set(d, e.z)));
        };
        const VD z = dot(f.n), x0 = dot(f.exh), y0 = dot(f.eyh), h = hn::Abs(z);
        MD ok = hn::And(h > zero, hn::And(IsFiniteV(d, ox), hn::And(IsFiniteV(d, oy), IsFiniteV(d, oz))));
        if (!f.light.two_sided) ok = hn::And(ok, z < zero);
        // MakeTrianglesSetup: (00, 10, 11) and (00, 11, 01) in the local frame, exact edges; |c00 . (edge x edge)| =
        // h wx wy for both.
        const VD x1 = hn::Add(x0, wx), y1 = hn::Add(y0, wy);
        const VD h2 = hn::Mul(h, h), x00 = hn::Mul(x0, x0), x11 = hn::Mul(x1, x1), y00 = hn::Mul(y0, y0),
                 y11 = hn::Mul(y1, y1);
        const VD l00 = hn::Sqrt(hn::Add(hn::Add(x00, y00), h2)), l10 = hn::Sqrt(hn::Add(hn::Add(x11, y00), h2)),
                 l11 = hn::Sqrt(hn::Add(hn::Add(x11, y11), h2)), l01 = hn::Sqrt(hn::Add(hn::Add(x00, y11), h2));
        const V3 c00{x0, y0, h}, ex{wx, zero, zero}, ey{zero, wy, zero}, exy{wx, wy, zero};
        const VD triple = hn::Mul(h, hn::Mul(wx, wy));
        const SphericalTriangleV tri0 = MakeSphericalTriangleV(d, c00, ex, exy, l00, l10, l11, triple);
        const SphericalTriangleV tri1 = MakeSphericalTriangleV(d, c00, exy, ey, l00, l11, l01, triple);
        // (Where either estimate nears kTrianglesStableAreaAbove the scalar path recomputes that area in the plane.)
        const VD stable = hn::Set(d, kTrianglesStableAreaAbove);
        ok = hn::And(ok, hn::Mul(two, tri0.area_error) <= hn::Mul(stable, tri0.area));
        ok = hn::And(ok, hn::Mul(two, tri1.area_error) <= hn::Mul(stable, tri1.area));
        ok = hn::And(ok, hn::And(tri0.angle_ok, tri1.angle_ok));
        const VD sum = hn::Add(tri0.area, tri1.area);
        ok = hn::And(ok, hn::And(sum >= hn::Set(d, kTrianglesBatchMinSolidAngle), IsFiniteV(d, sum)));
        const VD p1 = hn::Div(tri0.area, sum);
        hn::Store(hn::IfThenElseZero(ok, one), d, vector_lane);
        bool any_vector = false;
        for (size_t i = 0; i < N; ++i) any_vector |= vector_lane[i] > 0;
        for (size_t i = 0; i < count; ++i) vector_points += vector_lane[i] > 0;
        hn::Store(x0, d, plane_x0);
        hn::Store(y0, d, plane_y0);
        hn::Store(z, d, plane_z);
        hn::Store(hn::Div(one, sum), d, pdf_out);
        for (int k = 0; k < m; ++k) {
            if (any_vector) {
                VD u, v;
                LoadSampleLanes(d, uv, first, count, m, k, u, v);
                const MD first_triangle = u < p1;
                const VD u_tri = hn::Min(
                    hn::IfThenElse(first_triangle, hn::Div(u, p1), hn::Div(hn::Sub(u, p1), hn::Sub(one, p1))), one);
                VD beta, gamma;
                SampleSphericalTriangleBarycentricsV(d, SelectTriangleV(first_triangle, tri0, tri1), u_tri, v, beta,
                                                     gamma);
                // The barycentrics as light fractions (a, b): (B, C) = (10, 11) in the first, (11, 01) in the second.
                const VD sum_bg = hn::Add(beta, gamma);
                hn::Store(ClampNaNV(hn::IfThenElse(first_triangle, sum_bg, beta), zero, one), d, out_a);
                hn::Store(ClampNaNV(hn::IfThenElse(first_triangle, gamma, sum_bg), zero, one), d, out_b);
            }
            for (size_t i = 0; i < count; ++i) {
                const size_t j = (first + i) * size_t(m) + size_t(k);
                if (!(vector_lane[i] > 0)) {  // the scalar reference
                    out[j] = SampleTriangles(MakeTrianglesSetup(origins[first + i], f), uv[j]);
                    continue;
                }
                // LightSampleAt of local_rect.h: the point from the corner and the edges, the direction from the
                // local coordinates (X, Y, h) towards the plane.
                const double a = out_a[i], b = out_b[i];
                const double X = plane_x0[i] + a * f.wx, Y = plane_y0[i] + b * f.wy;
                LightSample<float>& ls = out[j];
                ls.point = Vec3f(corner + edge_x * a + edge_y * b);
                const Vec3d dir = f.exh * X + f.eyh * Y + f.n * plane_z[i];
                const double dist = Length(dir);
                ls.dist = float(dist);
                ls.dir = Vec3f(dir / dist);
                ls.pdf = float(pdf_out[i]);
            }
        }
    }
    return vector_points;
}

}  // namespace HWY_NAMESPACE
}  // namespace sphrect
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sphrect {

HWY_EXPORT(SampleTrianglesBatchImpl);

size_t SampleTrianglesBatch(const RectLightFrame<float>& frame, const Vec3f* origins, size_t n, const Point2<float>* uv,
                            int m, LightSample<float>* out) {
    if (n == 0 || m <= 0) return 0;
    return HWY_DYNAMIC_DISPATCH(SampleTrianglesBatchImpl)(frame, origins, n, uv, m, out);
}

}  // namespace sphrect
#endif
