// ns per sample and per setup of every technique, float and double, with the
// textbook single-precision spherical-rectangle formula (the paper's code as in
// Blender 3.4 Cycles) as the baseline.
//
//   build/native/bench/bench_sampling [--benchmark_filter=Sample]
//
// "Setup" is the per-(shading point, light) precomputation (the LightSampler
// constructor); "Sample" is one Sample(u, v) on a prepared sampler, (u, v) cycling
// through 1024 precomputed uniform points; shading points cycle through 64 ordinary
// configurations (above, beside and oblique to a 1 x 1.5 light at distances 0.3-5).
// "SetupFromFrame" is the same with the light's frame precomputed, as in the renderer.
// "SampleEdgeOn" is a nearly edge-on setup where `rectangle` refines its x-step.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "core/technique.h"
#include "core/textbook_spherical_rectangle.h"

using namespace sphrect;

namespace {

template <class T>
RectLight<T> Light() {
    return {{T(-0.5), T(-0.75), T(2)}, {T(1), T(0), T(0)}, {T(0), T(1.5), T(0)}, true};
}

template <class T>
const std::vector<Vec3<T>>& Origins() {
    static const std::vector<Vec3<T>> o = [] {
        std::mt19937 rng(1);
        std::uniform_real_distribution<double> U(-1, 1);
        std::vector<Vec3<T>> v;
        for (int i = 0; i < 64; ++i) v.push_back(Vec3<T>(T(2 * U(rng)), T(2 * U(rng)), T(1.7 - 3 * std::abs(U(rng)))));
        return v;
    }();
    return o;
}

template <class T>
const std::vector<Point2<T>>& UVs() {
    static const std::vector<Point2<T>> uv = [] {
        std::mt19937 rng(2);
        std::uniform_real_distribution<double> U(0, 1);
        std::vector<Point2<T>> v;
        for (int i = 0; i < 1024; ++i) v.push_back({T(U(rng)), T(U(rng))});
        return v;
    }();
    return uv;
}

// kFromFrame: the setup as the renderer runs it, with the light's frame (MakeRectLightFrame) computed once.
template <Technique K, class T, bool kFromFrame = false>
void BM_Setup(benchmark::State& state) {
    const RectLight<T> L = Light<T>();
    const RectLightFrame<T> F = MakeRectLightFrame(L);
    const Vec3<T> n(0, 0, 1);
    const auto& os = Origins<T>();
    size_t i = 0;
    for (auto _ : state) {
        if constexpr (kFromFrame) {
            LightSampler<K, T> s(os[i++ & 63], n, F);
            benchmark::DoNotOptimize(s);
        } else {
            LightSampler<K, T> s(os[i++ & 63], n, L);
            benchmark::DoNotOptimize(s);
        }
    }
}

template <Technique K, class T>
void BM_Sample(benchmark::State& state) {
    const RectLight<T> L = Light<T>();
    const LightSampler<K, T> s(Vec3<T>(T(0.2), T(-0.1), T(0.5)), Vec3<T>(0, 0, 1), L);
    const auto& uv = UVs<T>();
    size_t i = 0;
    for (auto _ : state) {
        LightSample<T> ls = s.Sample(uv[i++ & 1023]);
        benchmark::DoNotOptimize(ls);
    }
}

// Pdf (for MIS): rectangle_cosine's needs the inverse map.
template <Technique K, class T>
void BM_Pdf(benchmark::State& state) {
    const RectLight<T> L = Light<T>();
    const LightSampler<K, T> s(Vec3<T>(T(0.2), T(-0.1), T(0.5)), Vec3<T>(0, 0, 1), L);
    std::vector<Vec3<T>> pts;
    for (const Point2<T>& uv : UVs<T>()) pts.push_back(L.corner + L.ex * uv.u + L.ey * uv.v);
    size_t i = 0;
    for (auto _ : state) {
        T p = s.Pdf(pts[i++ & 1023]);
        benchmark::DoNotOptimize(p);
    }
}

void BM_Setup_Textbook(benchmark::State& state) {
    const RectLight<float> L = Light<float>();
    const auto& os = Origins<float>();
    size_t i = 0;
    for (auto _ : state) {
        TextbookSphericalRectangle q = MakeTextbookSphericalRectangle(os[i++ & 63], L);
        benchmark::DoNotOptimize(q);
    }
}

void BM_Sample_Textbook(benchmark::State& state) {
    const TextbookSphericalRectangle q = MakeTextbookSphericalRectangle(Vec3f(0.2f, -0.1f, 0.5f), Light<float>());
    const auto& uv = UVs<float>();
    size_t i = 0;
    for (auto _ : state) {
        const Point2<float> p = uv[i++ & 1023];
        LightSample<float> ls = SampleTextbookSphericalRectangle(q, p.u, p.v);
        benchmark::DoNotOptimize(ls);
    }
}

// A nearly edge-on setup (shading point 2 sizes beside the light at height 1e-6):
// `rectangle` refines its x-step by Newton steps there (polish_x).
template <Technique K>
void BM_SampleEdgeOn(benchmark::State& state) {
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, true};
    const LightSampler<K, float> s(Vec3f(2.f, 0.1f, 1e-6f), Vec3f(-1, 0, 0), L);
    const auto& uv = UVs<float>();
    size_t i = 0;
    for (auto _ : state) {
        LightSample<float> ls = s.Sample(uv[i++ & 1023]);
        benchmark::DoNotOptimize(ls);
    }
}

}  // namespace

BENCHMARK(BM_SampleEdgeOn<Technique::Rectangle>)->Name("SampleEdgeOn/rectangle/float");
BENCHMARK(BM_SampleEdgeOn<Technique::Triangles>)->Name("SampleEdgeOn/triangles/float");

#define SPHRECT_BENCH(K, name)                                                   \
    BENCHMARK(BM_Setup<Technique::K, float>)->Name("Setup/" name "/float");      \
    BENCHMARK(BM_Setup<Technique::K, double>)->Name("Setup/" name "/double");    \
    BENCHMARK(BM_Setup<Technique::K, float, true>)->Name("SetupFromFrame/" name "/float"); \
    BENCHMARK(BM_Sample<Technique::K, float>)->Name("Sample/" name "/float");    \
    BENCHMARK(BM_Sample<Technique::K, double>)->Name("Sample/" name "/double");  \
    BENCHMARK(BM_Pdf<Technique::K, float>)->Name("Pdf/" name "/float");          \
    BENCHMARK(BM_Pdf<Technique::K, double>)->Name("Pdf/" name "/double");

BENCHMARK(BM_Setup_Textbook)->Name("Setup/textbook_rectangle/float");
BENCHMARK(BM_Sample_Textbook)->Name("Sample/textbook_rectangle/float");
SPHRECT_BENCH(Area, "area")
SPHRECT_BENCH(Triangles, "triangles")
SPHRECT_BENCH(Rectangle, "rectangle")
SPHRECT_BENCH(RectangleCosine, "rectangle_cosine")

BENCHMARK_MAIN();
