// LightTree::SampleBatch: the light tree's descent for many receivers at once, each lane its own receiver and node,
// the nodes' importances (NodeImportance) and the left child's probability (LeftChildProbability) in Highway lanes
// of float, with the instruction set chosen at run time.  The same operations in the same order as the scalar code,
// compiled without contraction into fused multiply-adds (CMakeLists: -ffp-contract=off), so every lane's emitter,
// pmf and rescaled u are the scalar Sample's bit for bit (tests/native/test_light_tree_batch.cpp): a sample's pmf
// then equals the PMF shading computes for its MIS weights exactly.
#include "render/light_tree.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/light_tree_batch.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// (foreach_target.h first, then highway.h: Highway's dispatch idiom.)
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>

HWY_BEFORE_NAMESPACE();
namespace sphrect::render {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using VF = hn::Vec<DF>;
using MF = hn::Mask<DF>;
using DI = hn::RebindToSigned<DF>;
using VI = hn::Vec<DI>;

// std::max(a, b) and std::min(a, b) as the scalar code evaluates them (NaN handling included).
HWY_INLINE VF MaxOf(VF a, VF b) { return hn::IfThenElse(a < b, b, a); }
HWY_INLINE VF MinOf(VF a, VF b) { return hn::IfThenElse(b < a, b, a); }
HWY_INLINE VF SafeSqrtV(DF d, VF x) { return hn::Sqrt(MaxOf(hn::Zero(d), x)); }
HWY_INLINE VF CosSubClampedV(DF d, VF sin_a, VF cos_a, VF sin_b, VF cos_b) {
    return hn::IfThenElse(cos_a >= cos_b, hn::Set(d, 1.0f), hn::Add(hn::Mul(cos_a, cos_b), hn::Mul(sin_a, sin_b)));
}
HWY_INLINE VF SinSubClampedV(DF d, VF sin_a, VF cos_a, VF sin_b, VF cos_b) {
    return hn::IfThenZeroElse(cos_a >= cos_b, hn::Sub(hn::Mul(sin_a, cos_b), hn::Mul(cos_a, sin_b)));
}
// a.x b.x + a.y b.y + a.z b.z, left to right (vec3.h's Dot).
HWY_INLINE VF DotV(VF ax, VF ay, VF az, VF bx, VF by, VF bz) {
    return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
}

// The fields of the lanes' nodes (index `node` each), gathered from the 48-byte LightTreeNode.
struct NodesV {
    VF cx, cy, cz, radius, ax, ay, az, cos_o, cos_e, power;
    VI child, flags;
};
HWY_INLINE NodesV GatherNodes(DF d, const LightTreeNode* nodes, VI node) {
    static_assert(sizeof(LightTreeNode) == 12 * sizeof(float), "LightTreeNode: 12 words");
    const DI di;
    const float* base = reinterpret_cast<const float*>(nodes);
    const int32_t* ibase = reinterpret_cast<const int32_t*>(nodes);
    const VI word = hn::Mul(node, hn::Set(di, 12));
    auto field = [&](int k) { return hn::GatherIndex(d, base, hn::Add(word, hn::Set(di, k))); };
    NodesV n;
    n.cx = field(0);
    n.cy = field(1);
    n.cz = field(2);
    n.radius = field(3);
    n.ax = field(4);
    n.ay = field(5);
    n.az = field(6);
    n.cos_o = field(7);
    n.cos_e = field(8);
    n.power = field(9);
    n.child = hn::GatherIndex(di, ibase, hn::Add(word, hn::Set(di, 10)));
    n.flags = hn::GatherIndex(di, ibase, hn::Add(word, hn::Set(di, 11)));
    return n;
}

// NodeImportance of light_tree.h, lane by lane.
HWY_INLINE VF NodeImportanceV(DF d, const NodesV& node, VF px, VF py, VF pz, VF nx, VF ny, VF nz, MF has_normal) {
    const DI di;
    const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f), min_d2 = hn::Set(d, kLightTreeMinDistance2);
    const VF tx = hn::Sub(px, node.cx), ty = hn::Sub(py, node.cy), tz = hn::Sub(pz, node.cz);
    const VF d2 = DotV(tx, ty, tz, tx, ty, tz);
    const VF r2 = hn::Mul(node.radius, node.radius);
    const VF inside = hn::Div(node.power, MaxOf(MaxOf(d2, hn::Mul(hn::Set(d, 0.25f), r2)), min_d2));
    const VF inv_d = hn::Div(one, hn::Sqrt(d2));
    const VF wx = hn::Mul(tx, inv_d), wy = hn::Mul(ty, inv_d), wz = hn::Mul(tz, inv_d);
    const VF sin_b = hn::Mul(node.radius, inv_d), cos_b = hn::Mul(hn::Sqrt(hn::Sub(d2, r2)), inv_d);
    VF cos_w = DotV(node.ax, node.ay, node.az, wx, wy, wz);
    const MF two_sided =
        hn::RebindMask(d, hn::And(node.flags, hn::Set(di, int32_t(LightTreeNode::kTwoSided))) != hn::Zero(di));
    cos_w = hn::IfThenElse(two_sided, hn::Abs(cos_w), cos_w);
    const VF sin_w = SafeSqrtV(d, hn::Sub(one, hn::Mul(cos_w, cos_w)));
    const VF sin_o = SafeSqrtV(d, hn::Sub(one, hn::Mul(node.cos_o, node.cos_o)));
    const VF cos_x = CosSubClampedV(d, sin_w, cos_w, sin_o, node.cos_o);
    const VF sin_x = SinSubClampedV(d, sin_w, cos_w, sin_o, node.cos_o);
    const VF cos_p = CosSubClampedV(d, sin_x, cos_x, sin_b, cos_b);
    VF importance = hn::Div(hn::Mul(node.power, MaxOf(cos_p, zero)), MaxOf(d2, min_d2));
    const VF cos_i = hn::Neg(DotV(nx, ny, nz, wx, wy, wz));
    const VF sin_i = SafeSqrtV(d, hn::Sub(one, hn::Mul(cos_i, cos_i)));
    const VF cos_pi = CosSubClampedV(d, sin_i, cos_i, sin_b, cos_b);
    importance = hn::IfThenElse(has_normal, hn::Mul(importance, cos_pi), importance);
    importance = hn::IfThenElse(importance > zero, importance, hn::Set(d, kSmallestImportance));
    // The early returns, last first: behind the surface, outside the emission cone, inside the sphere, no power.
    importance = hn::IfThenZeroElse(hn::And(has_normal, hn::Not(cos_pi > zero)), importance);
    importance = hn::IfThenZeroElse(cos_p < node.cos_e, importance);
    importance = hn::IfThenElse(d2 <= r2, inside, importance);
    return hn::IfThenZeroElse(hn::Not(node.power > zero), importance);
}

// LeftChildProbability of light_tree.h, lane by lane.
HWY_INLINE VF LeftChildProbabilityV(DF d, VF i_left, VF i_right, VF power_left, VF power_right) {
    const VF zero = hn::Zero(d);
    const MF none = hn::Not(hn::Add(i_left, i_right) > zero);
    const VF l = hn::IfThenElse(none, power_left, i_left), r = hn::IfThenElse(none, power_right, i_right);
    const VF sum = hn::Add(l, r);
    const VF lo = hn::Set(d, 0x1p-24f), hi = hn::Set(d, 1 - 0x1p-24f);
    const VF ratio = hn::Div(l, sum);
    VF p = hn::IfThenElse(ratio < lo, lo, hn::IfThenElse(hi < ratio, hi, ratio));  // std::clamp
    p = hn::IfThenZeroElse(l == zero, p);
    p = hn::IfThenElse(r == zero, hn::Set(d, 1.0f), p);
    return hn::IfThenElse(hn::And(none, hn::Not(sum > zero)), hn::Set(d, 0.5f), p);
}

void SampleBatchImpl(const LightTree& tree, const LightTreeReceiver* receivers, const float* u, size_t n,
                     LightTreeSample* out) {
    const DF d;
    const DI di;
    constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(float);
    const size_t N = hn::Lanes(d);
    const LightTreeNode* nodes = tree.Nodes().data();
    const float a = tree.FluxShare();
    HWY_ALIGN float in[8][kMaxLanes];
    HWY_ALIGN float u_out[kMaxLanes], pmf_out[kMaxLanes], can_out[kMaxLanes];
    HWY_ALIGN int32_t emitter_out[kMaxLanes];
    const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f), below_one = hn::Set(d, kOneMinusEpsilonF);
    for (size_t first = 0; first < n; first += N) {
        const size_t count = std::min(N, n - first);
        for (size_t i = 0; i < N; ++i) {  // (a short batch repeats its last request)
            const size_t r = first + std::min(i, count - 1);
            const LightTreeReceiver& rc = receivers[r];
            const float values[8] = {rc.p.x, rc.p.y, rc.p.z, rc.n.x, rc.n.y, rc.n.z, rc.has_normal ? 1.0f : 0.0f, u[r]};
            for (int k = 0; k < 8; ++k) in[k][i] = values[k];
        }
        const VF px = hn::Load(d, in[0]), py = hn::Load(d, in[1]), pz = hn::Load(d, in[2]);
        const VF nx = hn::Load(d, in[3]), ny = hn::Load(d, in[4]), nz = hn::Load(d, in[5]);
        const MF has_normal = hn::Load(d, in[6]) > zero;
        VF uu = hn::Load(d, in[7]);
        // CanLight: the root's importance.
        const VF root = NodeImportanceV(d, GatherNodes(d, nodes, hn::Zero(di)), px, py, pz, nx, ny, nz, has_normal);
        hn::Store(hn::IfThenElseZero(root > zero, one), d, can_out);
        // SampleMixture's descent: u rescaled past the flux share (lanes below it are redone by the scalar path).
        if (a != 0) uu = MinOf(hn::Div(hn::Sub(uu, hn::Set(d, a)), hn::Set(d, 1 - a)), below_one);
        VI node = hn::Zero(di);
        VF pmf = one;
        for (;;) {
            const NodesV here = GatherNodes(d, nodes, node);
            const MF active = hn::RebindMask(
                d, hn::Eq(hn::And(here.flags, hn::Set(di, int32_t(LightTreeNode::kLeaf))), hn::Zero(di)));
            if (hn::AllFalse(d, active)) {
                hn::Store(here.child, di, emitter_out);
                break;
            }
            const VI left = here.child, right = hn::Add(left, hn::Set(di, 1));
            const NodesV l = GatherNodes(d, nodes, hn::IfThenElse(hn::RebindMask(di, active), left, hn::Zero(di)));
            const NodesV r = GatherNodes(d, nodes, hn::IfThenElse(hn::RebindMask(di, active), right, hn::Zero(di)));
            const VF p_left =
                LeftChildProbabilityV(d, NodeImportanceV(d, l, px, py, pz, nx, ny, nz, has_normal),
                                      NodeImportanceV(d, r, px, py, pz, nx, ny, nz, has_normal), l.power, r.power);
            const MF go_left = uu < p_left;
            const VF q = hn::Sub(one, p_left);
            const VF u_next =
                MinOf(hn::IfThenElse(go_left, hn::Div(uu, p_left), hn::Div(hn::Sub(uu, p_left), q)), below_one);
            const VF pmf_next = hn::Mul(pmf, hn::IfThenElse(go_left, p_left, q));
            uu = hn::IfThenElse(active, u_next, uu);
            pmf = hn::IfThenElse(active, pmf_next, pmf);
            node = hn::IfThenElse(hn::RebindMask(di, active), hn::IfThenElse(hn::RebindMask(di, go_left), left, right),
                                  node);
        }
        hn::Store(uu, d, u_out);
        hn::Store(pmf, d, pmf_out);
        for (size_t i = 0; i < count; ++i) {
            const size_t r = first + i;
            if (!(can_out[i] > 0)) {
                out[r] = {};
            } else if (a != 0 && u[r] < a) {  // chosen by flux: the scalar path
                out[r] = tree.Sample(receivers[r].p, receivers[r].n, u[r]);
            } else {
                LightTreeSample s;
                s.emitter = emitter_out[i];
                s.pmf = tree.MixturePMF(s.emitter, pmf_out[i]);
                s.u = u_out[i];
                out[r] = s;
            }
        }
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace sphrect::render
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace sphrect::render {

HWY_EXPORT(SampleBatchImpl);

void LightTree::SampleBatch(const LightTreeReceiver* receivers, const float* u, size_t n, LightTreeSample* out) const {
    if (n == 0) return;
    if (nodes_.empty()) {
        std::fill(out, out + n, LightTreeSample{});
        return;
    }
    HWY_DYNAMIC_DISPATCH(SampleBatchImpl)(*this, receivers, u, n, out);
}

}  // namespace sphrect::render
#endif
