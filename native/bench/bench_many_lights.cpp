// Many-lights benchmark: time per camera sample against the number of lights (issue 11).
//
//  BM_ManyLights/<kind>/<lights>/<selection>
//                                  kind 0: <lights> small one-sided rectangle lights (squares of side
//                                  4 cm facing down, visible to the camera) at heights 1.5-3 m over
//                                  a 20 m x 20 m ground; kind 1: the same number of point lights at
//                                  the same places.  The total power is the same at every count
//                                  (each light has 1/<lights> of it), so the image stays alike.
//                                  The ground is two triangles, with four boxes on it.
//                                  selection: kAllLightSelections' index (0 power, 1 tree, 2 ris with
//                                  the default ris_candidates).
//                                  Rectangle technique, power-heuristic MIS, Sobol', 1 light
//                                  sample, 1 thread.
//                                  Counters: ns/sample (process CPU time per camera sample),
//                                  commit_ms (building the RenderScene and Commit(): Embree BVHs of
//                                  the geometry and of the area lights, the power table),
//                                  renderer_ms (making the Renderer; the light tree is built by a
//                                  scene's first "tree" Renderer, which Google Benchmark's sizing run
//                                  makes, so its build time is bench_light_tree's), lights.
//
// One iteration renders 64 x 48 pixels at 4 samples (12,288 camera samples); with 10,000 lights or
// more, 32 x 24 pixels at 1 sample (768 camera samples, the same view), so that a run of the
// slowest cases stays in seconds: the per-sample time is what is compared.
//
// Times are process CPU seconds (manual timing), as in bench_render.cpp: on a shared machine they
// are steadier than wall time, and with threads = 1 they equal the rendering thread's time.
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "render/scene.h"

namespace sphrect::render {
namespace {

enum class LightKind { Rectangle = 0, Point = 1 };

constexpr float kGroundHalf = 10;    // the lights spread over [-10, 10]^2
constexpr float kLightSide = 0.04f;  // rectangle lights: squares of this side
constexpr float kTotalPower = 400;   // W, shared by all the lights

struct ImageSize {
    int width, height, samples;
};

ImageSize ImageFor(int lights) { return lights >= 10000 ? ImageSize{32, 24, 1} : ImageSize{64, 48, 4}; }

double ProcessCpuSeconds() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double MinOf(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

// An axis-aligned box, 12 triangles.
void AddBox(RenderScene& s, const Vec3f& lo, const Vec3f& hi) {
    std::vector<float> v;
    for (int k = 0; k < 8; ++k) v.insert(v.end(), {k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
    const int32_t t[] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                         2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    s.AddMesh("box", v.data(), 8, t, 12, nullptr, nullptr);
}

void AddLights(RenderScene& s, LightKind kind, int n) {
    std::mt19937 g(1234u + uint32_t(n));
    std::uniform_real_distribution<float> u(0, 1);
    const float area = kLightSide * kLightSide;
    // Power of a one-sided Lambertian emitter: P = pi A L; of an isotropic point: P = 4 pi I.
    const float radiance = kTotalPower / n / (kPi * area), intensity = kTotalPower / n / (4 * kPi);
    for (int i = 0; i < n; ++i) {
        const Vec3f c(2 * kGroundHalf * (u(g) - 0.5f), 2 * kGroundHalf * (u(g) - 0.5f), 1.5f + 1.5f * u(g));
        if (kind == LightKind::Rectangle) {
            // Corner, then edges ex, ey with ex x ey = -z: it emits down, towards the ground.
            s.AddRectLight(c - Vec3f(kLightSide / 2, kLightSide / 2, 0), {0, kLightSide, 0}, {kLightSide, 0, 0},
                           {radiance, radiance, radiance}, false, true);
        } else {
            s.AddPointLight(c, {intensity, intensity, intensity});
        }
    }
}

std::shared_ptr<RenderScene> ManyLightsScene(LightKind kind, int n) {
    auto s = std::make_shared<RenderScene>();
    const ImageSize size = ImageFor(n);
    CameraModel c;
    c.width = size.width;
    c.height = size.height;
    c.half_width = 0.6f;
    c.half_height = 0.6f * size.height / size.width;
    // Looking down at the ground from 8 m up and 9 m back, 37 degrees below the horizon.
    const float m[3][4] = {{1, 0, 0, 0}, {0, 0.8f, -0.6f, -9}, {0, 0.6f, 0.8f, 8}};
    std::copy(&m[0][0], &m[0][0] + 12, &c.to_world[0][0]);
    s->SetCamera(c);
    s->AddMaterial(DiffuseMaterial({0.6f, 0.6f, 0.6f}));
    const float ground[] = {-kGroundHalf, -kGroundHalf, 0, kGroundHalf,  -kGroundHalf, 0,
                            kGroundHalf,  kGroundHalf,  0, -kGroundHalf, kGroundHalf,  0};
    const int32_t gt[] = {0, 1, 2, 0, 2, 3};
    s->AddMesh("ground", ground, 4, gt, 2, nullptr, nullptr);
    AddBox(*s, {-3, -2, 0}, {-2, -1, 1});
    AddBox(*s, {1, -3, 0}, {2.5f, -1.5f, 0.6f});
    AddBox(*s, {-1, 2, 0}, {0, 3, 1.2f});
    AddBox(*s, {3, 1, 0}, {4, 2.5f, 0.8f});
    AddLights(*s, kind, n);
    s->Commit();
    return s;
}

struct BuiltScene {
    std::shared_ptr<RenderScene> scene;
    double commit_seconds;
};

// One scene per (kind, count), built once (its build and commit timed once, in CPU seconds).
const BuiltScene& SceneFor(LightKind kind, int n) {
    static std::map<std::pair<int, int>, BuiltScene> cache;
    const auto key = std::make_pair(int(kind), n);
    auto it = cache.find(key);
    if (it == cache.end()) {
        const double t0 = ProcessCpuSeconds();
        auto scene = ManyLightsScene(kind, n);
        it = cache.emplace(key, BuiltScene{scene, ProcessCpuSeconds() - t0}).first;
    }
    return it->second;
}

void BM_ManyLights(benchmark::State& state) {
    const LightKind kind = LightKind(state.range(0));
    const int n = int(state.range(1));
    const BuiltScene& built = SceneFor(kind, n);
    const ImageSize size = ImageFor(n);
    RenderOptions o;
    o.techniques = {Technique::Rectangle};
    o.mis = MisMode::Power;
    o.pattern = Pattern::Sobol;
    o.light_samples = 1;
    o.threads = 1;
    o.light_selection = kAllLightSelections[state.range(2)];
    // The renderer is made once (its setup timed apart); each iteration is one more progressive pass.
    const double t_setup = ProcessCpuSeconds();
    Renderer r(built.scene, o);
    const double setup_seconds = ProcessCpuSeconds() - t_setup;
    double seconds = 0;
    uint64_t samples = 0;
    for (auto _ : state) {
        const double t0 = ProcessCpuSeconds();
        r.Render(size.samples);
        const double dt = ProcessCpuSeconds() - t0;
        state.SetIterationTime(dt);
        seconds += dt;
        samples += uint64_t(size.width) * size.height * size.samples;
    }
    state.SetLabel(std::string(kind == LightKind::Rectangle ? "rect/" : "point/") +
                   LightSelectionName(o.light_selection) + "/" + std::to_string(size.width) + "x" +
                   std::to_string(size.height) + "x" + std::to_string(size.samples));
    state.counters["ns/sample"] = benchmark::Counter(1e9 * seconds / double(samples));
    state.counters["commit_ms"] = benchmark::Counter(1e3 * built.commit_seconds);
    state.counters["renderer_ms"] = benchmark::Counter(1e3 * setup_seconds);
    state.counters["lights"] = benchmark::Counter(double(n));
}
BENCHMARK(BM_ManyLights)
    ->ArgsProduct({{int(LightKind::Rectangle), int(LightKind::Point)}, {1, 10, 100, 1000, 10000, 100000}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

}  // namespace
}  // namespace sphrect::render

BENCHMARK_MAIN();
