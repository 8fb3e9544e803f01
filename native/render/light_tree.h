// A light tree: a BVH over emitters of every kind (area lights, emissive triangles, point and
// spot lights) with power and orientation bounds per node, after Conty Estevez & Kulla,
// "Importance Sampling of Many Lights with Adaptive Tree Splitting" (HPG 2018), as pbrt-v4's
// BVHLightSampler and Cycles' light tree do it.
//
//   LightBounds    what the tree knows of one emitter: world box, power, orientation cone.
//   LightTree      Build(bounds) once per scene; then per shading point, allocation-free and in
//                  float, Sample(p, n, u) -> (emitter, pmf, u rescaled) and PMF(p, n, emitter),
//                  the probability that Sample picks that emitter (the MIS pdf of an emitter a
//                  BSDF ray found).  n = (0,0,0): no normal (a point in a medium).
//   LightTreeAt    the same Sample(u) and PMF(emitter) at one receiver, each node's child
//                  probabilities computed once for all of that point's calls.
//
// Each emitter gives its own LightBounds (light_bounds.h): AreaLightBounds and TriangleLightBounds in
// area_light.h, DeltaLightBounds in delta_light.h.
// Emitter indices are positions in the vector given to Build; CollectTreeEmitters numbers the
// scene's area lights first, then its point and spot lights (suns stay outside: no finite bounds).
// Derivation of the importance and the build's cost: docs/light_tree.md.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "area_light.h"
#include "core/rng.h"
#include "delta_light.h"
#include "light_bounds.h"
#include "light_selector.h"
#include "sampling_util.h"

namespace sphrect::render {

// Which scene light a tree emitter is.
enum class TreeEmitterKind : uint8_t { Area, Delta };
struct TreeEmitterRef {
    TreeEmitterKind kind = TreeEmitterKind::Area;
    int index = 0;  // into area_lights or delta_lights
};
struct TreeEmitters {
    std::vector<LightBounds> bounds;
    std::vector<TreeEmitterRef> refs;  // refs[i] is emitter i of the tree
};
// A scene's point and spot lights stay beside the tree, each evaluated at every light sample as under "power", while
// there are at most this many of them: where a few strong lights each dominate somewhere, choosing them costs
// selection noise that evaluating them does not, and their shadow rays are few (docs/light_tree.md, starvation).
constexpr size_t kMaxDeltaLightsBesideTree = 8;
// Whether the scene's point and spot lights are tree emitters (more than kMaxDeltaLightsBesideTree of them).
bool DeltaLightsInTree(const std::vector<DeltaLight>& delta_lights);
// The area lights, then (when delta_lights_in_tree: a scene's DeltaLightsInTree) the point and spot lights.
TreeEmitters CollectTreeEmitters(const std::vector<AreaLight>& area_lights, const std::vector<DeltaLight>& delta_lights,
                                 bool delta_lights_in_tree);
// The tree emitter each delta light is in CollectTreeEmitters' numbering (after the area lights), -1 for one that
// is not a tree emitter (a sun, or a point or spot light beside the tree): what a scene needs of the numbering before
// (or without) building the tree.
std::vector<int> DeltaTreeEmitters(size_t num_area_lights, const std::vector<DeltaLight>& delta_lights,
                                   bool delta_lights_in_tree);

// A node, 48 bytes: the bounding sphere of its box (what the importance needs of the box), the
// union of its emitters' cones, their power (divided by the tree's total, so at most 1).
// An inner node's children are nodes child_or_emitter (left) and child_or_emitter + 1 (right);
// a leaf holds one emitter, index child_or_emitter.
struct LightTreeNode {
    Vec3f center;
    float radius = 0;  // bounding sphere of the box, padded outwards for rounding
    Vec3f axis;
    float cos_theta_o = 1, cos_theta_e = 0;  // rounded towards the wider cone
    float power = 0;
    uint32_t child_or_emitter = 0;
    uint32_t flags = 0;  // kLeaf, kTwoSided

    static constexpr uint32_t kLeaf = 1, kTwoSided = 2;
    bool IsLeaf() const { return flags & kLeaf; }
};
static_assert(sizeof(LightTreeNode) == 48, "LightTreeNode layout");

struct LightTreeSample {
    int emitter = -1;  // -1: the tree is empty or nothing in it can light the point
    float pmf = 0;
    float u = 0;  // the number given, rescaled at each level: again uniform in [0,1)
};

// Limits: the bit trail of an emitter's root-to-leaf path is a uint64, so depth <= 63; the
// build falls back to splitting by count at kLightTreeBinnedDepth, which bounds the depth by
// kLightTreeBinnedDepth + log2(kMaxLightTreeEmitters).
inline constexpr int kLightTreeMaxDepth = 63;
inline constexpr int kLightTreeBinnedDepth = 32;
inline constexpr int kMaxLightTreeEmitters = 1 << 30;

// ---- Importance of a node at a receiver (pbrt-v4's LightBounds::Importance, with the
// distance clamped to the node's bounding sphere as Cycles does inside a node). ----

// cos(max(0, a - b)) from the cosines and sines of a, b in [0, pi].
[[gnu::always_inline]] inline float CosSubClamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    return cos_a >= cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}
// sin(max(0, a - b)).
[[gnu::always_inline]] inline float SinSubClamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    return cos_a >= cos_b ? 0.0f : sin_a * cos_b - cos_a * sin_b;
}

inline constexpr float kLightTreeMinDistance2 = 1e-30f;  // with power <= 1: importance <= 1e30, sums finite
inline constexpr float kSmallestImportance = 1.4e-45f;   // what an underflowed non-zero importance becomes

// importance = power * cos(theta') * cos(theta'_i) / d^2, where, seen from p, theta_b is the
// half-angle of the node's bounding sphere, theta_w the angle between the axis and the direction
// from the node to p, theta' = max(0, theta_w - theta_o - theta_b) the smallest angle of
// emission towards the node's box (0 when theta' > theta_e: nothing emitted towards p), and
// theta'_i = max(0, theta_i - theta_b) the smallest angle of incidence at a receiver with normal n
// (0 beyond pi/2: the box is behind the surface).  Inside the sphere every direction is possible
// and d is clamped to half its radius (Cycles' clamp; clamping to the radius, pbrt's choice,
// made the light choice's second moment on many lights over a plane several times larger:
// bench_light_tree's BM_LightTreeSelectionMoment, docs/light_tree.md).  Zero only when no emitter
// of the node can light p.
[[gnu::always_inline]] inline float NodeImportance(const LightTreeNode& node, const Vec3f& p, const Vec3f& n,
                                                   bool has_normal) {
    if (!(node.power > 0)) return 0;
    const Vec3f to_p = p - node.center;
    const float d2 = Dot(to_p, to_p);
    const float r2 = node.radius * node.radius;
    if (d2 <= r2) return node.power / std::max(std::max(d2, 0.25f * r2), kLightTreeMinDistance2);
    const float inv_d = 1 / std::sqrt(d2);
    const Vec3f wi = to_p * inv_d;  // from the node towards p
    // sin and cos of theta_b: r / d and sqrt(d^2 - r^2) / d (both roots at once, not one after the other).
    const float sin_b = node.radius * inv_d, cos_b = std::sqrt(d2 - r2) * inv_d;

    float cos_w = Dot(node.axis, wi);
    if (node.flags & LightTreeNode::kTwoSided) cos_w = std::abs(cos_w);
    const float sin_w = SafeSqrt(1 - cos_w * cos_w);
    const float sin_o = SafeSqrt(1 - node.cos_theta_o * node.cos_theta_o);
    const float cos_x = CosSubClamped(sin_w, cos_w, sin_o, node.cos_theta_o);
    const float sin_x = SinSubClamped(sin_w, cos_w, sin_o, node.cos_theta_o);
    const float cos_p = CosSubClamped(sin_x, cos_x, sin_b, cos_b);
    if (cos_p < node.cos_theta_e) return 0;

    float importance = node.power * std::max(cos_p, 0.0f) / std::max(d2, kLightTreeMinDistance2);
    if (has_normal) {
        const float cos_i = -Dot(n, wi);  // towards the node
        const float sin_i = SafeSqrt(1 - cos_i * cos_i);
        const float cos_pi = CosSubClamped(sin_i, cos_i, sin_b, cos_b);
        if (!(cos_pi > 0)) return 0;
        importance *= cos_pi;
    }
    // cos_p == 0 exactly is the edge of the emitting side: keep it (conservative) as underflow.
    return importance > 0 ? importance : kSmallestImportance;
}

// Probability of the left child given both importances: their ratio, kept within
// [2^-24, 1 - 2^-24] while both are non-zero (so that a child that can contribute keeps a
// representable share); by power when both are zero (the parent's looser bounds let p in
// where neither child's does: the pick cannot contribute, but the pmfs still sum to 1).
[[gnu::always_inline]] inline float LeftChildProbability(float i_left, float i_right, float power_left,
                                                         float power_right) {
    if (!(i_left + i_right > 0)) {
        i_left = power_left;
        i_right = power_right;
        if (!(i_left + i_right > 0)) return 0.5f;
    }
    if (i_right == 0) return 1;
    if (i_left == 0) return 0;
    constexpr float kMinShare = 0x1p-24f;
    return std::clamp(i_left / (i_left + i_right), kMinShare, 1 - kMinShare);
}

// A receiver: point p, normal n (0,0,0: none, a point in a medium).
struct LightTreeReceiver {
    Vec3f p, n;
    bool has_normal;
    LightTreeReceiver(const Vec3f& p_, const Vec3f& n_)
        : p(p_), n(n_), has_normal(n_.x != 0 || n_.y != 0 || n_.z != 0) {}
};

// The share of the tree's choices made by flux alone (EmitterFlux, as light_selection "power" chooses area lights): a
// defensive mixture, pmf = share * flux pmf + (1 - share) * the tree's own.  The tree's estimates are bounds, and an
// emitter whose favourable bound is far above its true contribution (an area light seen edge-on from the floor beside
// it) otherwise starves its neighbours, whose samples then carry weights of 1 / pmf up to 2^24; with the mixture no
// emitter's pmf falls below share x its flux pmf, so the second moment of a light sample is at most 1 / share times
// power selection's (docs/light_tree.md, starvation, with the measurements that chose the share).
inline constexpr float kTreeFluxShare = 0.1f;

// What an emitter sends in all, in the units of AreaLightPower (flux / pi): L A per side of an area light, 4 I for a
// point or spot light (as RenderScene::Commit weighs them).
inline double EmitterFlux(const LightBounds& b) {
    if (b.cos_theta_o <= -1 || b.cos_theta_e >= 1) return 4 * b.power;
    return b.two_sided ? 2 * b.power : b.power;
}

class LightTree {
  public:
    // Throws std::invalid_argument naming the emitter for NaN/infinite bounds, power or cone,
    // negative power, lo > hi, a zero axis of a cone narrower than the sphere, or too many.
    // Emitters with zero power stay outside the tree (PMF 0, never sampled).  Large subtrees are
    // built on up to `threads` threads (0: the hardware's); the tree is the same for any count.
    void Build(const std::vector<LightBounds>& emitters, int threads = 0);

    bool Empty() const { return nodes_.empty(); }
    int NumEmitters() const { return int(trails_.size()); }
    int NumNodes() const { return int(nodes_.size()); }
    int Depth() const { return depth_; }
    size_t MemoryBytes() const {
        return nodes_.capacity() * sizeof(LightTreeNode) + trails_.capacity() * sizeof(uint64_t);
    }
    const std::vector<LightTreeNode>& Nodes() const { return nodes_; }

    // One emitter for the receiver (p, n) from one uniform u in [0,1): down from the root, the
    // left child with probability LeftChildProbability, u rescaled to the chosen interval.
    LightTreeSample Sample(const Vec3f& p, const Vec3f& n, float u) const {
        const LightTreeReceiver r(p, n);
        if (!CanLight(r)) return {};
        return SampleMixture(u, [&](uint32_t left) { return LeftProbability(left, r); });
    }

    // The probability that Sample(p, n, .) returns `emitter`: the same products along the
    // emitter's root-to-leaf path (its bit trail: bit k = right child at depth k).
    float PMF(const Vec3f& p, const Vec3f& n, int emitter) const {
        if (!InTree(emitter)) return 0;
        const LightTreeReceiver r(p, n);
        if (!CanLight(r)) return 0;
        return MixturePMF(emitter, PathPMF(emitter, [&](uint32_t left) { return LeftProbability(left, r); }));
    }

    // Sample for n receivers at once: out[i] = Sample(receivers[i].p, receivers[i].n, u[i]), the same floats (bit for
    // bit), with the descent's node importances in SIMD lanes (light_tree_batch.cpp; the choices made by flux, a
    // tenth, take the scalar path).  No allocation.
    void SampleBatch(const LightTreeReceiver* receivers, const float* u, size_t n, LightTreeSample* out) const;

    // ---- The pieces of Sample and PMF, for LightTreeAt (which memoises p_left per node). ----

    float FluxShare() const { return flux_share_; }

    // Whether anything in the tree can light r: the root's importance > 0.
    bool CanLight(const LightTreeReceiver& r) const {
        return !nodes_.empty() && NodeImportance(nodes_[0], r.p, r.n, r.has_normal) > 0;
    }
    bool InTree(int emitter) const {
        return emitter >= 0 && emitter < int(trails_.size()) && trails_[emitter] != kNotInTree;
    }
    // The probability at r of the left child of an inner node, given as its children's first
    // index `left` (each inner node's own: the memo's key).
    float LeftProbability(uint32_t left, const LightTreeReceiver& r) const {
        const LightTreeNode& l = nodes_[left];
        const LightTreeNode& rt = nodes_[left + 1];
        return LeftChildProbability(NodeImportance(l, r.p, r.n, r.has_normal),
                                    NodeImportance(rt, r.p, r.n, r.has_normal), l.power, rt.power);
    }
    // Sample's choice (CanLight holds): by flux with probability kTreeFluxShare, else down the tree, u rescaled to the
    // chosen branch; the pmf is the mixture's, MixturePMF.
    template <class PLeft>
    LightTreeSample SampleMixture(float u, PLeft&& p_left_of) const {
        const float a = flux_share_;
        if (a == 0) return Descend(u, p_left_of);
        if (u < a) {
            LightTreeSample s;
            s.emitter = flux_.SelectRemapped(std::min(u / a, kOneMinusEpsilonF), &s.u);
            s.pmf = MixturePMF(s.emitter, PathPMF(s.emitter, p_left_of));
            return s;
        }
        LightTreeSample s = Descend(std::min((u - a) / (1 - a), kOneMinusEpsilonF), p_left_of);
        s.pmf = MixturePMF(s.emitter, s.pmf);
        return s;
    }
    // The probability that SampleMixture picks `emitter`, whose pmf down the tree is tree_pmf.
    float MixturePMF(int emitter, float tree_pmf) const {
        if (flux_share_ == 0) return tree_pmf;
        return flux_share_ * flux_.pmf[size_t(emitter)] + (1 - flux_share_) * tree_pmf;
    }
    // Sample's descent (CanLight holds) with p_left_of(left) the probability of child `left`.
    template <class PLeft>
    LightTreeSample Descend(float u, PLeft&& p_left_of) const {
        uint32_t i = 0;
        float pmf = 1;
        while (!nodes_[i].IsLeaf()) {
            const uint32_t left = nodes_[i].child_or_emitter, right = left + 1;
            const float p_left = p_left_of(left);
            if (u < p_left) {
                u = std::min(u / p_left, kOneMinusEpsilonF);
                pmf *= p_left;
                i = left;
            } else {
                u = std::min((u - p_left) / (1 - p_left), kOneMinusEpsilonF);
                pmf *= 1 - p_left;
                i = right;
            }
        }
        LightTreeSample s;
        s.emitter = int(nodes_[i].child_or_emitter);
        s.pmf = pmf;
        s.u = u;
        return s;
    }
    // PMF's product along the path of `emitter` (InTree and CanLight hold).
    template <class PLeft>
    float PathPMF(int emitter, PLeft&& p_left_of) const {
        const uint64_t trail = trails_[emitter];
        uint32_t i = 0;
        float pmf = 1;
        for (int depth = 0; !nodes_[i].IsLeaf(); ++depth) {
            const uint32_t left = nodes_[i].child_or_emitter, right = left + 1;
            const float p_left = p_left_of(left);
            if ((trail >> depth) & 1) {
                pmf *= 1 - p_left;
                i = right;
            } else {
                pmf *= p_left;
                i = left;
            }
        }
        return pmf;
    }

  private:
    static constexpr uint64_t kNotInTree = ~uint64_t(0);

    std::vector<LightTreeNode> nodes_;  // nodes_[0] the root, then siblings in pairs
    std::vector<uint64_t> trails_;      // per emitter; kNotInTree for zero power
    LightSelector flux_;                // per emitter, by EmitterFlux (the mixture's other half)
    float flux_share_ = 0;              // kTreeFluxShare; 0 with one emitter (nothing to mix)
    int depth_ = 0;
};

// The tree seen from one receiver: Sample and PMF exactly as LightTree's (the same floats),
// with the root's test and, when `memoize`, each inner node's left-child probability computed
// once -- a shading point's light samples and its BSDF rays' pmfs all descend from the same root.
// With one light sample per point the memo costs more than it saves (docs/light_tree.md), so it is
// only asked for with several.  The memo is direct-mapped on the node index: a small tree fits
// whole, a large one keeps the nodes last visited; a bit mask says which slots are filled, so a
// receiver starts it with one store.
class LightTreeAt {
  public:
    LightTreeAt(const LightTree& tree, const Vec3f& p, const Vec3f& n, bool memoize)
        : tree_(tree), r_(p, n), memoize_(memoize) {}

    LightTreeSample Sample(float u) {
        if (!CanLight()) return {};
        return tree_.SampleMixture(u, [this](uint32_t left) { return LeftProbability(left); });
    }

    float PMF(int emitter) {
        if (!tree_.InTree(emitter) || !CanLight()) return 0;
        return tree_.MixturePMF(emitter,
                                tree_.PathPMF(emitter, [this](uint32_t left) { return LeftProbability(left); }));
    }

  private:
    static constexpr uint32_t kSlots = 64;  // the bits of filled_

    bool CanLight() {
        if (can_light_ < 0) can_light_ = tree_.CanLight(r_) ? 1 : 0;
        return can_light_ == 1;
    }
    // Keyed by `left`, the first child of the inner node.
    float LeftProbability(uint32_t left) {
        if (!memoize_) return tree_.LeftProbability(left, r_);
        const uint32_t slot = (left >> 1) % kSlots;  // siblings pairs start at odd indices
        const uint64_t bit = uint64_t(1) << slot;
        if (!(filled_ & bit) || left_[slot] != left) {
            filled_ |= bit;
            left_[slot] = left;
            p_left_[slot] = tree_.LeftProbability(left, r_);
        }
        return p_left_[slot];
    }

    const LightTree& tree_;
    LightTreeReceiver r_;
    bool memoize_;
    int can_light_ = -1;     // unknown until the first call
    uint64_t filled_ = 0;    // bit k: slot k holds p_left of left child left_[k]
    uint32_t left_[kSlots];  // (not initialised: read only where filled_ says so)
    float p_left_[kSlots];
};

}  // namespace sphrect::render
