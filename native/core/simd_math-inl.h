// Vector helpers shared by the batched kernels (rectangle_batch.cpp, triangle_batch.cpp), in Highway's per-target
// namespace: a "-inl.h" header, re-included once per instruction set by foreach_target.h (hence the toggled guard).
#include <algorithm>
#include <cstddef>
#include <limits>

#include "core/vec3.h"

#if defined(SPHRECT_CORE_SIMD_MATH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SPHRECT_CORE_SIMD_MATH_INL_H_
#undef SPHRECT_CORE_SIMD_MATH_INL_H_
#else
#define SPHRECT_CORE_SIMD_MATH_INL_H_
#endif

#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace sphrect {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DD = hn::ScalableTag<double>;
using VD = hn::Vec<DD>;
using MD = hn::Mask<DD>;

// ClampNaN of vec3.h: x within [lo, hi], NaN -> lo.
HWY_INLINE VD ClampNaNV(VD x, VD lo, VD hi) { return hn::IfThenElse(x > lo, hn::IfThenElse(x < hi, x, hi), lo); }

// atan2(y, x) for y >= 0 (not both 0), from an arctangent on [0, 1].
HWY_INLINE VD Atan2NonNegative(DD d, VD y, VD x) {
    const VD ax = hn::Abs(x);
    const MD steep = y > ax;
    const VD t = hn::Div(hn::IfThenElse(steep, ax, y), hn::IfThenElse(steep, y, ax));
    const VD a = hn::Atan(d, t);
    const VD half_pi = hn::Set(d, 1.5707963267948966), pi = hn::Set(d, 3.141592653589793);
    const VD r = hn::IfThenElse(steep, hn::Sub(half_pi, a), a);
    return hn::IfThenElse(x < hn::Zero(d), hn::Sub(pi, r), r);
}

// A 3-vector of lanes.
struct V3 {
    VD x, y, z;
};
HWY_INLINE V3 Add3(const V3& a, const V3& b) { return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)}; }
HWY_INLINE V3 Sub3(const V3& a, const V3& b) { return {hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)}; }
HWY_INLINE V3 Scale3(const V3& a, VD s) { return {hn::Mul(a.x, s), hn::Mul(a.y, s), hn::Mul(a.z, s)}; }
HWY_INLINE VD Dot3(const V3& a, const V3& b) { return hn::MulAdd(a.x, b.x, hn::MulAdd(a.y, b.y, hn::Mul(a.z, b.z))); }
HWY_INLINE V3 Cross3(const V3& a, const V3& b) {
    return {hn::Sub(hn::Mul(a.y, b.z), hn::Mul(a.z, b.y)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(a.x, b.z)),
            hn::Sub(hn::Mul(a.x, b.y), hn::Mul(a.y, b.x))};
}
HWY_INLINE VD Length3(const V3& a) { return hn::Sqrt(Dot3(a, a)); }
// Whether every lane of v is finite.
HWY_INLINE MD IsFiniteV(DD d, VD v) { return hn::Abs(v) < hn::Set(d, std::numeric_limits<double>::infinity()); }

// The lanes of a batch of `count` requests from `first` (a short batch repeats its last request): point
// points[first + i], and sample k of each request's m at uv[(first + i) m + k].
HWY_INLINE V3 LoadPointLanes(DD d, const Vec3f* points, size_t first, size_t count) {
    constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    HWY_ALIGN double x[kMaxLanes], y[kMaxLanes], z[kMaxLanes];
    for (size_t i = 0; i < hn::Lanes(d); ++i) {
        const Vec3f& p = points[first + std::min(i, count - 1)];
        x[i] = p.x, y[i] = p.y, z[i] = p.z;
    }
    return {hn::Load(d, x), hn::Load(d, y), hn::Load(d, z)};
}
HWY_INLINE void LoadSampleLanes(DD d, const Point2<float>* uv, size_t first, size_t count, int m, int k, VD& u, VD& v) {
    constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    HWY_ALIGN double lane_u[kMaxLanes], lane_v[kMaxLanes];
    for (size_t i = 0; i < hn::Lanes(d); ++i) {
        const Point2<float>& p = uv[(first + std::min(i, count - 1)) * size_t(m) + size_t(k)];
        lane_u[i] = p.u, lane_v[i] = p.v;
    }
    u = hn::Load(d, lane_u);
    v = hn::Load(d, lane_v);
}

}  // namespace HWY_NAMESPACE
}  // namespace sphrect
HWY_AFTER_NAMESPACE();

#endif  // SPHRECT_CORE_SIMD_MATH_INL_H_
