// Light tree (render/light_tree.h): pmfs sum to 1, sampling frequencies match PMF (chi-square),
// LightTreeAt's memoised Sample and PMF equal the tree's bit for bit,
// PMF > 0 for every emitter that can light the point, and degenerate input.
//
// Statistics: fixed seeds.  The chi-square tests share a suite-wide false-failure rate of 1e-4,
// Sidak-corrected over the kChi2Tests configurations (per test alpha = 1 - (1 - 1e-4)^(1/m)), with
// the threshold from the Wilson-Hilferty approximation of the chi-square quantile.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/rng.h"
#include "render/light_tree.h"
#include "simd_targets.h"

namespace sphrect::render {
namespace {

Vec3f RandomUnit(std::mt19937& g) {
    std::normal_distribution<float> n;
    for (;;) {
        const Vec3f v(n(g), n(g), n(g));
        const float l = Length(v);
        if (l > 1e-3f) return v / l;
    }
}

// A scene of every emitter kind: rectangles and ellipses (random orientation, one- and
// two-sided), point and spot lights, mesh triangles, powers over four decades, in a 20 m box.
struct Emitters {
    std::vector<AreaLight> area;
    std::vector<DeltaLight> delta;
    TreeEmitters tree;
};

Emitters MixedScene(int n, uint32_t seed) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<float> u(0, 1);
    Emitters e;
    for (int i = 0; i < n; ++i) {
        const Vec3f c(20 * u(g) - 10, 20 * u(g) - 10, 20 * u(g) - 10);
        const Spectrum radiance = Spectrum(1, 1, 1) * std::pow(10.0f, 4 * u(g) - 2);
        const int kind = int(5 * u(g));
        if (kind == 4) {
            const Vec3f a = RandomUnit(g) * (0.05f + u(g)), b = RandomUnit(g) * (0.05f + u(g));
            e.area.push_back(MakeTriangleAreaLight(c, c + a, c + b, radiance));
        } else if (kind <= 1) {
            const Vec3f nrm = RandomUnit(g);
            const Vec3f a = Normalize(Cross(nrm, RandomUnit(g))) * (0.05f + u(g));
            const Vec3f b = Normalize(Cross(nrm, a)) * (0.05f + u(g));
            const bool two_sided = u(g) < 0.3f;
            e.area.push_back(kind == 0 ? MakeRectAreaLight(c - a * 0.5f - b * 0.5f, a, b, radiance, two_sided, true)
                                       : MakeEllipseAreaLight(c, a, b, radiance, two_sided, true));
        } else {
            DeltaLight d;
            d.kind = kind == 2 ? DeltaKind::Point : DeltaKind::Spot;
            d.position = c;
            d.power = radiance;
            d.axis = RandomUnit(g);
            d.cos_half_angle = std::cos(0.1f + 1.4f * u(g));
            e.delta.push_back(d);
        }
    }
    e.tree = CollectTreeEmitters(e.area, e.delta, true);
    return e;
}

// Can emitter i light the receiver (p, n)?  Area lights: some point of a 16 x 16 grid on the
// light is above the receiver's horizon and (one-sided) p in front of the light; delta lights:
// IlluminateFromDelta is non-zero and above the horizon.  n = 0: no horizon.
bool CanLight(const Emitters& e, int i, const Vec3f& p, const Vec3f& n) {
    const TreeEmitterRef ref = e.tree.refs[i];
    const bool has_normal = n.x != 0 || n.y != 0 || n.z != 0;
    if (ref.kind == TreeEmitterKind::Delta) {
        const DeltaIllumination di = IlluminateFromDelta(e.delta[ref.index], p, {});
        return !IsBlack(di.li) && (!has_normal || Dot(di.wi, n) > 0);
    }
    const AreaLight& l = e.area[ref.index];
    if (!l.two_sided && Dot(l.n, p - l.center) <= 0) return false;
    for (int a = 0; a < 16; ++a)
        for (int b = 0; b < 16; ++b) {
            const float s = (a + 0.5f) / 16, t = (b + 0.5f) / 16;
            Vec3f q;
            if (l.shape == AreaShape::Rectangle) {
                q = l.frame.light.corner + l.frame.light.ex * s + l.frame.light.ey * t;
            } else if (l.shape == AreaShape::Triangle) {
                q = l.v0 + l.e1 * (s * (1 - t)) + l.e2 * (s * t);  // covers the triangle
            } else {
                const Point2<float> d = SampleUniformDiskConcentric({s, t});
                q = l.center + l.ax * d.u + l.ay * d.v;
            }
            if (!has_normal || Dot(q - p, n) > 0) return true;
        }
    return false;
}

struct Receiver {
    Vec3f p, n;
};

std::vector<Receiver> RandomReceivers(int count, uint32_t seed, bool with_normal) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<Receiver> r;
    for (int i = 0; i < count; ++i)
        r.push_back(
            {Vec3f(24 * u(g) - 12, 24 * u(g) - 12, 24 * u(g) - 12), with_normal ? RandomUnit(g) : Vec3f(0, 0, 0)});
    return r;
}

double PMFSum(const LightTree& tree, const Receiver& r) {
    double sum = 0;
    for (int i = 0; i < tree.NumEmitters(); ++i) sum += tree.PMF(r.p, r.n, i);
    return sum;
}

// Subtrees of kParallelNode items or more are built on threads of their own: the tree is the same
// node for node (bytes) and pmf for pmf whatever the thread count.
TEST(LightTree, SameTreeOnAnyNumberOfThreads) {
    const Emitters e = MixedScene(150000, 77);
    LightTree one, many;
    one.Build(e.tree.bounds, 1);
    many.Build(e.tree.bounds, 4);
    ASSERT_EQ(one.NumNodes(), many.NumNodes());
    ASSERT_GT(one.NumNodes(), 1 << 17);
    EXPECT_EQ(one.Depth(), many.Depth());
    EXPECT_EQ(0, std::memcmp(one.Nodes().data(), many.Nodes().data(), one.Nodes().size() * sizeof(LightTreeNode)));
    for (const Receiver& r : RandomReceivers(50, 5, true))
        for (int i = 0; i < one.NumEmitters(); i += 997) EXPECT_EQ(one.PMF(r.p, r.n, i), many.PMF(r.p, r.n, i));
}

TEST(LightTree, PMFsSumToOneWithAndWithoutNormal) {
    const Emitters e = MixedScene(300, 1);
    LightTree tree;
    tree.Build(e.tree.bounds);
    ASSERT_EQ(tree.NumEmitters(), 300);
    EXPECT_LE(tree.Depth(), kLightTreeMaxDepth);
    for (const bool with_normal : {true, false})
        for (const Receiver& r : RandomReceivers(200, 2, with_normal)) {
            const double sum = PMFSum(tree, r);
            // Nothing can light p only when the root's importance is 0: then every pmf is 0.
            if (tree.Sample(r.p, r.n, 0.5f).emitter < 0)
                EXPECT_EQ(sum, 0);
            else
                EXPECT_NEAR(sum, 1.0, 1e-4) << "p " << r.p.x << " " << r.p.y << " " << r.p.z;
        }
}

TEST(LightTree, SampledPMFIsPMFAndURescaled) {
    const Emitters e = MixedScene(300, 3);
    LightTree tree;
    tree.Build(e.tree.bounds);
    PCG32 rng(7);
    for (const Receiver& r : RandomReceivers(50, 4, true))
        for (int k = 0; k < 100; ++k) {
            const LightTreeSample s = tree.Sample(r.p, r.n, BitsToUnitFloat(rng.NextU32()));
            if (s.emitter < 0) continue;
            EXPECT_GT(s.pmf, 0);
            EXPECT_EQ(s.pmf, tree.PMF(r.p, r.n, s.emitter));
            EXPECT_GE(s.u, 0);
            EXPECT_LT(s.u, 1);
        }
    // The rescaled u of the picks of one emitter, from a fine grid of u, spread over [0,1).
    const Receiver r = RandomReceivers(1, 5, true)[0];
    constexpr int kGrid = 1 << 16;
    std::vector<std::vector<float>> rescaled(tree.NumEmitters());
    for (int k = 0; k < kGrid; ++k) {
        const LightTreeSample s = tree.Sample(r.p, r.n, (k + 0.5f) / kGrid);
        if (s.emitter >= 0) rescaled[s.emitter].push_back(s.u);
    }
    int checked = 0;
    for (const std::vector<float>& us : rescaled) {
        if (us.size() < 200) continue;
        ++checked;
        const auto [lo, hi] = std::minmax_element(us.begin(), us.end());
        double mean = 0;
        for (float x : us) mean += x;
        mean /= us.size();
        const double cell = 1.0 / us.size();  // the grid's step in the rescaled u
        EXPECT_LT(*lo, 2 * cell);
        EXPECT_GT(*hi, 1 - 2 * cell);
        EXPECT_NEAR(mean, 0.5, 2 * cell);
    }
    EXPECT_GT(checked, 0);
}

// Upper alpha-quantile of chi-square with k degrees of freedom (Wilson-Hilferty).
double Chi2Threshold(int k, double alpha) {
    // Normal quantile z with P(Z > z) = alpha, by bisection on erfc.
    double lo = 0, hi = 40;
    for (int i = 0; i < 200; ++i) {
        const double mid = (lo + hi) / 2;
        (0.5 * std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
    }
    const double z = lo, h = 2.0 / (9 * k);
    return k * std::pow(1 - h + z * std::sqrt(h), 3);
}

constexpr int kChi2Tests = 12;

// LightTreeAt memoises each node's child probability per receiver: its Sample and PMF must be
// LightTree's, bit for bit, whatever the order of the calls, on trees that fit its memo (4
// emitters) and that overflow it (300: nodes share slots), with and without a normal.
TEST(LightTree, AtReceiverMatchesTreeExactly) {
    for (const int n : {1, 4, 300}) {
        const Emitters e = MixedScene(n, 11);
        LightTree tree;
        tree.Build(e.tree.bounds);
        PCG32 rng(13);
        int sampled = 0;
        for (const bool memoize : {true, false})
            for (const bool with_normal : {true, false})
                for (const Receiver& r : RandomReceivers(100, 17, with_normal)) {
                    LightTreeAt at(tree, r.p, r.n, memoize);
                    for (int k = 0; k < 16; ++k) {
                        const float u = BitsToUnitFloat(rng.NextU32());
                        const LightTreeSample a = at.Sample(u), b = tree.Sample(r.p, r.n, u);
                        EXPECT_EQ(a.emitter, b.emitter);
                        EXPECT_EQ(a.pmf, b.pmf);
                        EXPECT_EQ(a.u, b.u);
                        sampled += a.emitter >= 0;
                        const int emitter = int(rng.NextU32() % uint32_t(n + 1)) - (k == 0);  // -1 and n too
                        EXPECT_EQ(at.PMF(emitter), tree.PMF(r.p, r.n, emitter)) << "emitter " << emitter;
                    }
                }
        EXPECT_GT(sampled, 0) << n << " emitters";
    }
}

TEST(LightTree, PickFrequenciesMatchPMF) {
    const Emitters e = MixedScene(120, 6);
    LightTree tree;
    tree.Build(e.tree.bounds);
    const double alpha = 1 - std::pow(1 - 1e-4, 1.0 / kChi2Tests);
    std::vector<Receiver> receivers = RandomReceivers(kChi2Tests / 2, 8, true);
    for (const Receiver& r : RandomReceivers(kChi2Tests / 2, 9, false)) receivers.push_back(r);
    ASSERT_EQ(int(receivers.size()), kChi2Tests);
    constexpr int kDraws = 200000;
    PCG32 rng(11);
    for (const Receiver& r : receivers) {
        std::vector<int> counts(tree.NumEmitters() + 1, 0);  // last: no emitter
        for (int k = 0; k < kDraws; ++k) {
            const LightTreeSample s = tree.Sample(r.p, r.n, BitsToUnitFloat(rng.NextU32()));
            ++counts[s.emitter < 0 ? tree.NumEmitters() : s.emitter];
        }
        // Pearson's statistic; cells expecting fewer than 5 pooled into one.
        double chi2 = 0, pooled_expected = 0, pooled_observed = 0;
        int cells = 0;
        for (int i = 0; i < tree.NumEmitters(); ++i) {
            const double expected = kDraws * double(tree.PMF(r.p, r.n, i));
            if (expected == 0) {
                EXPECT_EQ(counts[i], 0) << "emitter " << i << " picked with PMF 0";
                continue;
            }
            if (expected < 5) {
                pooled_expected += expected;
                pooled_observed += counts[i];
                continue;
            }
            chi2 += (counts[i] - expected) * (counts[i] - expected) / expected;
            ++cells;
        }
        if (pooled_expected > 0) {
            chi2 += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) /
                    std::max(pooled_expected, 5.0);
            ++cells;
        }
        if (cells < 2) continue;
        EXPECT_LT(chi2, Chi2Threshold(cells - 1, alpha)) << "cells " << cells;
    }
}

// The defensive mixture (kTreeFluxShare): wherever the tree can light a receiver, no emitter's pmf falls below the
// share times its flux pmf -- the bound that keeps a light sample's second moment within 1 / share of power
// selection's -- and a single emitter is not mixed (its pmf stays 1).
TEST(LightTree, NoEmitterFallsBelowItsShareOfFlux) {
    const Emitters e = MixedScene(300, 23);
    LightTree tree;
    tree.Build(e.tree.bounds);
    double total_flux = 0;
    for (const LightBounds& b : e.tree.bounds) total_flux += EmitterFlux(b);
    int checked = 0;
    for (const bool with_normal : {true, false})
        for (const Receiver& r : RandomReceivers(200, 29, with_normal)) {
            if (!(tree.PMF(r.p, r.n, tree.Sample(r.p, r.n, 0.5f).emitter) > 0)) continue;  // nothing can light r
            for (int i = 0; i < tree.NumEmitters(); ++i) {
                const double floor = kTreeFluxShare * EmitterFlux(e.tree.bounds[size_t(i)]) / total_flux;
                EXPECT_GE(tree.PMF(r.p, r.n, i), floor * (1 - 1e-5)) << i;
                ++checked;
            }
        }
    EXPECT_GT(checked, 10000);

    const Emitters one = MixedScene(1, 3);
    LightTree single;
    single.Build(CollectTreeEmitters(one.area, one.delta, true).bounds);
    const LightTreeSample s = single.Sample({0, 0, 0}, {}, 0.7f);
    ASSERT_EQ(s.emitter, 0);
    EXPECT_EQ(s.pmf, 1.0f);
    EXPECT_EQ(s.u, 0.7f);
}

TEST(LightTree, PMFPositiveForEveryEmitterThatCanLight) {
    const Emitters e = MixedScene(200, 12);
    LightTree tree;
    tree.Build(e.tree.bounds);
    int lit = 0;
    for (const bool with_normal : {true, false})
        for (const Receiver& r : RandomReceivers(100, 13, with_normal))
            for (int i = 0; i < tree.NumEmitters(); ++i)
                if (CanLight(e, i, r.p, r.n)) {
                    ++lit;
                    EXPECT_GT(tree.PMF(r.p, r.n, i), 0) << "emitter " << i;
                }
    EXPECT_GT(lit, 1000);
    // Near field: receivers within 0.3 m of an emitter's centre (inside node bounding spheres).
    std::mt19937 g(21);
    std::uniform_real_distribution<float> u(-0.3f, 0.3f);
    int near_lit = 0;
    for (int k = 0; k < 400; ++k) {
        const LightBounds& b = e.tree.bounds[k % e.tree.bounds.size()];
        const Receiver r{(b.lo + b.hi) * 0.5f + Vec3f(u(g), u(g), u(g)), k % 2 ? RandomUnit(g) : Vec3f(0, 0, 0)};
        for (int i = 0; i < tree.NumEmitters(); ++i)
            if (CanLight(e, i, r.p, r.n)) {
                ++near_lit;
                EXPECT_GT(tree.PMF(r.p, r.n, i), 0) << "emitter " << i << " near " << k;
            }
    }
    EXPECT_GT(near_lit, 1000);
}

TEST(LightTree, ZeroOnlyWhereNothingCanLight) {
    // A one-sided rectangle facing +z at z = 0: nothing below it, everything above.
    const AreaLight l = MakeRectAreaLight({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, {1, 1, 1}, false, true);
    LightTree tree;
    tree.Build({AreaLightBounds(l)});
    EXPECT_EQ(tree.PMF({0, 0, 1}, {0, 0, -1}, 0), 1.0f);
    EXPECT_EQ(tree.Sample({0, 0, 1}, {0, 0, -1}, 0.3f).pmf, 1.0f);
    EXPECT_EQ(tree.PMF({0, 0, -2}, {0, 0, 1}, 0), 0.0f);  // behind the light
    EXPECT_EQ(tree.Sample({0, 0, -2}, {0, 0, 1}, 0.3f).emitter, -1);
    // Within the node's bounding sphere (radius sqrt 2) every direction counts as possible:
    // conservative, so even just behind the light the pmf stays 1.
    EXPECT_EQ(tree.PMF({0, 0, -1}, {0, 0, 1}, 0), 1.0f);
    EXPECT_EQ(tree.PMF({0, 0, 3}, {0, 0, 1}, 0), 0.0f);      // light below the horizon
    EXPECT_EQ(tree.PMF({5, 0, 0.01f}, {0, 0, 0}, 0), 1.0f);  // grazing, in a medium
    // A spot's cone: lit inside, not outside.
    DeltaLight spot;
    spot.kind = DeltaKind::Spot;
    spot.position = {0, 0, 0};
    spot.axis = {0, 0, -1};
    spot.power = {1, 1, 1};
    spot.cos_half_angle = std::cos(0.5f);
    LightBounds b;
    ASSERT_TRUE(DeltaLightBounds(spot, &b));
    tree.Build({b});
    EXPECT_EQ(tree.PMF({0.2f, 0, -1}, {0, 0, 1}, 0), 1.0f);
    EXPECT_EQ(tree.PMF({2, 0, -1}, {0, 0, 1}, 0), 0.0f);
}

TEST(LightTree, SingleEmitterOfEachKind) {
    const Emitters e = MixedScene(40, 14);
    for (size_t i = 0; i < e.tree.bounds.size(); ++i) {
        LightTree tree;
        tree.Build({e.tree.bounds[i]});
        ASSERT_EQ(tree.NumNodes(), 1);
        for (const Receiver& r : RandomReceivers(20, 15, true)) {
            const LightTreeSample s = tree.Sample(r.p, r.n, 0.7f);
            if (s.emitter < 0) {
                EXPECT_EQ(tree.PMF(r.p, r.n, 0), 0);
                continue;
            }
            EXPECT_EQ(s.emitter, 0);
            EXPECT_EQ(s.pmf, 1.0f);
            EXPECT_EQ(s.u, 0.7f);
        }
    }
}

TEST(LightTree, ZeroPowerEmittersStayOut) {
    Emitters e = MixedScene(50, 16);
    for (size_t i = 0; i < e.tree.bounds.size(); i += 3) e.tree.bounds[i].power = 0;
    LightTree tree;
    tree.Build(e.tree.bounds);
    for (const Receiver& r : RandomReceivers(30, 17, false)) {
        for (size_t i = 0; i < e.tree.bounds.size(); i += 3) EXPECT_EQ(tree.PMF(r.p, r.n, int(i)), 0);
        EXPECT_NEAR(PMFSum(tree, r), 1.0, 1e-4);
    }
    for (LightBounds& b : e.tree.bounds) b.power = 0;
    tree.Build(e.tree.bounds);
    EXPECT_TRUE(tree.Empty());
    EXPECT_EQ(tree.Sample({0, 0, 0}, {0, 0, 1}, 0.5f).emitter, -1);
    EXPECT_EQ(tree.PMF({0, 0, 0}, {0, 0, 1}, 0), 0);
    tree.Build({});
    EXPECT_TRUE(tree.Empty());
}

TEST(LightTree, CoincidentEmittersShareEqually) {
    // 1000 identical rectangles, and 1000 point lights at one point (zero-size bounds).
    const AreaLight l = MakeRectAreaLight({-1, -1, 2}, {2, 0, 0}, {0, 2, 0}, {1, 1, 1}, true, true);
    DeltaLight point;
    point.position = {1, 2, 3};
    point.power = {2, 2, 2};
    LightBounds pb;
    ASSERT_TRUE(DeltaLightBounds(point, &pb));
    for (const LightBounds& one : {AreaLightBounds(l), pb}) {
        const std::vector<LightBounds> same(1000, one);
        LightTree tree;
        tree.Build(same);
        EXPECT_LE(tree.Depth(), 10);
        for (const Receiver& r : RandomReceivers(10, 18, false)) {
            EXPECT_NEAR(PMFSum(tree, r), 1.0, 1e-4);
            EXPECT_NEAR(tree.PMF(r.p, r.n, 123), 1e-3, 1e-6);
        }
        // The receiver at the point lights' position itself.
        EXPECT_NEAR(PMFSum(tree, {one.lo, {0, 0, 1}}), 1.0, 1e-4);
    }
}

TEST(LightTree, LightsOnALineStayShallow) {
    // Zero-area cost terms (point lights on a line) must not degenerate into a chain.
    std::vector<LightBounds> line;
    for (int i = 0; i < 4096; ++i) {
        DeltaLight d;
        d.position = {float(i) * 0.01f, 0, 0};
        d.power = {1, 1, 1};
        LightBounds b;
        DeltaLightBounds(d, &b);
        line.push_back(b);
    }
    LightTree tree;
    tree.Build(line);
    EXPECT_LE(tree.Depth(), 40);
    EXPECT_NEAR(PMFSum(tree, {{20, 1, 0}, {0, 0, 0}}), 1.0, 1e-4);
}

TEST(LightTree, RejectsBadInputWithItsIndex) {
    const Emitters e = MixedScene(10, 19);
    auto expect_rejected = [&](auto spoil, const std::string& what) {
        std::vector<LightBounds> b = e.tree.bounds;
        spoil(b[3]);
        LightTree tree;
        try {
            tree.Build(b);
            ADD_FAILURE() << what << " accepted";
        } catch (const std::invalid_argument& ex) {
            EXPECT_NE(std::string(ex.what()).find("emitter 3"), std::string::npos) << ex.what();
        }
    };
    expect_rejected([](LightBounds& b) { b.lo.x = NAN; }, "NaN bounds");
    expect_rejected([](LightBounds& b) { b.hi.y = INFINITY; }, "infinite bounds");
    expect_rejected([](LightBounds& b) { b.power = NAN; }, "NaN power");
    expect_rejected([](LightBounds& b) { b.power = -1; }, "negative power");
    expect_rejected([](LightBounds& b) { b.cos_theta_o = NAN; }, "NaN cone");
    expect_rejected(
        [](LightBounds& b) {
            b.axis = {0, 0, 0};
            b.cos_theta_o = 1;
        },
        "zero axis");
    expect_rejected(
        [](LightBounds& b) {
            std::swap(b.lo, b.hi);
            b.hi.x -= 1;
        },
        "lo > hi");
}

// The tree's point: its choice follows the contributions better than power does.  On 1000 small
// down-facing lights at heights 1-3 over a plane, receivers on the plane: the relative second moment
// sum f^2/pmf / (sum f)^2 of the one-sample estimate of sum f, f = power cos_light cos_receiver / d^2
// at the light's centre, averaged over 32 receivers (deterministic: 2.03 for the tree, 42.8 for
// power when written).
TEST(LightTree, ChoiceFollowsContributionsBetterThanPower) {
    std::mt19937 g(22);
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<LightBounds> lights;
    double total_power = 0;
    for (int i = 0; i < 1000; ++i) {
        const float s = 0.05f + 0.15f * u(g), power = std::pow(10.0f, 2 * u(g));
        const Vec3f c(32 * u(g) - 16, 32 * u(g) - 16, 1 + 2 * u(g));
        lights.push_back(
            AreaLightBounds(MakeRectAreaLight(c, {0, s, 0}, {s, 0, 0}, Spectrum(1, 1, 1) * power, false, true)));
        total_power += lights.back().power;
    }
    LightTree tree;
    tree.Build(lights);
    double tree_moment = 0, power_moment = 0;
    const Vec3f up(0, 0, 1);
    for (int r = 0; r < 32; ++r) {
        const Vec3f p(32 * u(g) - 16, 32 * u(g) - 16, 0);
        double sum = 0, tree_sq = 0, power_sq = 0;
        for (int e = 0; e < int(lights.size()); ++e) {
            const Vec3f d = p - (lights[e].lo + lights[e].hi) * 0.5f;
            const double cos2 = double(d.z) * d.z / Dot(d, d);  // cos at the light times cos at p
            const double f = lights[e].power * cos2 / Dot(d, d);
            sum += f;
            tree_sq += f * f / tree.PMF(p, up, e);
            power_sq += f * f / (lights[e].power / total_power);
        }
        tree_moment += tree_sq / (sum * sum) / 32;
        power_moment += power_sq / (sum * sum) / 32;
    }
    EXPECT_LT(tree_moment, 0.25 * power_moment) << "tree " << tree_moment << " power " << power_moment;
    EXPECT_LT(tree_moment, 6);
}

TEST(LightTree, TriangleLightBounds) {
    const AreaLight t = MakeTriangleAreaLight({0, 0, 1}, {2, 0, 1}, {0, 1, 3}, {2, 2, 2});
    const LightBounds b = AreaLightBounds(t);
    EXPECT_EQ(b.lo.x, 0);
    EXPECT_EQ(b.hi.x, 2);
    EXPECT_EQ(b.hi.y, 1);
    EXPECT_EQ(b.lo.z, 1);
    EXPECT_EQ(b.hi.z, 3);
    EXPECT_NEAR(b.power, 2 * t.area, 1e-5);
    EXPECT_NEAR(Dot(b.axis, t.n), 1, 1e-6);
    EXPECT_EQ(b.two_sided, t.two_sided);
    // Degenerate (collinear) triangle: no power, stays out of the tree.
    const LightBounds d = TriangleLightBounds({0, 0, 0}, {1, 1, 1}, {2, 2, 2}, 1, true);
    EXPECT_EQ(d.power, 0);
    LightTree tree;
    tree.Build({d, b});
    EXPECT_EQ(tree.PMF({0.5f, 0.3f, 0}, {0, 0, 0}, 0), 0);
    EXPECT_EQ(tree.PMF({0.5f, 0.3f, 0}, {0, 0, 0}, 1), 1);
}

TEST(LightTree, SunIsNoTreeEmitter) {
    DeltaLight sun;
    sun.kind = DeltaKind::Sun;
    LightBounds b;
    EXPECT_FALSE(DeltaLightBounds(sun, &b));
    const TreeEmitters t = CollectTreeEmitters({}, {sun}, true);
    EXPECT_TRUE(t.bounds.empty());
}

// The batched descent (LightTree::SampleBatch, SIMD lanes) returns Sample's emitter, pmf and rescaled u bit for bit,
// with and without normals, receivers inside nodes' spheres included, on every instruction set: shading's PMF of a
// batched choice is then exactly its pmf (deterministic inputs: no false failures).
TEST(LightTree, SampleBatchEqualsSampleBitForBit) {
    for (int n : {1, 2, 37, 400}) {
        const Emitters e = MixedScene(n, 17 + uint32_t(n));
        LightTree tree;
        tree.Build(e.tree.bounds);
        std::vector<LightTreeReceiver> receivers;
        std::vector<float> u;
        std::mt19937 g(5);
        std::uniform_real_distribution<float> uniform(0, 1);
        for (bool with_normal : {false, true})
            for (const Receiver& r : RandomReceivers(300, 3 + uint32_t(n), with_normal)) {
                receivers.emplace_back(r.p, r.n);
                u.push_back(uniform(g));
            }
        // u at the ends and at the flux share's edge.
        for (float x : {0.0f, kTreeFluxShare, std::nextafter(kTreeFluxShare, 1.0f), kOneMinusEpsilonF}) {
            receivers.emplace_back(Vec3f(0.5f, 0.5f, 0.5f), Vec3f(0, 0, 1));
            u.push_back(x);
        }
        ForEachTarget([&] {
            std::vector<LightTreeSample> batch(receivers.size());
            tree.SampleBatch(receivers.data(), u.data(), receivers.size(), batch.data());
            for (size_t i = 0; i < receivers.size(); ++i) {
                const LightTreeSample ref = tree.Sample(receivers[i].p, receivers[i].n, u[i]);
                ASSERT_EQ(batch[i].emitter, ref.emitter) << n << " lights, request " << i;
                ASSERT_EQ(std::memcmp(&batch[i].pmf, &ref.pmf, sizeof(float)), 0) << batch[i].pmf << " " << ref.pmf;
                ASSERT_EQ(std::memcmp(&batch[i].u, &ref.u, sizeof(float)), 0) << batch[i].u << " " << ref.u;
            }
        });
    }
}

}  // namespace
}  // namespace sphrect::render
