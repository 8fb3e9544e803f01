// ns per sample and per setup of every technique, float and double, with the
// textbook single-precision spherical-rectangle formula (the paper's code as in
// Blender 3.4 Cycles) as the baseline.  The stages and their inputs are
// core/sampler_timing.h, which the study's cost table runs through the module too.
//
//   build/native/bench/bench_sampling [--benchmark_filter=Sample]
#include <benchmark/benchmark.h>

#include <string>

#include "core/sampler_timing.h"

int main(int argc, char** argv) {
    sphrect::sampler_timing::ForEachStage([](const std::string& name, auto stage) {
        benchmark::RegisterBenchmark(name.c_str(), [stage](benchmark::State& state) {
            size_t i = 0;
            for (auto _ : state) {
                auto result = stage(i++);
                benchmark::DoNotOptimize(result);
            }
        });
    });
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
