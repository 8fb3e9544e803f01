// Renderer benchmarks.
//
//  BM_Render/<technique>/<mis>/<pattern>  one technique per renderer, 1 thread, on a ~100k-triangle scene
//                                (ground + four tessellated spheres, one rectangle light standing
//                                on the ground).  Counters: rays/s (camera + shadow + BSDF rays),
//                                wall seconds per camera sample, light_frac = share of the
//                                technique's light sampling in its thread time.
//  BM_RawEmbree/<rays per sample> the same camera rays, then the same number of occlusion rays per
//                                camera sample towards uniform points on the light, with no
//                                sampling technique and no shading: the ray-casting floor.
//  BM_DiffuseKernel/<forced>     the diffuse scene with the kernel the scene selects (0: no medium,
//                                glossy or lens code at all, i.e. exactly a renderer built without
//                                them) and with the kernel that has medium + glossy + depth of field
//                                compiled in and switched off by run-time tests (1): what a single
//                                generic kernel would cost a diffuse scene.
//
// Times are process CPU seconds (manual timing), not wall time: on a shared, loaded machine
// they are far steadier, and with threads = 1 they equal the rendering thread's time.
#include <benchmark/benchmark.h>

#include <time.h>

#include <cmath>
#include <memory>
#include <vector>

#include "core/rng.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace sphrect::render {
namespace {

constexpr int kWidth = 96, kHeight = 72, kSamples = 4;

// UV sphere: (rings - 1) * segments * 2 triangles (approximately).
void AddSphere(RenderScene& s, const Vec3f& c, float r, int rings, int segments) {
    std::vector<float> v;
    std::vector<int32_t> t;
    for (int i = 0; i <= rings; ++i) {
        const float theta = kPi * i / rings;
        for (int j = 0; j < segments; ++j) {
            const float phi = 2 * kPi * j / segments;
            v.insert(v.end(), {c.x + r * std::sin(theta) * std::cos(phi), c.y + r * std::sin(theta) * std::sin(phi),
                               c.z + r * std::cos(theta)});
        }
    }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const int a = i * segments + j, b = i * segments + (j + 1) % segments;
            const int cc = a + segments, d = b + segments;
            if (i > 0) t.insert(t.end(), {a, b, d});
            if (i < rings - 1) t.insert(t.end(), {a, d, cc});
        }
    s.AddMesh("sphere", v.data(), v.size() / 3, t.data(), t.size() / 3, nullptr, nullptr);
}

std::shared_ptr<RenderScene> BenchScene() {
    auto s = std::make_shared<RenderScene>();
    CameraModel c;
    c.width = kWidth;
    c.height = kHeight;
    c.half_width = 0.45f;
    c.half_height = 0.45f * kHeight / kWidth;
    const float m[3][4] = {{1, 0, 0, 0}, {0, 0.8f, -0.6f, -6}, {0, 0.6f, 0.8f, 4.5f}};
    std::copy(&m[0][0], &m[0][0] + 12, &c.to_world[0][0]);
    s->SetCamera(c);
    s->AddDiffuseMaterial({0.6f, 0.6f, 0.6f});
    const float ground[] = {-20, -20, 0, 20, -20, 0, 20, 20, 0, -20, 20, 0};
    const int32_t gt[] = {0, 1, 2, 0, 2, 3};
    s->AddMesh("ground", ground, 4, gt, 2, nullptr, nullptr);
    const Vec3f centres[] = {{-1.2f, -0.5f, 0.5f}, {0.2f, -1.0f, 0.6f}, {1.3f, 0.2f, 0.45f}, {-0.3f, 0.7f, 0.4f}};
    for (const Vec3f& ct : centres) AddSphere(*s, ct, ct.z, 112, 112);  // 4 x 24.9k triangles
    s->AddRectLight({-1.0f, 1.6f, 0.02f}, {2.0f, 0, 0}, {0, 0, 1.2f}, {6, 6, 6}, true, false);
    s->Commit();
    return s;
}

double ProcessCpuSeconds() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

const std::shared_ptr<RenderScene>& Scene() {
    static const std::shared_ptr<RenderScene> scene = BenchScene();
    return scene;
}

void BM_Render(benchmark::State& state) {
    RenderOptions o;
    o.techniques = {kAllTechniques[state.range(0)]};
    o.mis = state.range(1) ? MisMode::Balance : MisMode::None;
    o.threads = 1;
    o.pattern = kAllPatterns[state.range(2)];
    uint64_t rays = 0, samples = 0;
    double light = 0, total = 0;
    for (auto _ : state) {
        const double t0 = ProcessCpuSeconds();
        Renderer r(Scene(), o);
        r.Render(kSamples);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
        const TechniqueStats st = r.Stats(0);
        rays += st.rays + st.camera_rays;
        samples += uint64_t(kWidth) * kHeight * kSamples;
        light += st.light_time;
        total += st.light_time + st.shading_time + st.camera_time;
    }
    state.SetLabel(std::string(TechniqueName(o.techniques[0])) + (o.mis == MisMode::None ? "/no-mis/" : "/balance/") +
                   PatternName(o.pattern));
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["s/sample"] = benchmark::Counter(double(samples), benchmark::Counter::kIsRate |
                                                                          benchmark::Counter::kInvert);
    state.counters["light_frac"] = benchmark::Counter(light / total);
    state.counters["triangles"] = benchmark::Counter(double(Scene()->NumTriangles()));
}
// Sobol' (the default pattern) for every technique; the area technique also with independent
// samples, to show what the pattern costs.
BENCHMARK(BM_Render)->ArgsProduct({{0, 1, 2, 3}, {0, 1}, {4}})->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_Render)->Args({0, 0, 0})->Unit(benchmark::kMillisecond)->UseManualTime();

// Camera rays with first hits, then `rays_per_sample` occlusion rays per hit towards uniformly
// chosen points of the light: no technique, no BSDF, no accumulation.
void BM_RawEmbree(benchmark::State& state) {
    const RenderScene& s = *Scene();
    const AreaLight& light = s.area_lights[0];
    const int per_sample = int(state.range(0));
    uint64_t rays = 0, samples = 0;
    for (auto _ : state) {
        const double t0 = ProcessCpuSeconds();
        PCG32 rng(1);
        uint64_t occluded = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                for (int i = 0; i < kSamples; ++i) {
                    const Ray ray = GenerateCameraRay<false>(s.camera, x + rng.NextFloat(), y + rng.NextFloat(), {});
                    RTCIntersectContext ctx;
                    rtcInitIntersectContext(&ctx);
                    RTCRayHit rh;
                    rh.ray = {ray.o.x, ray.o.y, ray.o.z, 0, ray.d.x, ray.d.y, ray.d.z, 0, kInf, 0xffffffffu, 0, 0};
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(s.rtc_scene, &ctx, &rh);
                    ++rays;
                    ++samples;
                    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
                    const Vec3f n = Normalize(Vec3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
                    const Vec3f p = ray.o + ray.d * rh.ray.tfar + n * (Dot(n, ray.d) < 0 ? 1e-4f : -1e-4f);
                    for (int k = 0; k < per_sample; ++k) {
                        const Vec3f q = light.rect.corner + light.rect.ex * rng.NextFloat() +
                                        light.rect.ey * rng.NextFloat();
                        const Vec3f d = q - p;
                        const float dist = Length(d);
                        RTCRay r = {p.x, p.y, p.z, 0, d.x / dist, d.y / dist, d.z / dist, 0, dist * 0.9999f,
                                    0xffffffffu, 0, 0};
                        rtcOccluded1(s.rtc_scene, &ctx, &r);
                        occluded += r.tfar < 0;
                        ++rays;
                    }
                }
        benchmark::DoNotOptimize(occluded);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
    }
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["s/sample"] = benchmark::Counter(double(samples), benchmark::Counter::kIsRate |
                                                                          benchmark::Counter::kInvert);
}
BENCHMARK(BM_RawEmbree)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseManualTime();

void BM_DiffuseKernel(benchmark::State& state) {
    RenderOptions o;
    o.techniques = {Technique::Rectangle};
    o.threads = 1;
    o.force_all_features = state.range(0) != 0;
    for (auto _ : state) {
        const double t0 = ProcessCpuSeconds();
        Renderer r(Scene(), o);
        r.Render(kSamples);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
    }
    state.SetLabel(o.force_all_features ? "generic kernel: medium+glossy+dof compiled in, off at run time" : "specialised diffuse kernel");
    state.counters["s/sample"] = benchmark::Counter(double(kWidth) * kHeight * kSamples * state.iterations(),
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_DiffuseKernel)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseManualTime();

}  // namespace
}  // namespace sphrect::render

BENCHMARK_MAIN();
