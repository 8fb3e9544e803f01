// The cost table of the techniques: one list of timed stages (name + one call), run by the
// Google Benchmark program native/bench/bench_sampling and, through the module
// (sphrect._native._study_sampler_timings), by the study's table, which then needs no
// benchmark binary from a build tree.
//
// Stages, named "<stage>/<technique>/<precision>":
//   Setup           the per-(shading point, light) setup (the LightSampler constructor);
//                   shading points cycle through 64 ordinary configurations (above, beside
//                   and oblique to a 1 x 1.5 light at distances 0.3-5)
//   SetupFromFrame  the same with the light's frame precomputed, as in the renderer
//   Sample          one Sample(u, v) on a prepared sampler, (u, v) cycling through 1024
//                   precomputed uniform points
//   SampleOffAxis   the same with a normal pointing beside the light (cos varies over it)
//   SampleEdgeOn    the same in a nearly edge-on setup, where `rectangle` refines its x-step
//   Pdf             PDF(point) (for MIS; rectangle_cosine's needs the inverse map)
// plus the textbook single-precision map (textbook_rectangle.h) as the baseline.
#pragma once

#include <chrono>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "technique.h"
#include "textbook_rectangle.h"

namespace sphrect::sampler_timing {

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

// Each stage is a callable: stage(i) makes call number i and returns its result.
template <Technique K, class T>
auto SetupStage() {
    return [L = Light<T>()](size_t i) { return LightSampler<K, T>(Origins<T>()[i & 63], Vec3<T>(0, 0, 1), L); };
}

template <Technique K, class T>
auto SetupFromFrameStage() {
    return [F = MakeRectLightFrame(Light<T>())](size_t i) {
        return LightSampler<K, T>(Origins<T>()[i & 63], Vec3<T>(0, 0, 1), F);
    };
}

template <Technique K, class T>
auto SampleStage() {
    const LightSampler<K, T> s(Vec3<T>(T(0.2), T(-0.1), T(0.5)), Vec3<T>(0, 0, 1), Light<T>());
    return [s](size_t i) { return s.Sample(UVs<T>()[i & 1023]); };
}

template <Technique K, class T>
auto PDFStage() {
    const RectLight<T> L = Light<T>();
    const LightSampler<K, T> s(Vec3<T>(T(0.2), T(-0.1), T(0.5)), Vec3<T>(0, 0, 1), L);
    std::vector<Vec3<T>> pts;
    for (const Point2<T>& uv : UVs<T>()) pts.push_back(L.corner + L.ex * uv.u + L.ey * uv.v);
    return [s, pts](size_t i) { return s.PDF(pts[i & 1023]); };
}

// The Sample stage's setup with a tilted normal (1, 0, 0.2): n points beside the light, so the
// cosine varies over it and `rectangle_projected` inverts its near/far sweep by Newton steps
// (with n = (0, 0, 1), the Sample stage's, n points into the light: the closed-form star case).
template <Technique K>
auto SampleOffAxisStage() {
    const LightSampler<K, float> s(Vec3f(0.2f, -0.1f, 0.5f), Normalize(Vec3f(1, 0, 0.2f)), Light<float>());
    return [s](size_t i) { return s.Sample(UVs<float>()[i & 1023]); };
}

// A nearly edge-on setup (shading point 2 sizes beside the light at height 1e-6).
template <Technique K>
auto SampleEdgeOnStage() {
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, true};
    const LightSampler<K, float> s(Vec3f(2.f, 0.1f, 1e-6f), Vec3f(-1, 0, 0), L);
    return [s](size_t i) { return s.Sample(UVs<float>()[i & 1023]); };
}

inline auto TextbookSetupStage() {
    return [L = Light<float>()](size_t i) { return MakeTextbookRectangle(Origins<float>()[i & 63], L); };
}

inline auto TextbookSampleStage() {
    const TextbookRectangle q = MakeTextbookRectangle(Vec3f(0.2f, -0.1f, 0.5f), Light<float>());
    return [q](size_t i) {
        const Point2<float> p = UVs<float>()[i & 1023];
        return SampleTextbookRectangle(q, p.u, p.v);
    };
}

// Calls f(name, stage) for every stage of the table, in its order.
template <class F>
void ForEachStage(F&& f) {
    f("SampleEdgeOn/rectangle/float", SampleEdgeOnStage<Technique::Rectangle>());
    f("SampleEdgeOn/triangles/float", SampleEdgeOnStage<Technique::Triangles>());
    f("Setup/textbook_rectangle/float", TextbookSetupStage());
    f("Sample/textbook_rectangle/float", TextbookSampleStage());
    for (Technique t : kAllTechniques)
        DispatchTechnique(t, [&](auto tag) {
            constexpr Technique K = decltype(tag)::value;
            const std::string name = TechniqueName(K);
            f("Setup/" + name + "/float", SetupStage<K, float>());
            f("Setup/" + name + "/double", SetupStage<K, double>());
            f("SetupFromFrame/" + name + "/float", SetupFromFrameStage<K, float>());
            f("Sample/" + name + "/float", SampleStage<K, float>());
            f("Sample/" + name + "/double", SampleStage<K, double>());
            f("SampleOffAxis/" + name + "/float", SampleOffAxisStage<K>());
            f("Pdf/" + name + "/float", PDFStage<K, float>());
            f("Pdf/" + name + "/double", PDFStage<K, double>());
        });
}

// Keeps a result from being optimised away (as benchmark::DoNotOptimize does).
template <class V>
inline void KeepResult(const V& v) {
    asm volatile("" : : "r"(&v) : "memory");
}

// ns per call of `stage`: runs of growing length until one takes at least min_seconds.
template <class Stage>
double NanosecondsPerCall(const Stage& stage, double min_seconds) {
    using Clock = std::chrono::steady_clock;
    for (size_t calls = 16;; calls *= 4) {
        const Clock::time_point start = Clock::now();
        for (size_t i = 0; i < calls; ++i) KeepResult(stage(i));
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        if (seconds >= min_seconds || calls >= (size_t(1) << 40)) return seconds * 1e9 / double(calls);
    }
}

}  // namespace sphrect::sampler_timing
