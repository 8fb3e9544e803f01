// Light tree benchmarks (render/light_tree.h), on N random small lights over a plane: one-sided
// squares of side 0.05-0.2 facing down at heights 1-3 over a square of side sqrt(N) (about one
// light per square metre at any N), powers over two decades, every tenth a point light and every
// tenth a spot.  Receivers: points on the plane z = 0, normal +z.
//
//  BM_LightTreeBuild/<N>/<T>  Build of the tree from its LightBounds on T threads (wall-clock
//                          time: large subtrees build in parallel).  Counters: bytes_per_emitter
//                          (nodes + bit trails, LightTree::MemoryBytes() / N), depth.
//  BM_LightTreeSample/<N>  one Sample(p, n, u) per iteration (receivers and u cycled from tables).
//  BM_LightTreePMF/<N>     one PMF(p, n, emitter) per iteration (the emitter a Sample chose).
//  BM_LightTreeSelectionMoment/<N>  not a timing: the relative second moment of the light
//                          choice, tree against power (see below; 1 is the ideal).
//
// Times are CPU times (the benchmark library's default), 1 thread, except the build's.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "render/light_tree.h"

namespace sphrect::render {
namespace {

std::vector<LightBounds> LightsOverPlane(int n, uint32_t seed) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<float> u(0, 1);
    const float side = std::sqrt(float(n));
    std::vector<LightBounds> lights;
    lights.reserve(n);
    for (int i = 0; i < n; ++i) {
        const Vec3f c(side * (u(g) - 0.5f), side * (u(g) - 0.5f), 1 + 2 * u(g));
        const float power = std::pow(10.0f, 2 * u(g));
        if (i % 10 == 3 || i % 10 == 7) {
            DeltaLight d;
            d.kind = i % 10 == 3 ? DeltaKind::Point : DeltaKind::Spot;
            d.position = c;
            d.power = Spectrum(power, power, power);
            d.axis = {0, 0, -1};
            d.cos_half_angle = std::cos(0.6f);
            LightBounds b;
            DeltaLightBounds(d, &b);
            lights.push_back(b);
        } else {
            const float s = 0.05f + 0.15f * u(g);
            const AreaLight l = MakeRectAreaLight(c - Vec3f(s / 2, s / 2, 0), {0, s, 0}, {s, 0, 0},
                                                  Spectrum(power, power, power), false, true);
            lights.push_back(AreaLightBounds(l));
        }
    }
    return lights;
}

const std::vector<LightBounds>& Lights(int n) {
    static std::map<int, std::vector<LightBounds>> cache;
    auto it = cache.find(n);
    if (it == cache.end()) it = cache.emplace(n, LightsOverPlane(n, 1234u + n)).first;
    return it->second;
}

const LightTree& Tree(int n) {
    static std::map<int, LightTree> cache;
    auto it = cache.find(n);
    if (it == cache.end()) {
        it = cache.emplace(n, LightTree()).first;
        it->second.Build(Lights(n));
    }
    return it->second;
}

struct Query {
    Vec3f p;
    float u;
};

std::vector<Query> Queries(int n) {
    std::mt19937 g(99);
    std::uniform_real_distribution<float> u(0, 1);
    const float side = std::sqrt(float(n));
    std::vector<Query> q(4096);
    for (Query& x : q) x = {Vec3f(side * (u(g) - 0.5f), side * (u(g) - 0.5f), 0), std::min(u(g), 0x1.fffffep-1f)};
    return q;
}

void BM_LightTreeBuild(benchmark::State& state) {
    const int n = int(state.range(0)), threads = int(state.range(1));
    const std::vector<LightBounds>& lights = Lights(n);
    LightTree tree;
    for (auto _ : state) {
        tree.Build(lights, threads);
        benchmark::DoNotOptimize(tree.Nodes().data());
    }
    state.counters["bytes_per_emitter"] = double(tree.MemoryBytes()) / n;
    state.counters["depth"] = tree.Depth();
}

void BM_LightTreeSample(benchmark::State& state) {
    const int n = int(state.range(0));
    const LightTree& tree = Tree(n);
    const std::vector<Query> q = Queries(n);
    const Vec3f up(0, 0, 1);
    size_t k = 0;
    for (auto _ : state) {
        const Query& x = q[k++ & 4095];
        benchmark::DoNotOptimize(tree.Sample(x.p, up, x.u));
    }
}

void BM_LightTreePMF(benchmark::State& state) {
    const int n = int(state.range(0));
    const LightTree& tree = Tree(n);
    const std::vector<Query> q = Queries(n);
    const Vec3f up(0, 0, 1);
    std::vector<int> chosen(q.size());
    for (size_t i = 0; i < q.size(); ++i) chosen[i] = std::max(0, tree.Sample(q[i].p, up, q[i].u).emitter);
    size_t k = 0;
    for (auto _ : state) {
        const size_t i = k++ & 4095;
        benchmark::DoNotOptimize(tree.PMF(q[i].p, up, chosen[i]));
    }
}

// Not a timing: how well the tree's pmf follows the emitters' contributions, against choosing by
// power.  With the unoccluded contribution of emitter e at receiver p estimated at its centre,
// f_e = power_e * cos_e+ * cos_p+ / d^2 (cos_e: the emitter's side, 1 for points, its cone for
// spots), the one-sample estimator f_e / pmf_e of sum f has relative second moment
// sum_e (f_e^2 / pmf_e) / (sum_e f_e)^2 (1: pmf proportional to f).  Mean over 64 receivers.
double ProxyContribution(const LightBounds& b, const Vec3f& p, const Vec3f& n) {
    const Vec3f c = (b.lo + b.hi) * 0.5f;
    const Vec3f d = p - c;
    const float d2 = Dot(d, d);
    const Vec3f w = d / std::sqrt(d2);
    float emit = 1;
    if (b.cos_theta_o > -1) {
        const float cos_l = Dot(b.axis, w);
        emit = b.cos_theta_e >= 1 ? (cos_l > b.cos_theta_o ? 1.0f : 0.0f) : std::max(0.0f, cos_l);
    }
    return b.power * emit * std::max(0.0f, -Dot(n, w)) / d2;
}

void BM_LightTreeSelectionMoment(benchmark::State& state) {
    const int n = int(state.range(0));
    const std::vector<LightBounds>& lights = Lights(n);
    const LightTree& tree = Tree(n);
    const std::vector<Query> q = Queries(n);
    const Vec3f up(0, 0, 1);
    double total_power = 0;
    for (const LightBounds& b : lights) total_power += b.power;
    double tree_moment = 0, power_moment = 0;
    int receivers = 0;
    for (auto _ : state) {
        for (int r = 0; r < 64; ++r) {
            double sum = 0, tree_sq = 0, power_sq = 0;
            for (int e = 0; e < n; ++e) {
                const double f = ProxyContribution(lights[e], q[r].p, up);
                if (f == 0) continue;
                sum += f;
                tree_sq += f * f / tree.PMF(q[r].p, up, e);
                power_sq += f * f / (lights[e].power / total_power);
            }
            if (!(sum > 0)) continue;
            tree_moment += tree_sq / (sum * sum);
            power_moment += power_sq / (sum * sum);
            ++receivers;
        }
    }
    state.counters["moment_tree"] = tree_moment / receivers;
    state.counters["moment_power"] = power_moment / receivers;
}

BENCHMARK(BM_LightTreeBuild)
    ->ArgsProduct({{10, 100, 1000, 10000, 100000, 1000000}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LightTreeSample)->RangeMultiplier(10)->Range(10, 1000000)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_LightTreePMF)->RangeMultiplier(10)->Range(10, 1000000)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_LightTreeSelectionMoment)->RangeMultiplier(10)->Range(10, 10000)->Iterations(1);

}  // namespace
}  // namespace sphrect::render

BENCHMARK_MAIN();
