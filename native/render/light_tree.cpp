// Building the light tree (light_tree.h): the scene's emitters, validation, and a binned
// surface-area-orientation-heuristic (SAOH) split per node, top-down; the nodes' bounds and
// cones are then the exact unions of their children's, bottom-up.
#include "light_tree.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <optional>
#include <string>
#include <system_error>
#include <thread>

namespace sphrect::render {

// ---- The scene's emitters, each bounding itself (area_light.h, delta_light.h) ----

bool DeltaLightsInTree(const std::vector<DeltaLight>& delta_lights) {
    return size_t(std::count_if(delta_lights.begin(), delta_lights.end(), [](const DeltaLight& l) {
               return l.kind != DeltaKind::Sun;
           })) > kMaxDeltaLightsBesideTree;
}

TreeEmitters CollectTreeEmitters(const std::vector<AreaLight>& area_lights, const std::vector<DeltaLight>& delta_lights,
                                 bool delta_lights_in_tree) {
    TreeEmitters e;
    for (size_t i = 0; i < area_lights.size(); ++i) {
        e.bounds.push_back(AreaLightBounds(area_lights[i]));
        e.refs.push_back({TreeEmitterKind::Area, int(i)});
    }
    if (!delta_lights_in_tree) return e;
    for (size_t i = 0; i < delta_lights.size(); ++i) {
        LightBounds b;
        if (!DeltaLightBounds(delta_lights[i], &b)) continue;
        e.bounds.push_back(b);
        e.refs.push_back({TreeEmitterKind::Delta, int(i)});
    }
    return e;
}

std::vector<int> DeltaTreeEmitters(size_t num_area_lights, const std::vector<DeltaLight>& delta_lights,
                                   bool delta_lights_in_tree) {
    std::vector<int> emitters(delta_lights.size(), -1);
    if (!delta_lights_in_tree) return emitters;
    int next = int(num_area_lights);
    for (size_t i = 0; i < delta_lights.size(); ++i) {
        LightBounds b;
        if (DeltaLightBounds(delta_lights[i], &b)) emitters[i] = next++;  // as CollectTreeEmitters counts them
    }
    return emitters;
}

namespace {

constexpr double kPiD = 3.14159265358979323846;

// ---- Direction cones, in double (build only) ----

struct Cone {
    Vec3d axis{0, 0, 1};
    double theta_o = 0, theta_e = 0;  // radians
    bool two_sided = false;
};

double AngleBetween(const Vec3d& a, const Vec3d& b) {
    // Numerically stable for nearly (anti)parallel unit vectors.
    const double dot = Dot(a, b);
    if (dot < 0) return kPiD - 2 * std::asin(std::min(1.0, Length(a + b) / 2));
    return 2 * std::asin(std::min(1.0, Length(b - a) / 2));
}

// Smallest cone containing both (pbrt-v4's DirectionCone Union): theta_o spans both spreads
// and the angle between the axes; the axis rotated from a's towards b's by theta_o - theta_a.
Cone Union(const Cone& a, const Cone& b) {
    Cone c;
    c.theta_e = std::max(a.theta_e, b.theta_e);
    c.two_sided = a.two_sided || b.two_sided;
    const double theta_d = AngleBetween(a.axis, b.axis);
    if (std::min(theta_d + b.theta_o, kPiD) <= a.theta_o) {
        c.axis = a.axis;
        c.theta_o = a.theta_o;
        return c;
    }
    if (std::min(theta_d + a.theta_o, kPiD) <= b.theta_o) {
        c.axis = b.axis;
        c.theta_o = b.theta_o;
        return c;
    }
    const double theta_o = (a.theta_o + theta_d + b.theta_o) / 2;
    const Vec3d k = Cross(a.axis, b.axis);
    const double k_len = Length(k);
    if (theta_o >= kPiD || !(k_len > 0)) {
        c.theta_o = kPiD;
        return c;
    }
    const double theta_r = theta_o - a.theta_o;
    const Vec3d toward_b = Cross(k / k_len, a.axis);  // unit, perpendicular to a, in the plane of a and b
    c.axis = Normalize(a.axis * std::cos(theta_r) + toward_b * std::sin(theta_r));
    c.theta_o = theta_o;
    return c;
}

// The solid-angle measure of a cone's emission, M_Omega (Conty Estevez & Kulla, eq. 1):
// 2 pi (1 - cos theta_o) + pi/2 (2 theta_w sin theta_o - cos(theta_o - 2 theta_w)
// - 2 theta_o sin theta_o + cos theta_o), theta_w = min(theta_o + theta_e, pi).
double OrientationMeasure(double theta_o, double theta_e) {
    const double theta_w = std::min(theta_o + theta_e, kPiD);
    const double cos_o = std::cos(theta_o), sin_o = std::sin(theta_o);
    return 2 * kPiD * (1 - cos_o) +
           kPiD / 2 * (2 * theta_w * sin_o - std::cos(theta_o - 2 * theta_w) - 2 * theta_o * sin_o + cos_o);
}

// ---- Boxes ----

struct Box {
    Vec3f lo{FLT_MAX, FLT_MAX, FLT_MAX}, hi{-FLT_MAX, -FLT_MAX, -FLT_MAX};
    void Grow(const Vec3f& l, const Vec3f& h) {
        lo = {std::min(lo.x, l.x), std::min(lo.y, l.y), std::min(lo.z, l.z)};
        hi = {std::max(hi.x, h.x), std::max(hi.y, h.y), std::max(hi.z, h.z)};
    }
    void Grow(const Box& b) { Grow(b.lo, b.hi); }
    bool Valid() const { return lo.x <= hi.x; }
    Vec3f Extent() const { return hi - lo; }
};

// The split cost's area term: surface area, plus a small multiple of the squared diagonal so
// that flat and linear sets of emitters (lights on a line, points) still prefer tight groups.
float AreaMeasure(const Box& b) {
    if (!b.Valid()) return 0;
    const Vec3f e = b.Extent();
    return 2 * (e.x * e.y + e.y * e.z + e.z * e.x) + 1e-3 * Dot(e, e);
}

// ---- Build ----

// An emitter during the build, with what the split cost needs of its cone (contiguous, so the
// binning reads no other array).
struct BuildItem {
    Vec3f lo, hi, centroid;
    float power;  // of the tree's total
    Vec3f axis;
    float theta_o, theta_e;
    uint32_t emitter;
    bool two_sided;
};

// A bucket of the binned split: box, power and what estimates its cone (the sum of its unit
// axes and the widest theta_o, theta_e; the node's real cone is the children's exact union).
struct Bucket {
    Box box;
    float power;
    Vec3f axis_sum;
    int count;
    float theta_o, theta_e;
    bool two_sided;

    static Bucket Empty() { return {Box(), 0, Vec3f(), 0, 0, 0, false}; }

    void Add(const BuildItem& it) {
        box.Grow(it.lo, it.hi);
        power += it.power;
        axis_sum += it.axis;
        count += 1;
        theta_o = std::max(theta_o, it.theta_o);
        theta_e = std::max(theta_e, it.theta_e);
        two_sided = two_sided || it.two_sided;
    }

    void Add(const Bucket& b) {
        box.Grow(b.box);
        power += b.power;
        axis_sum += b.axis_sum;
        count += b.count;
        theta_o = std::max(theta_o, b.theta_o);
        theta_e = std::max(theta_e, b.theta_e);
        two_sided = two_sided || b.two_sided;
    }
    // power * M_Omega * area, the cone's spread estimated from the axes' mean resultant length
    // r: 2 acos(r) (0 for equal axes, pi for opposite or scattered ones), approximated by
    // pi sqrt(1 - r) (exact at both ends, 11% wide near r = 1), then rounded up to a multiple of
    // pi/256 so that the cached measure is found again.
    template <class Measure>
    double Cost(Measure& orientation_measure) const {
        if (count == 0) return 0;
        const float resultant = std::min(1.0f, Length(axis_sum) / float(count));
        const float spread = std::min(float(kPiD), float(kPiD) * std::sqrt(1 - resultant) + theta_o);
        const float step = float(kPiD) / 256;
        const double m = orientation_measure(std::ceil(spread / step) * step, theta_e) * (two_sided ? 2 : 1);
        return power * m * AreaMeasure(box);
    }
};

// OrientationMeasure with the last few arguments remembered: lights of a scene share few
// cones (a ceiling of panels facing down), so most split candidates repeat them.
class CachedOrientationMeasure {
  public:
    double operator()(float theta_o, float theta_e) {
        for (const Entry& e : entries_)
            if (e.theta_o == theta_o && e.theta_e == theta_e) return e.measure;
        Entry& e = entries_[next_++ % kEntries];
        e = {theta_o, theta_e, OrientationMeasure(theta_o, theta_e)};
        return e.measure;
    }

  private:
    struct Entry {
        float theta_o = -1, theta_e = -1;
        double measure = 0;
    };
    static constexpr int kEntries = 8;
    Entry entries_[kEntries];
    unsigned next_ = 0;
};

constexpr int kBuckets = 12;

struct NodeBounds {
    Box box;
    Cone cone;
    double power = 0;
};

// The boxes of a set of items: of their bounds (the node's box) and of their centroids (what
// the binning cuts).
struct ItemExtent {
    Box box, centroids;
    void Grow(const BuildItem& it) {
        box.Grow(it.lo, it.hi);
        centroids.Grow(it.centroid, it.centroid);
    }
};

ItemExtent ExtentOf(const std::vector<BuildItem>& items, size_t begin, size_t end) {
    ItemExtent e;
    for (size_t i = begin; i < end; ++i) e.Grow(items[i]);
    return e;
}

// Nodes with more items than this bin a regular subsample of kBinnedSample of them (the cost
// only compares candidate planes); the partition itself moves every item.
constexpr size_t kBinnedSample = 16384;
constexpr size_t kSmallNode = 4;
constexpr size_t kAllAxesNode = 1024;

// Nodes with at least this many items build their two subtrees on two threads while threads
// remain (LightTree::Build's `threads`).
constexpr size_t kParallelNode = 1 << 15;

class Builder {
  public:
    Builder(std::vector<BuildItem>& items, std::vector<LightTreeNode>& nodes, std::vector<uint64_t>& trails)
        : items_(items), nodes_(nodes), trails_(trails) {}

    // Builds node `index` over items [begin, end), its descendants in nodes [first_free,
    // first_free + 2 (end - begin) - 2): its two children side by side at first_free (traversal
    // reads both from neighbouring memory), then the left child's descendants, then the right's.
    // That is the order a depth-first build would allocate them in, fixed by the item counts
    // alone, so that subtrees built on other threads (up to `threads` in all) give the same tree.
    NodeBounds Build(uint32_t index, size_t begin, size_t end, const ItemExtent& extent, int depth, uint64_t trail,
                     uint32_t first_free, int threads) {
        max_depth_ = std::max(max_depth_, depth);
        NodeBounds nb;
        if (end - begin == 1) {
            const BuildItem& it = items_[begin];
            nb.box.Grow(it.lo, it.hi);
            nb.cone = ConeOf(it);
            nb.power = it.power;
            trails_[it.emitter] = trail;
            Store(index, nb, LightTreeNode::kLeaf, it.emitter);
            return nb;
        }
        ItemExtent left_extent, right_extent;
        const size_t mid = Split(begin, end, extent, depth, left_extent, right_extent);
        const uint32_t children = first_free;
        const uint32_t left_free = children + 2, right_free = left_free + 2 * uint32_t(mid - begin) - 2;
        const uint64_t right_trail = trail | (uint64_t(1) << depth);
        NodeBounds left, right;
        std::thread left_thread;
        std::optional<Builder> left_builder;  // its own scratch; disjoint items, nodes, trails
        if (threads > 1 && end - begin >= kParallelNode) {
            const int left_threads = threads / 2;
            left_builder.emplace(items_, nodes_, trails_);
            try {
                left_thread = std::thread([&] {
                    left = left_builder->Build(children, begin, mid, left_extent, depth + 1, trail, left_free,
                                               left_threads);
                });
            } catch (const std::system_error&) {  // no thread to be had: build it here
            }
        }
        if (left_thread.joinable()) {
            right =
                Build(children + 1, mid, end, right_extent, depth + 1, right_trail, right_free, threads - threads / 2);
            left_thread.join();
            max_depth_ = std::max(max_depth_, left_builder->max_depth_);
        } else {
            left = Build(children, begin, mid, left_extent, depth + 1, trail, left_free, 1);
            right = Build(children + 1, mid, end, right_extent, depth + 1, right_trail, right_free, 1);
        }
        nb.box = left.box;
        nb.box.Grow(right.box);
        nb.cone = Union(left.cone, right.cone);
        nb.power = left.power + right.power;
        Store(index, nb, 0, children);
        return nb;
    }

    int MaxDepth() const { return max_depth_; }

  private:
    // Where [begin, end) is cut, with the two halves' extents: the binned SAOH's best plane over
    // the three axes (n / 2 buckets up to kBuckets), or the middle by count along the widest
    // axis of the centroids (at most kSmallNode items, where the candidates' costs would cost
    // more than the rest of the build; coincident centroids; no plane separating the binned
    // sample; deeper than kLightTreeBinnedDepth).
    size_t Split(size_t begin, size_t end, const ItemExtent& extent, int depth, ItemExtent& left, ItemExtent& right) {
        const Vec3f ce = extent.centroids.Extent();
        const Vec3f be = extent.box.Extent();
        const int widest = ce.x >= ce.y && ce.x >= ce.z ? 0 : (ce.y >= ce.z ? 1 : 2);
        const size_t n = end - begin;
        if (depth < kLightTreeBinnedDepth && ce[widest] > 0 && n > kSmallNode) {
            const int buckets = int(std::min<size_t>(kBuckets, n / 2));
            const Vec3f clo = extent.centroids.lo;
            // Small nodes bin only their widest axis (the binning and the sweeps are most of the
            // build, and nodes are mostly small); larger ones all three.
            bool binned[3];
            for (int dim = 0; dim < 3; ++dim) binned[dim] = ce[dim] > 0 && (n > kAllAxesNode || dim == widest);
            Bucket(&bins)[3][kBuckets] = bins_;  // only the `buckets` used are cleared
            for (int dim = 0; dim < 3; ++dim) std::fill_n(bins[dim], buckets, Bucket::Empty());
            const size_t stride = n > kBinnedSample ? n / kBinnedSample : 1;
            const Vec3f scale(buckets / ce.x, buckets / ce.y, buckets / ce.z);
            for (size_t i = begin; i < end; i += stride) {
                const BuildItem& it = items_[i];
                for (int dim = 0; dim < 3; ++dim)
                    if (binned[dim]) bins[dim][BucketOf(it.centroid[dim], clo[dim], scale[dim], buckets)].Add(it);
            }
            double best_cost = INFINITY;
            int best_dim = -1, best_cut = 0;
            const float max_extent = std::max({be.x, be.y, be.z});
            for (int dim = 0; dim < 3; ++dim) {
                if (!binned[dim]) continue;
                // Cost of cutting after bucket k: prefix and suffix sweeps.
                double below[kBuckets];
                Bucket acc = Bucket::Empty();
                for (int k = 0; k < buckets - 1; ++k) {
                    acc.Add(bins[dim][k]);
                    below[k] = acc.count > 0 ? acc.Cost(measure_) : -1;
                }
                Bucket above = Bucket::Empty();
                const double regularize = be[dim] > 0 ? max_extent / be[dim] : 1;  // pbrt's K_r: thin boxes
                for (int k = buckets - 2; k >= 0; --k) {
                    above.Add(bins[dim][k + 1]);
                    if (below[k] < 0 || above.count == 0) continue;
                    const double cost = (below[k] + above.Cost(measure_)) * regularize;
                    if (cost < best_cost) {
                        best_cost = cost;
                        best_dim = dim;
                        best_cut = k;
                    }
                }
            }
            if (best_dim >= 0) {
                const float lo = clo[best_dim], dim_scale = scale[best_dim];
                const size_t mid = Partition(begin, end, left, right, [&](const BuildItem& it) {
                    return BucketOf(it.centroid[best_dim], lo, dim_scale, buckets) <= best_cut;
                });
                if (mid > begin && mid < end) return mid;
            }
        }
        const size_t mid = begin + n / 2;
        if (ce[widest] > 0)
            std::nth_element(
                items_.begin() + begin, items_.begin() + mid, items_.begin() + end,
                [&](const BuildItem& a, const BuildItem& b) { return a.centroid[widest] < b.centroid[widest]; });
        left = ExtentOf(items_, begin, mid);
        right = ExtentOf(items_, mid, end);
        return mid;
    }

    // std::partition that also grows each side's extent: every item is tested once.
    template <class GoesLeft>
    size_t Partition(size_t begin, size_t end, ItemExtent& left, ItemExtent& right, const GoesLeft& goes_left) {
        left = right = ItemExtent();
        size_t i = begin, j = end;
        for (;;) {
            while (i < j && goes_left(items_[i])) left.Grow(items_[i++]);
            while (i < j && !goes_left(items_[j - 1])) right.Grow(items_[--j]);
            if (i >= j) return i;
            std::swap(items_[i], items_[j - 1]);  // items_[i] goes right, items_[j - 1] left: swapped
            left.Grow(items_[i++]);
            right.Grow(items_[--j]);
        }
    }

    // Bucket of centroid coordinate c: floor((c - lo) * buckets / extent), clamped.
    static int BucketOf(float c, float lo, float scale, int buckets) {
        return std::clamp(int((c - lo) * scale), 0, buckets - 1);
    }
    // The leaf's cone, from the item's copy (float; the stored cone's padding covers the rounding).
    static Cone ConeOf(const BuildItem& it) {
        Cone c;
        c.axis = Normalize(Vec3d(it.axis));
        c.theta_o = it.theta_o;
        c.theta_e = it.theta_e;
        c.two_sided = it.two_sided;
        return c;
    }

    // The node as traversal reads it, padded outwards: the sphere by a relative 2^-12 of its
    // radius and 2^-20 of the box's coordinates, the cone's angles by 1e-6 rad, the cosines
    // rounded towards the wider cone.
    void Store(uint32_t index, const NodeBounds& nb, uint32_t flags, uint32_t child_or_emitter) {
        LightTreeNode& node = nodes_[index];
        const Vec3f lo = nb.box.lo, hi = nb.box.hi;
        node.center = (lo + hi) * 0.5f;
        const float coord = std::max(MaxAbsComponent(lo), MaxAbsComponent(hi));
        node.radius = 0.5f * Length(hi - lo) * (1 + 0x1p-12f) + coord * 0x1p-20f + FLT_MIN;
        node.axis = Vec3f(nb.cone.axis);
        node.cos_theta_o = WiderCos(nb.cone.theta_o);
        node.cos_theta_e = WiderCos(nb.cone.theta_e);
        node.power = std::max(float(nb.power), kSmallestImportance);
        node.child_or_emitter = child_or_emitter;
        node.flags = flags | (nb.cone.two_sided ? LightTreeNode::kTwoSided : 0);
    }
    static float WiderCos(double theta) {
        if (theta >= kPiD) return -1;
        return std::max(-1.0f, std::nextafter(float(std::cos(std::min(kPiD, theta + 1e-6))), -2.0f));
    }

    std::vector<BuildItem>& items_;
    std::vector<LightTreeNode>& nodes_;
    std::vector<uint64_t>& trails_;
    CachedOrientationMeasure measure_;
    Bucket bins_[3][kBuckets];  // Split's scratch (Split returns before the recursion goes on)
    int max_depth_ = 0;
};

[[noreturn]] void Reject(size_t i, const std::string& what) {
    throw std::invalid_argument("LightTree: emitter " + std::to_string(i) + ": " + what);
}

void Validate(const LightBounds& b, size_t i) {
    if (!IsFinite(b.lo) || !IsFinite(b.hi)) Reject(i, "bounds not finite (NaN or infinite coordinates)");
    if (!(b.lo.x <= b.hi.x && b.lo.y <= b.hi.y && b.lo.z <= b.hi.z)) Reject(i, "bounds with lo > hi");
    if (!std::isfinite(b.power)) Reject(i, "power not finite");
    if (b.power < 0) Reject(i, "negative power");
    if (!(std::isfinite(b.cos_theta_o) && std::isfinite(b.cos_theta_e))) Reject(i, "cone angles not finite");
    if (b.cos_theta_o > -1 && (!IsFinite(b.axis) || !(Dot(b.axis, b.axis) > 0)))
        Reject(i, "cone axis zero or not finite");
}

}  // namespace

void LightTree::Build(const std::vector<LightBounds>& emitters, int threads) {
    nodes_.clear();
    depth_ = 0;
    if (emitters.size() > size_t(kMaxLightTreeEmitters))
        throw std::invalid_argument("LightTree: " + std::to_string(emitters.size()) + " emitters, more than " +
                                    std::to_string(kMaxLightTreeEmitters));
    trails_.assign(emitters.size(), kNotInTree);
    flux_ = {};
    flux_share_ = 0;
    double total = 0;
    for (size_t i = 0; i < emitters.size(); ++i) {
        Validate(emitters[i], i);
        total += emitters[i].power;
    }
    if (!(total > 0)) return;
    std::vector<double> flux(emitters.size());
    for (size_t i = 0; i < emitters.size(); ++i) flux[i] = EmitterFlux(emitters[i]);
    flux_.Build(flux);
    flux_share_ = std::count_if(emitters.begin(), emitters.end(), [](const LightBounds& b) { return b.power > 0; }) > 1
                      ? kTreeFluxShare
                      : 0.0f;

    std::vector<BuildItem> items;
    items.reserve(emitters.size());
    for (size_t i = 0; i < emitters.size(); ++i) {
        const LightBounds& b = emitters[i];
        if (!(b.power > 0)) continue;
        Cone c;
        const bool sphere = b.cos_theta_o <= -1;
        c.axis = sphere ? Vec3d(0, 0, 1) : Normalize(Vec3d(b.axis));
        c.theta_o = sphere ? kPiD : std::acos(std::clamp(double(b.cos_theta_o), -1.0, 1.0));
        c.theta_e = std::acos(std::clamp(double(b.cos_theta_e), -1.0, 1.0));
        c.two_sided = b.two_sided;
        items.push_back({b.lo, b.hi, (b.lo + b.hi) * 0.5f, float(b.power / total), Vec3f(c.axis), float(c.theta_o),
                         float(c.theta_e), uint32_t(i), c.two_sided});
    }
    nodes_.assign(2 * items.size() - 1, LightTreeNode());
    if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
    Builder builder(items, nodes_, trails_);
    builder.Build(0, 0, items.size(), ExtentOf(items, 0, items.size()), 0, 0, 1, threads);
    depth_ = builder.MaxDepth();
}

}  // namespace sphrect::render
