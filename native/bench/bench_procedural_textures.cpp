// Cost of Cycles' procedural textures (render/svm/procedural_textures.h): ns per evaluation at random points in
// [-4, 4]^3 (w alike), with Blender's default settings unless the name says otherwise.
//   build/native/bench/bench_procedural_textures
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "render/svm/procedural_textures.h"

using namespace sphrect;
using namespace sphrect::render::svm;

namespace {

struct Points {
    std::vector<Vec3f> p;
    std::vector<float> w;
    Points() {
        std::mt19937 rng(1);
        std::uniform_real_distribution<float> u(-4.0f, 4.0f);
        for (int i = 0; i < 1024; ++i) {
            p.emplace_back(u(rng), u(rng), u(rng));
            w.push_back(u(rng));
        }
    }
};
const Points& points() {
    static const Points pts;
    return pts;
}

// Runs f(p, w) over the points, one evaluation per iteration.
template <class F>
void Run(benchmark::State& state, F&& f) {
    const Points& pts = points();
    size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(f(pts.p[i], pts.w[i]));
        i = (i + 1) & 1023;
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}

}  // namespace

// Perlin noise alone (Cycles' snoise), by dimension.
static void BM_SignedNoise(benchmark::State& state) {
    const int n = int(state.range(0));
    Run(state, [&](const Vec3f& p, float w) {
        switch (n) {
            case 1: return SignedNoise1(w);
            case 2: return SignedNoise2(p.x, p.y);
            case 3: return SignedNoise3(p.x, p.y, p.z);
            default: return SignedNoise4(p.x, p.y, p.z, w);
        }
    });
}
BENCHMARK(BM_SignedNoise)->DenseRange(1, 4);

// Args: dimensions; Color computed or not.
static void BM_Noise(benchmark::State& state) {
    NoiseTextureParams params;
    params.dimensions = int(state.range(0));
    const bool color = state.range(1) != 0;
    Run(state, [&](const Vec3f& p, float w) { return NoiseTexture(params, p, w, color).fac; });
}
BENCHMARK(BM_Noise)->ArgsProduct({{1, 2, 3, 4}, {0, 1}});

// Args: dimensions, type.
static void BM_Musgrave(benchmark::State& state) {
    MusgraveTextureParams params;
    params.dimensions = int(state.range(0));
    params.type = MusgraveType(state.range(1));
    state.SetLabel(kMusgraveTypeNames[state.range(1)]);
    Run(state, [&](const Vec3f& p, float w) { return MusgraveTexture(params, p, w); });
}
BENCHMARK(BM_Musgrave)->ArgsProduct({{1, 2, 3, 4}, {0, 1, 2, 3, 4}});

// Args: dimensions, feature.
static void BM_Voronoi(benchmark::State& state) {
    VoronoiTextureParams params;
    params.dimensions = int(state.range(0));
    params.feature = VoronoiFeature(state.range(1));
    state.SetLabel(kVoronoiFeatureNames[state.range(1)]);
    Run(state, [&](const Vec3f& p, float w) { return VoronoiTexture(params, p, w).distance; });
}
BENCHMARK(BM_Voronoi)->ArgsProduct({{1, 2, 3, 4}, {0, 1, 2, 3, 4}});

static void BM_WhiteNoise(benchmark::State& state) {
    WhiteNoiseTextureParams params;
    params.dimensions = int(state.range(0));
    Run(state, [&](const Vec3f& p, float w) { return WhiteNoiseTexture(params, p, w).color.x; });
}
BENCHMARK(BM_WhiteNoise)->DenseRange(1, 4);

static void BM_Gradient(benchmark::State& state) {
    GradientTextureParams params;
    params.type = GradientType(state.range(0));
    state.SetLabel(kGradientTypeNames[state.range(0)]);
    Run(state, [&](const Vec3f& p, float) { return GradientTexture(params, p); });
}
BENCHMARK(BM_Gradient)->DenseRange(0, 6);

static void BM_Checker(benchmark::State& state) {
    const CheckerTextureParams params;
    Run(state, [&](const Vec3f& p, float) { return CheckerTexture(params, p).fac; });
}
BENCHMARK(BM_Checker);

// Arg: distortion (0: none, 1: 2 with the default detail -- a fractal noise per evaluation).
static void BM_Wave(benchmark::State& state) {
    WaveTextureParams params;
    params.distortion = state.range(0) ? 2.0f : 0.0f;
    Run(state, [&](const Vec3f& p, float) { return WaveTexture(params, p); });
}
BENCHMARK(BM_Wave)->Arg(0)->Arg(1);

static void BM_Magic(benchmark::State& state) {
    MagicTextureParams params;
    params.depth = int(state.range(0));
    Run(state, [&](const Vec3f& p, float) { return MagicTexture(params, p).fac; });
}
BENCHMARK(BM_Magic)->Arg(2)->Arg(10);

static void BM_Brick(benchmark::State& state) {
    const BrickTextureParams params;
    Run(state, [&](const Vec3f& p, float) { return BrickTexture(params, p).fac; });
}
BENCHMARK(BM_Brick);

BENCHMARK_MAIN();
