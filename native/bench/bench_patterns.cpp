// Cost of the sample patterns: ns per point for a per-pixel set of n points
// (GeneratePattern), for one pixel's points of one dimension as the renderer draws them (SampleDimensionPoints),
// and for one index-wise Sobol' point (progressive passes).
//   build/native/bench/bench_patterns
#include <benchmark/benchmark.h>

#include <vector>

#include "core/patterns.h"

using namespace sphrect;

static void BM_GeneratePattern(benchmark::State& state) {
    const Pattern p = Pattern(state.range(0));
    const uint32_t n = uint32_t(state.range(1));
    std::vector<Point2<float>> pts(n);
    uint64_t seed = 0;
    for (auto _ : state) {
        GeneratePattern(p, n, MixBits(++seed), pts.data());  // a new pixel each time
        benchmark::DoNotOptimize(pts.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * n);
    state.SetLabel(PatternName(p));
}
BENCHMARK(BM_GeneratePattern)->ArgsProduct({{0, 1, 2, 3, 4}, {16, 256, 4096}});

static void BM_SobolPoint(benchmark::State& state) {
    uint32_t i = 0;
    for (auto _ : state) {
        const Point2<float> q = SobolPoint(i++, 12345);
        benchmark::DoNotOptimize(q);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_SobolPoint);

// One pixel's points of one dimension as the renderer draws them (SampleDimensionPoints: the dimension's seed, its
// keys, the shuffled indices), n points a call: BM_DimensionPoints/<pattern>/<n>.
static void BM_DimensionPoints(benchmark::State& state) {
    const Pattern p = Pattern(state.range(0));
    const uint32_t n = uint32_t(state.range(1));
    std::vector<Point2<float>> pts(n);
    uint64_t pixel = 0;
    for (auto _ : state) {
        SampleDimensionPoints(p, n, 0, 0, DimensionSeed(MixBits(++pixel), 3), true, pts.data());
        benchmark::DoNotOptimize(pts.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * n);
    state.SetLabel(PatternName(p));
}
BENCHMARK(BM_DimensionPoints)->ArgsProduct({{1, 4}, {1, 4, 16}});

static void BM_PCG32NextFloat(benchmark::State& state) {
    PCG32 rng(1);
    for (auto _ : state) benchmark::DoNotOptimize(rng.NextFloat());
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_PCG32NextFloat);

BENCHMARK_MAIN();
