// Renderer benchmarks.
//
//  BM_Render/<technique>/<mis>/<pattern>/<light samples>
//                                one technique per renderer, 1 thread, on a ~100k-triangle scene
//                                (ground + four tessellated spheres, one rectangle light standing
//                                on the ground; SPHRECT_BENCH_SCENE=dense: a 72k-triangle bumpy
//                                ground and coarser spheres, so that rays cost more).  Counters: rays/s (camera +
//                                shadow + BSDF rays), CPU seconds per camera sample, light_frac = share of the
//                                technique's light sampling in its thread time.
//  BM_RawEmbree/<technique>/<mis>/<light samples>
//                                the ray-casting floor of the same render: the same number of
//                                camera rays (same camera), and per hit the rays the renderer casts
//                                there -- one occlusion ray per valid light sample that leaves the
//                                surface, towards a point drawn by the same technique (so the ray
//                                directions have the same distribution), and with MIS one per
//                                cosine-distributed BSDF direction that reaches the light, up to it
//                                -- traced in the renderer's order and with its calls: per 16 x 16
//                                tile the camera rays as one coherent rtcIntersect1M stream, then
//                                the occlusion rays as one rtcOccluded1M stream.
//                                All rays are generated before the clock starts; only the tracing
//                                is timed (no sampling, no shading, no accumulation).
//                                The counter `secondary/sample` lets one check that the ray
//                                counts match the renderer's (rays/s x s/sample - 1).
//  BM_RaysAndSampler/<technique>/<light samples>
//                                BM_RawEmbree without MIS plus only the technique's own work: its
//                                setup per shading point and its map per light sample (the same
//                                points, (u, v) and hence rays), in the renderer's per-tile order.
//                                The floor for any renderer that calls this core's samplers
//                                (ab_bench_render.py BUILD/bench_render prints it next to the
//                                raw rays and the render).
//  BM_DiskRender/<ellipse technique>/<mis>/<light samples>, BM_DiskRawEmbree/<same>, BM_DiskRaysAndSampler/<ellipse
//  technique>/<light samples>
//                                the same three on the disk-light variant of the scene (a disk of the rectangle's
//                                area, radiance and sides), by kAllEllipseTechniques (area, spherical_ellipse);
//                                raw and rays + sampler also with index 2, the map at every point (kDiskMapEverywhere).
//  BM_GlossyRender/<technique>/<mis>/<light samples>, BM_GlossyRawEmbree/<same>, BM_GlossyRaysAndSampler/<technique>/
//  <light samples>               the same three on the glossy + textured variant (GGX spheres of roughness 0.3,
//                                the ground's colour from a texture), rectangle only.
//  BM_DiffuseKernel/<forced>     the diffuse scene with the kernel the scene selects (0: no medium,
//                                glossy or lens code at all, i.e. exactly a renderer built without
//                                them) and with the kernel that has medium + glossy + depth of field
//                                compiled in and switched off by run-time tests (1): what a single
//                                generic kernel would cost a diffuse scene.
//  BM_MediumKernel/<media>       the diffuse scene in a medium of the same coefficients everywhere: 0 the world's,
//                                1 an object volume, a box around the whole scene (the same image), 2 both, half each;
//                                and 3 a box around the spheres only: what object volumes cost where used.
//
// Times are process CPU seconds (manual timing), not wall time: on a shared, loaded machine
// they are far steadier, and with threads = 1 they equal the rendering thread's time.
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "core/ellipse_technique.h"
#include "core/rectangle_batch.h"
#include "core/triangles_batch.h"
#include "core/rng.h"
#include "core/technique.h"
#include "render/embree_rays.h"
#include "render/integrator/ellipse_sampling_at.h"
#include "render/renderer.h"
#include "render/sampling_util.h"
#include "render/scene.h"

namespace sphrect::render {
namespace {

constexpr int kWidth = 96, kHeight = 72, kSamples = 4;

// UV sphere: (rings - 1) * segments * 2 triangles (approximately), of material `material`.
void AddSphere(RenderScene& s, const Vec3f& c, float r, int rings, int segments, int32_t material) {
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
    // (No ids for material 0: the scenes of the older benchmarks stay exactly as they were.)
    const std::vector<int32_t> ids(material ? t.size() / 3 : 0, material);
    s.AddMesh("sphere", v.data(), v.size() / 3, t.data(), t.size() / 3, nullptr, material ? ids.data() : nullptr);
}

// Bumpy ground: an n x n grid over [-h, h]^2, z = a sin(3x) sin(3y) (2 n^2 triangles).
void AddBumpyGround(RenderScene& s, float h, int n, float a) {
    std::vector<float> v;
    std::vector<int32_t> t;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const float x = -h + 2 * h * j / n, y = -h + 2 * h * i / n;
            v.insert(v.end(), {x, y, a * std::sin(3 * x) * std::sin(3 * y)});
        }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const int k = i * (n + 1) + j;
            t.insert(t.end(), {k, k + 1, k + n + 2, k, k + n + 2, k + n + 1});
        }
    s.AddMesh("ground", v.data(), v.size() / 3, t.data(), t.size() / 3, nullptr, nullptr);
}

// SPHRECT_BENCH_SCENE=dense: the same camera, light and spheres, but most of the triangles in a bumpy
// ground the camera rays hit (rays cost more); default: a two-triangle ground and finer spheres.
bool DenseScene() {
    const char* v = std::getenv("SPHRECT_BENCH_SCENE");
    return v && std::string(v) == "dense";
}

// What BenchScene adds before it commits the scene (a medium, volumes), or nothing.
using SceneExtras = void (*)(RenderScene&);

// The bench scene's variants (flags, combined with |):
//  kTextured      the ground's base colour read from a 1 x 1 image (the lookup, the material rebuilt per hit and
//                 the vertex fetch for the texture coordinates are paid; the meshes have no UVs, so (0, 0) is read);
//                 without kGlossySpheres the spheres share the ground's material, so they are textured too.
//  kGlossySpheres the spheres in a Principled BSDF (GGX) of roughness 0.3: the glossy kernel.
//  kDiskLight     the rectangle light replaced by a disk of the same area, radiance (hence power) and sides,
//                 standing on the ground where the rectangle stands and facing the same way.
enum SceneFlags { kTextured = 1, kGlossySpheres = 2, kDiskLight = 4 };

// The rectangle light: corner, edges (normal ex x ey = -y: towards the spheres), radiance, two-sided, unseen.
const Vec3f kLightCorner{-1.0f, 1.6f, 0.02f}, kLightEx{2.0f, 0, 0}, kLightEy{0, 0, 1.2f};
const Spectrum kLightRadiance{6, 6, 6};

std::shared_ptr<RenderScene> BenchScene(int flags = 0, SceneExtras extras = nullptr) {
    const bool textured = flags & kTextured;
    auto s = std::make_shared<RenderScene>();
    CameraModel c;
    c.width = kWidth;
    c.height = kHeight;
    c.half_width = 0.45f;
    c.half_height = 0.45f * kHeight / kWidth;
    const float m[3][4] = {{1, 0, 0, 0}, {0, 0.8f, -0.6f, -6}, {0, 0.6f, 0.8f, 4.5f}};
    std::copy(&m[0][0], &m[0][0] + 12, &c.to_world[0][0]);
    s->SetCamera(c);
    Material ground = DiffuseMaterial({0.6f, 0.6f, 0.6f});
    if (textured) {
        const float grey[3] = {0.6f, 0.6f, 0.6f};
        TextureLookup& lookup = ground.textures[int(TexturedInput::kBaseColor)];
        lookup.image = s->AddImage("grey", 1, 1, 3, nullptr, grey, false);
    }
    s->AddMaterial(ground);
    int32_t sphere_material = 0;
    if (flags & kGlossySpheres) {
        Material glossy;
        glossy.name = "glossy";
        glossy.kind = MaterialKind::kPrincipled;
        glossy.inputs.base_color = {0.6f, 0.6f, 0.6f};
        glossy.inputs.roughness = 0.3f;
        sphere_material = s->AddMaterial(glossy);
    }
    const bool dense = DenseScene();
    if (dense) {
        AddBumpyGround(*s, 6.0f, 190, 0.04f);  // 72.2k triangles
    } else {
        const float ground[] = {-20, -20, 0, 20, -20, 0, 20, 20, 0, -20, 20, 0};
        const int32_t gt[] = {0, 1, 2, 0, 2, 3};
        s->AddMesh("ground", ground, 4, gt, 2, nullptr, nullptr);
    }
    const Vec3f centres[] = {{-1.2f, -0.5f, 0.5f}, {0.2f, -1.0f, 0.6f}, {1.3f, 0.2f, 0.45f}, {-0.3f, 0.7f, 0.4f}};
    const int rings = dense ? 56 : 112;  // 4 x 6.1k or 4 x 24.9k triangles
    for (const Vec3f& ct : centres) AddSphere(*s, ct, ct.z, rings, rings, sphere_material);
    if (flags & kDiskLight) {
        const float area = Length(Cross(kLightEx, kLightEy)), radius = std::sqrt(area / kPi);
        const Vec3f centre(kLightCorner.x + 0.5f * kLightEx.x, kLightCorner.y, kLightCorner.z + radius);
        s->AddEllipseLight(centre, Normalize(kLightEx) * radius, Normalize(kLightEy) * radius, kLightRadiance, true,
                           false);
    } else {
        s->AddRectLight(kLightCorner, kLightEx, kLightEy, kLightRadiance, true, false);
    }
    if (extras) extras(*s);
    s->Commit();
    return s;
}

// Repetition statistic: on a shared machine the least disturbed repetition is the best estimate.
double MinOf(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

double ProcessCpuSeconds() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

const std::shared_ptr<RenderScene>& Scene() {
    static const std::shared_ptr<RenderScene> scene = BenchScene();
    return scene;
}
const std::shared_ptr<RenderScene>& DiskScene() {
    static const std::shared_ptr<RenderScene> scene = BenchScene(kDiskLight);
    return scene;
}
const std::shared_ptr<RenderScene>& GlossyScene() {
    static const std::shared_ptr<RenderScene> scene = BenchScene(kTextured | kGlossySpheres);
    return scene;
}

// The options of BM_Render and its scene variants: one thread, power light selection.
RenderOptions BenchOptions(Technique technique, bool mis, Pattern pattern, int light_samples) {
    RenderOptions o;
    o.light_selection = LightSelection::Power;  // what these measure (not the defaults)
    o.techniques = {technique};
    o.mis = mis ? MisMode::Balance : MisMode::None;
    o.threads = 1;
    o.pattern = pattern;
    o.light_samples = light_samples;
    return o;
}

// Renders `scene` with `o` per iteration; the label names the case.
void RenderCase(benchmark::State& state, const std::shared_ptr<RenderScene>& scene, const RenderOptions& o,
                const std::string& label) {
    uint64_t rays = 0, samples = 0;
    double light = 0, total = 0;
    for (auto _ : state) {
        const double t0 = ProcessCpuSeconds();
        Renderer r(scene, o);
        r.Render(kSamples);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
        const TechniqueStats st = r.Stats(0);
        rays += st.rays + st.camera_rays;
        samples += uint64_t(kWidth) * kHeight * kSamples;
        light += st.light_time;
        total += st.light_time + st.shading_time + st.camera_time;
    }
    state.SetLabel(label);
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["s/sample"] =
        benchmark::Counter(double(samples), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["light_frac"] = benchmark::Counter(light / total);
    state.counters["triangles"] = benchmark::Counter(double(scene->NumTriangles()));
}

std::string MisLabel(bool mis) { return mis ? "/balance" : "/no-mis"; }

void BM_Render(benchmark::State& state) {
    const RenderOptions o = BenchOptions(kAllTechniques[state.range(0)], state.range(1) != 0,
                                         kAllPatterns[state.range(2)], int(state.range(3)));
    RenderCase(state, Scene(), o,
               std::string(TechniqueName(o.techniques[0])) + MisLabel(o.mis == MisMode::Balance) + "/" +
                   PatternName(o.pattern) + "/ls=" + std::to_string(o.light_samples));
}
// Sobol' (the default pattern) for every technique; the area technique also with independent
// samples, to show what the pattern costs; and 4 light samples per camera sample.
BENCHMARK(BM_Render)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}, {4}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);
BENCHMARK(BM_Render)
    ->Args({0, 0, 0, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);
BENCHMARK(BM_Render)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}, {4}, {4}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

// The rays of one render, generated once (untimed) and traced by BM_RawEmbree.
struct RawRays {
    std::vector<RTCRayHit> camera;      // one per camera sample, ready to trace
    std::vector<uint32_t> tile_first;   // camera samples of tile t: [tile_first[t], tile_first[t + 1])
    std::vector<RTCRay> shadow;         // occlusion rays (light and BSDF samples), tile by tile
    std::vector<uint32_t> tile_shadow;  // their ranges per tile, as tile_first
    // What the shadow rays were drawn from, for BM_RaysAndSampler (without MIS): per camera sample
    // that hit, its point, unit geometric normal (facing the camera) and shadow-ray origin; per
    // light sample its (u, v).
    struct ShadingPoint {
        Vec3f p, n, origin;
    };
    std::vector<ShadingPoint> points;
    std::vector<uint32_t> tile_points;    // shading points of tile t: [tile_points[t], tile_points[t + 1])
    std::vector<Point2<float>> light_uv;  // light_samples per shading point
};

// Queues the occlusion ray a light sample casts from a shading point (unit normal n, ray origin
// `origin`), as the renderer does: none for an invalid sample or one below the surface.
void AddShadowRay(const Vec3f& origin, const Vec3f& n, const LightSample<float>& ls, std::vector<RTCRay>& out) {
    if (ls.pdf > 0 && std::isfinite(ls.pdf) && Dot(ls.dir, n) > 0)
        out.push_back(MakeRTCRay(origin, ls.dir, 0, ShadowRayLength(ls.dist)));
}

// The light sampling of the scene's one light at a shading point, as the renderer does it: a rectangle technique's
// sampler (core/technique.h), or for an ellipse light the renderer's own EllipseSamplingAt (its area fallback
// where the map cannot pay, its setup kept for the point's samples).  make(p, n) -> an object with Valid() and
// Sample(uv).
// `rectangle`'s, `rectangle_cosine`'s and `triangles`': batched over a tile's points (core/rectangle_batch.h,
// core/triangles_batch.h), as the renderer takes them (TraceTileWithSampler's overload); one point at a time where
// rays are drawn (MakeRawRays).
template <Technique K>
struct BatchedRectangleSampling {
    const RectLightFrame<float>* frame;
    LightSampler<K, float> operator()(const Vec3f& p, const Vec3f& n) const { return {p, n, *frame}; }
};

template <Technique K>
auto RectSampling(const RenderScene& s) {
    const RectLightFrame<float>* frame = &s.area_lights[0].frame;
    if constexpr (K == Technique::Rectangle || K == Technique::RectangleCosine || K == Technique::Triangles) {
        return BatchedRectangleSampling<K>{frame};
    } else {
        return [frame](const Vec3f& p, const Vec3f& n) { return LightSampler<K, float>(p, n, *frame); };
    }
}

struct EllipseSampling {
    const AreaLight* light;
    Vec3f origin;
    EllipseSamplingAt at;
    bool Valid() const { return true; }  // (an invalid setup's samples have pdf 0)
    LightSample<float> Sample(Point2<float> u) { return at.Sample(*light, 0, origin, u); }
};

auto EllipseSamplingOf(const RenderScene& s, EllipseTechnique technique) {
    const AreaLight* light = &s.area_lights[0];
    return [light, technique](const Vec3f& p, const Vec3f&) {
        return EllipseSampling{light, p, EllipseSamplingAt(technique)};
    };
}

template <class MakeSampling>
RawRays MakeRawRays(const RenderScene& s, bool mis, int light_samples, MakeSampling make_sampling) {
    const AreaLight& light = s.area_lights[0];
    RawRays out;
    PCG32 rng(1);
    auto camera_sample = [&](int x, int y) {
        const Ray ray = GenerateCameraRay<false>(s.camera, x + rng.NextFloat(), y + rng.NextFloat(), {});
        RTCRayHit rh = MakeRTCRayHit(ray.o, ray.d, ray.tmin, ray.tmax);
        out.camera.push_back(rh);
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcIntersect1(s.rtc_scene, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
        // As the renderer: unit geometric normal facing the camera, offset shadow origin.
        Vec3f n = Normalize(Vec3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
        if (Dot(n, ray.d) > 0) n = -n;
        const Vec3f p = ray.o + ray.d * rh.ray.tfar;
        const Vec3f origin = OffsetOrigin(p, n);
        out.points.push_back({p, n, origin});
        auto sampler = make_sampling(p, n);
        const Frame frame = Frame::FromZ(n);
        for (int j = 0; j < light_samples; ++j) {
            const float u = rng.NextFloat(), v = rng.NextFloat();
            out.light_uv.push_back({u, v});
            AddShadowRay(origin, n, sampler.Valid() ? sampler.Sample({u, v}) : LightSample<float>{}, out.shadow);
            if (mis) {
                const float a = rng.NextFloat(), b = rng.NextFloat();
                const Vec3f d = frame.FromLocal(SampleCosineHemisphere({a, b}));
                const float t = IntersectAreaLight(light, origin, d, kInf);
                if (!std::isinf(t)) out.shadow.push_back(MakeRTCRay(origin, d, 0, ShadowRayLength(t)));
            }
        }
    };
    // Pixels in the renderer's order: 16 x 16 tiles, row by row inside each.
    constexpr int kTile = 16;
    for (int ty = 0; ty < kHeight; ty += kTile)
        for (int tx = 0; tx < kWidth; tx += kTile) {
            for (int y = ty; y < std::min(ty + kTile, kHeight); ++y)
                for (int x = tx; x < std::min(tx + kTile, kWidth); ++x)
                    for (int i = 0; i < kSamples; ++i) camera_sample(x, y);
            out.tile_first.push_back(uint32_t(out.camera.size()));
            out.tile_points.push_back(uint32_t(out.points.size()));
            out.tile_shadow.push_back(uint32_t(out.shadow.size()));
        }
    for (auto* v : {&out.tile_first, &out.tile_points, &out.tile_shadow}) v->insert(v->begin(), 0);
    return out;
}

// Traces tile `tile`'s camera rays (in place) as the renderer does: one coherent stream.
uint64_t TraceCameraTile(const RenderScene& s, const RawRays& in, size_t tile, RTCRayHit* camera) {
    const uint32_t c0 = in.tile_first[tile], c1 = in.tile_first[tile + 1];
    IntersectCameraRays(s.rtc_scene, camera + c0, c1 - c0);
    uint64_t hits = 0;
    for (uint32_t i = c0; i < c1; ++i) hits += camera[i].hit.geomID;
    return hits;
}

// Traces shadow rays[0..n) (in place) as the renderer does: one incoherent stream.
uint64_t TraceShadowRays(const RenderScene& s, RTCRay* rays, size_t n) {
    OccludeShadowRays(s.rtc_scene, rays, n, sizeof(RTCRay));
    uint64_t blocked = 0;
    for (size_t i = 0; i < n; ++i) blocked += rays[i].tfar < 0;
    return blocked;
}

// Traces rays_in per iteration, as the renderer does; the label names the case.
void RawEmbreeCase(benchmark::State& state, const RenderScene& s, const RawRays& rays_in, const std::string& label) {
    uint64_t rays = 0, samples = 0;
    const size_t secondary = rays_in.shadow.size();
    std::vector<RTCRayHit> camera;
    std::vector<RTCRay> shadow;
    for (auto _ : state) {
        camera = rays_in.camera;  // (traced in place; the copies are not timed)
        shadow = rays_in.shadow;
        const double t0 = ProcessCpuSeconds();
        uint64_t blocked = 0;
        // As the renderer traces them: per tile, the camera rays as one coherent stream, then
        // the occlusion rays queued by shading as one stream.
        for (size_t t = 0; t + 1 < rays_in.tile_first.size(); ++t) {
            blocked += TraceCameraTile(s, rays_in, t, camera.data());
            const uint32_t k0 = rays_in.tile_shadow[t], k1 = rays_in.tile_shadow[t + 1];
            blocked += TraceShadowRays(s, shadow.data() + k0, k1 - k0);
        }
        benchmark::DoNotOptimize(blocked);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
        rays += rays_in.camera.size() + secondary;
        samples += rays_in.camera.size();
    }
    state.SetLabel(label);
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["s/sample"] =
        benchmark::Counter(double(samples), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["secondary/sample"] = benchmark::Counter(double(secondary) / rays_in.camera.size());
}

// BM_RawEmbree's case on a scene of one rectangle light: arguments technique, MIS, light samples; name(technique)
// starts the label.
template <class Name>
void RectRawEmbreeCase(benchmark::State& state, const RenderScene& s, Name name) {
    const Technique technique = kAllTechniques[state.range(0)];
    const bool mis = state.range(1) != 0;
    const int light_samples = int(state.range(2));
    const RawRays rays_in = DispatchTechnique(
        technique, [&](auto tag) { return MakeRawRays(s, mis, light_samples, RectSampling<decltype(tag)::value>(s)); });
    RawEmbreeCase(state, s, rays_in, name(technique) + MisLabel(mis) + "/ls=" + std::to_string(light_samples));
}

std::string TechniqueLabel(Technique technique) { return TechniqueName(technique); }

void BM_RawEmbree(benchmark::State& state) { RectRawEmbreeCase(state, *Scene(), TechniqueLabel); }
BENCHMARK(BM_RawEmbree)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}, {1, 4}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

// Embree's call forms on the rays BM_RawEmbree traces (rectangle, no MIS, one light sample), tile by tile:
// BM_EmbreeCalls/<rays>/<form>, rays 0 the camera rays (intersection), 1 the shadow rays (occlusion); form 0 the
// renderer's streams (IntersectCameraRays / OccludeShadowRays), 1 and 2 packets of 8 and 16 rays
// (rtcIntersect8/16, rtcOccluded8/16, flagged coherent for the camera rays), 3 a ray at a time.  What issue 31 asks
// to measure before choosing (docs/renderer.md).
template <int W, class Packet>
void LoadPacket(const RTCRay* const* rays, size_t count, Packet& p, int* valid) {
    for (size_t i = 0; i < size_t(W); ++i) {
        const RTCRay& r = *rays[std::min(i, count - 1)];
        valid[i] = i < count ? -1 : 0;
        p.org_x[i] = r.org_x;
        p.org_y[i] = r.org_y;
        p.org_z[i] = r.org_z;
        p.tnear[i] = r.tnear;
        p.dir_x[i] = r.dir_x;
        p.dir_y[i] = r.dir_y;
        p.dir_z[i] = r.dir_z;
        p.time[i] = 0;
        p.tfar[i] = r.tfar;
        p.mask[i] = r.mask;
        p.id[i] = unsigned(i);
        p.flags[i] = 0;
    }
}

template <int W, class RayHitN, class RayN>
uint64_t TracePackets(const RenderScene& s, bool camera, RTCRayHit* hits, RTCRay* rays, size_t n) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    if (camera) ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    uint64_t result = 0;
    alignas(64) int valid[W];
    for (size_t first = 0; first < n; first += W) {
        const size_t count = std::min(n - first, size_t(W));
        const RTCRay* in[W];
        for (size_t i = 0; i < count; ++i) in[i] = camera ? &hits[first + i].ray : &rays[first + i];
        if (camera) {
            alignas(64) RayHitN p;
            LoadPacket<W>(in, count, p.ray, valid);
            for (int i = 0; i < W; ++i) p.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
            if constexpr (W == 8)
                rtcIntersect8(valid, s.rtc_scene, &ctx, &p);
            else
                rtcIntersect16(valid, s.rtc_scene, &ctx, &p);
            for (size_t i = 0; i < count; ++i) result += p.hit.geomID[i];
        } else {
            alignas(64) RayN p;
            LoadPacket<W>(in, count, p, valid);
            if constexpr (W == 8)
                rtcOccluded8(valid, s.rtc_scene, &ctx, &p);
            else
                rtcOccluded16(valid, s.rtc_scene, &ctx, &p);
            for (size_t i = 0; i < count; ++i) result += p.tfar[i] < 0;
        }
    }
    return result;
}

void BM_EmbreeCalls(benchmark::State& state) {
    const bool camera = state.range(0) == 0;
    const int form = int(state.range(1));
    const RenderScene& s = *Scene();
    static const RawRays rays_in = MakeRawRays(s, false, 1, RectSampling<Technique::Rectangle>(s));
    std::vector<RTCRayHit> hits;
    std::vector<RTCRay> shadow;
    uint64_t rays = 0;
    for (auto _ : state) {
        hits = rays_in.camera;
        shadow = rays_in.shadow;
        const double t0 = ProcessCpuSeconds();
        uint64_t result = 0;
        for (size_t t = 0; t + 1 < rays_in.tile_first.size(); ++t) {
            const uint32_t c0 = camera ? rays_in.tile_first[t] : rays_in.tile_shadow[t];
            const uint32_t c1 = camera ? rays_in.tile_first[t + 1] : rays_in.tile_shadow[t + 1];
            RTCRayHit* h = hits.data() + c0;
            RTCRay* r = shadow.data() + c0;
            const size_t n = c1 - c0;
            if (form == 0 && camera) {
                IntersectCameraRays(s.rtc_scene, h, n);
            } else if (form == 0) {
                OccludeShadowRays(s.rtc_scene, r, n, sizeof(RTCRay));
            } else if (form == 1) {
                result += TracePackets<8, RTCRayHit8, RTCRay8>(s, camera, h, r, n);
            } else if (form == 2) {
                result += TracePackets<16, RTCRayHit16, RTCRay16>(s, camera, h, r, n);
            } else {
                RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                for (size_t i = 0; i < n; ++i) {
                    if (camera)
                        rtcIntersect1(s.rtc_scene, &ctx, &h[i]);
                    else
                        rtcOccluded1(s.rtc_scene, &ctx, &r[i]);
                }
            }
            rays += n;
        }
        benchmark::DoNotOptimize(result);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
    }
    static const char* const kForms[] = {"stream", "packets of 8", "packets of 16", "one at a time"};
    state.SetLabel(std::string(camera ? "camera rays, " : "shadow rays, ") + kForms[form]);
    state.counters["s/ray"] =
        benchmark::Counter(double(rays), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_EmbreeCalls)
    ->ArgsProduct({{0, 1}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

// One tile of BM_RaysAndSampler: the camera stream, then per shading point the technique's
// setup and its light samples, queued as shadow rays, then the queue traced as one stream.
template <class MakeSampling>
uint64_t TraceTileWithSampler(const RenderScene& s, const RawRays& in, int light_samples, size_t tile,
                              RTCRayHit* camera, std::vector<RTCRay>& queue, const MakeSampling& make_sampling) {
    uint64_t blocked = TraceCameraTile(s, in, tile, camera);
    queue.clear();
    for (uint32_t k = in.tile_points[tile]; k < in.tile_points[tile + 1]; ++k) {
        const RawRays::ShadingPoint& sp = in.points[k];
        auto sampler = make_sampling(sp.p, sp.n);
        for (int j = 0; j < light_samples; ++j) {
            const Point2<float> uv = in.light_uv[size_t(k) * light_samples + j];
            AddShadowRay(sp.origin, sp.n, sampler.Valid() ? sampler.Sample(uv) : LightSample<float>{}, queue);
        }
    }
    return blocked + TraceShadowRays(s, queue.data(), queue.size());
}

// The same with a batched technique: the tile's points and their light samples in one batch.
template <Technique K>
uint64_t TraceTileWithSampler(const RenderScene& s, const RawRays& in, int light_samples, size_t tile,
                              RTCRayHit* camera, std::vector<RTCRay>& queue,
                              const BatchedRectangleSampling<K>& sampling) {
    uint64_t blocked = TraceCameraTile(s, in, tile, camera);
    queue.clear();
    const uint32_t first = in.tile_points[tile], count = in.tile_points[tile + 1] - first;
    static thread_local std::vector<Vec3f> origins, normals;
    static thread_local std::vector<LightSample<float>> samples;
    origins.resize(count);
    normals.resize(count);
    samples.resize(size_t(count) * light_samples);
    for (uint32_t k = 0; k < count; ++k) {
        origins[k] = in.points[first + k].p;
        normals[k] = in.points[first + k].n;
    }
    const Point2<float>* uv = &in.light_uv[size_t(first) * light_samples];
    if constexpr (K == Technique::RectangleCosine)
        SampleRectangleCosineBatch(*sampling.frame, origins.data(), normals.data(), count, uv, light_samples,
                                   samples.data());
    else if constexpr (K == Technique::Triangles)
        SampleTrianglesBatch(*sampling.frame, origins.data(), count, uv, light_samples, samples.data());
    else
        SampleRectangleBatch(*sampling.frame, origins.data(), count, uv, light_samples, samples.data());
    for (uint32_t k = 0; k < count; ++k) {
        const RawRays::ShadingPoint& sp = in.points[first + k];
        for (int j = 0; j < light_samples; ++j)
            AddShadowRay(sp.origin, sp.n, samples[size_t(k) * light_samples + j], queue);
    }
    return blocked + TraceShadowRays(s, queue.data(), queue.size());
}

// BM_RaysAndSampler/<technique>/<light samples>: BM_RawEmbree (no MIS) plus the one piece of work
// no renderer using the technique can skip -- its setup at each shading point and its map per
// light sample, from the same points and (u, v) as the raw rays (so the shadow rays are the same).
// No pattern, camera, BSDF, shading or accumulation.  (this - raw) / raw is the least a renderer
// calling this core's sampler per shading point and light sample adds to the raw rays.
// BM_RaysAndSampler and its variants: rays_in (drawn with make_sampling) traced tile by tile, with the light
// sampling make_sampling makes at each point timed too; the label names the case.
template <class MakeSampling>
void RaysAndSamplerCase(benchmark::State& state, const RenderScene& s, const RawRays& rays_in, int light_samples,
                        const MakeSampling& make_sampling, const std::string& label) {
    uint64_t rays = 0, samples = 0, shadow_rays = 0;
    std::vector<RTCRayHit> camera;
    std::vector<RTCRay> queue;
    for (auto _ : state) {
        camera = rays_in.camera;  // (traced in place; the copy is not timed)
        shadow_rays = 0;
        const double t0 = ProcessCpuSeconds();
        uint64_t blocked = 0;
        for (size_t t = 0; t + 1 < rays_in.tile_first.size(); ++t) {
            blocked += TraceTileWithSampler(s, rays_in, light_samples, t, camera.data(), queue, make_sampling);
            shadow_rays += queue.size();
        }
        benchmark::DoNotOptimize(blocked);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
        rays += rays_in.camera.size() + shadow_rays;
        samples += rays_in.camera.size();
    }
    if (shadow_rays != rays_in.shadow.size()) state.SkipWithError("shadow rays differ from BM_RawEmbree's");
    state.SetLabel(label);
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["s/sample"] =
        benchmark::Counter(double(samples), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// BM_RaysAndSampler's case on a scene of one rectangle light: arguments technique, light samples; name(technique)
// starts the label.
template <class Name>
void RectRaysAndSamplerCase(benchmark::State& state, const RenderScene& s, Name name) {
    const Technique technique = kAllTechniques[state.range(0)];
    const int light_samples = int(state.range(1));
    DispatchTechnique(technique, [&](auto tag) {
        const auto sampling = RectSampling<decltype(tag)::value>(s);
        RaysAndSamplerCase(state, s, MakeRawRays(s, false, light_samples, sampling), light_samples, sampling,
                           name(technique) + "/no-mis/ls=" + std::to_string(light_samples));
    });
}

void BM_RaysAndSampler(benchmark::State& state) { RectRaysAndSamplerCase(state, *Scene(), TechniqueLabel); }
BENCHMARK(BM_RaysAndSampler)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {1, 4}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

// The disk scene (kDiskLight): the renderer with each ellipse technique, its raw rays and its rays + sampler, as
// BM_Render / BM_RawEmbree / BM_RaysAndSampler (the ellipse sampling is the renderer's own EllipseSamplingAt).
// Labels "<ellipse technique> (disk scene)/...".
// Index 2 of BM_DiskRawEmbree / BM_DiskRaysAndSampler (no render: the renderer cannot be told to): the core's
// spherical ellipse map at every shading point, without the renderer's area fallback where area sampling is
// nearly uniform (core/ellipse_map_choice.h, which in this scene takes almost every point: counter map_share):
// what the map itself costs.
constexpr int kDiskMapEverywhere = 2;

std::string DiskLabel(int index) {
    if (index == kDiskMapEverywhere) return "spherical_ellipse map everywhere (disk scene)";
    return std::string(EllipseTechniqueName(kAllEllipseTechniques[index])) + " (disk scene)";
}

// f(make_sampling) with the disk scene's light sampling number `index` (see kDiskMapEverywhere).
template <class F>
decltype(auto) DispatchDiskSampling(const RenderScene& s, int index, F&& f) {
    if (index != kDiskMapEverywhere) return f(EllipseSamplingOf(s, kAllEllipseTechniques[index]));
    const EllipseLightFrame<float>* frame = &s.area_lights[0].ellipse_frame;
    return f([frame](const Vec3f& p, const Vec3f& n) {
        return EllipseSampler<EllipseTechnique::SphericalEllipse, float>(p, n, *frame);
    });
}

void BM_DiskRender(benchmark::State& state) {
    RenderOptions o = BenchOptions(Technique::Rectangle, state.range(1) != 0, Pattern::Sobol, int(state.range(2)));
    o.ellipse_technique = kAllEllipseTechniques[state.range(0)];
    RenderCase(state, DiskScene(), o,
               DiskLabel(int(state.range(0))) + MisLabel(o.mis == MisMode::Balance) + "/" + PatternName(o.pattern) +
                   "/ls=" + std::to_string(o.light_samples));
}
void BM_DiskRawEmbree(benchmark::State& state) {
    const RenderScene& s = *DiskScene();
    const bool mis = state.range(1) != 0;
    const int light_samples = int(state.range(2));
    const RawRays rays_in = DispatchDiskSampling(
        s, int(state.range(0)), [&](const auto& sampling) { return MakeRawRays(s, mis, light_samples, sampling); });
    RawEmbreeCase(state, s, rays_in,
                  DiskLabel(int(state.range(0))) + MisLabel(mis) + "/ls=" + std::to_string(light_samples));
}
void BM_DiskRaysAndSampler(benchmark::State& state) {
    const RenderScene& s = *DiskScene();
    const int light_samples = int(state.range(1));
    DispatchDiskSampling(s, int(state.range(0)), [&](const auto& sampling) {
        const RawRays rays_in = MakeRawRays(s, false, light_samples, sampling);
        RaysAndSamplerCase(state, s, rays_in, light_samples, sampling,
                           DiskLabel(int(state.range(0))) + "/no-mis/ls=" + std::to_string(light_samples));
        // The share of shading points where spherical_ellipse runs its map (elsewhere it samples by area, no setup).
        size_t mapped = 0;
        for (const RawRays::ShadingPoint& sp : rays_in.points)
            mapped += !EllipseAreaSamplingSuffices(sp.p, s.area_lights[0].ellipse_frame);
        state.counters["map_share"] =
            benchmark::Counter(double(mapped) / double(std::max<size_t>(rays_in.points.size(), 1)));
    });
}
BENCHMARK(BM_DiskRender)
    ->ArgsProduct({{0, 1}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);
BENCHMARK(BM_DiskRawEmbree)
    ->ArgsProduct({{0, 1}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);
BENCHMARK(BM_DiskRawEmbree)
    ->Args({kDiskMapEverywhere, 0, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);
BENCHMARK(BM_DiskRaysAndSampler)
    ->ArgsProduct({{0, 1, kDiskMapEverywhere}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

// The glossy + textured scene (kTextured | kGlossySpheres: GGX spheres of roughness 0.3, the ground's colour from
// a texture) with a rectangle technique: the glossy kernel's cost against the same raw rays.  Its raw rays' BSDF
// directions (with MIS) are cosine-distributed as in BM_RawEmbree, not the GGX lobe's: with MIS its raw floor is
// an estimate (compare secondary/sample with the render's rays/s x s/sample - 1).  Labels "<technique> (glossy
// textured scene)/...".
std::string GlossyLabel(Technique t) { return std::string(TechniqueName(t)) + " (glossy textured scene)"; }

void BM_GlossyRender(benchmark::State& state) {
    const RenderOptions o =
        BenchOptions(kAllTechniques[state.range(0)], state.range(1) != 0, Pattern::Sobol, int(state.range(2)));
    RenderCase(state, GlossyScene(), o,
               GlossyLabel(o.techniques[0]) + MisLabel(o.mis == MisMode::Balance) + "/" + PatternName(o.pattern) +
                   "/ls=" + std::to_string(o.light_samples));
}
void BM_GlossyRawEmbree(benchmark::State& state) { RectRawEmbreeCase(state, *GlossyScene(), GlossyLabel); }
void BM_GlossyRaysAndSampler(benchmark::State& state) { RectRaysAndSamplerCase(state, *GlossyScene(), GlossyLabel); }
// Rectangle (kAllTechniques[2]), without and with balance MIS, one light sample.
BENCHMARK(BM_GlossyRender)
    ->ArgsProduct({{2}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);
BENCHMARK(BM_GlossyRawEmbree)
    ->ArgsProduct({{2}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);
BENCHMARK(BM_GlossyRaysAndSampler)
    ->ArgsProduct({{2}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

void BM_DiffuseKernel(benchmark::State& state) {
    RenderOptions o;
    o.mis = MisMode::Balance;  // what these measure (not the defaults)
    o.light_selection = LightSelection::Power;
    o.techniques = {Technique::Rectangle};
    o.threads = 1;
    o.force_all_features = state.range(0) != 0;
    for (auto _ : state) {
        const double t0 = ProcessCpuSeconds();
        Renderer r(Scene(), o);
        r.Render(kSamples);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
    }
    state.SetLabel(o.force_all_features ? "generic kernel: medium+glossy+dof compiled in, off at run time"
                                        : "specialised diffuse kernel");
    state.counters["s/sample"] = benchmark::Counter(double(kWidth) * kHeight * kSamples * state.iterations(),
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_DiffuseKernel)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

// The diffuse scene (0) and the same scene with its base colour from a texture (1): what a texture costs
// where it is used.  That a scene without textures pays nothing for them is the A/B of BM_DiffuseKernel/0
// between builds before and after textures (ab_bench_render.py).
void BM_TexturedKernel(benchmark::State& state) {
    static const std::shared_ptr<RenderScene> textured = BenchScene(kTextured);
    RenderOptions o;
    o.mis = MisMode::Balance;  // what these measure (not the defaults)
    o.light_selection = LightSelection::Power;
    o.techniques = {Technique::Rectangle};
    o.threads = 1;
    for (auto _ : state) {
        const double t0 = ProcessCpuSeconds();
        Renderer r(state.range(0) ? textured : Scene(), o);
        r.Render(kSamples);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
    }
    state.SetLabel(state.range(0) ? "base colour from a texture" : "constant base colour");
    state.counters["s/sample"] = benchmark::Counter(double(kWidth) * kHeight * kSamples * state.iterations(),
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_TexturedKernel)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

// The bench scene's media (BM_MediumKernel): coefficients and boxes.
const Spectrum kFogScattering(0.15f, 0.15f, 0.15f), kFogAbsorption(0.03f, 0.03f, 0.03f);
constexpr float kFogAnisotropy = 0.3f;

void AddBoxVolume(RenderScene& s, Vec3f lo, Vec3f hi, float share) {
    std::vector<float> v;
    for (int i = 0; i < 8; ++i) {  // vertex index = x + 2 y + 4 z
        v.push_back(i & 1 ? hi.x : lo.x);
        v.push_back(i & 2 ? hi.y : lo.y);
        v.push_back(i & 4 ? hi.z : lo.z);
    }
    const int32_t t[] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                         2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    s.AddVolume("fog", v.data(), 8, t, 12, kFogScattering * share, kFogAbsorption * share, kFogAnisotropy);
}

void BM_MediumKernel(benchmark::State& state) {
    static const std::shared_ptr<RenderScene> scenes[] = {
        BenchScene(0, [](RenderScene& s) { s.SetMedium(kFogScattering, kFogAbsorption, kFogAnisotropy); }),
        BenchScene(0,
                   [](RenderScene& s) {
                       AddBoxVolume(s, {-30, -30, -30}, {30, 30, 30}, 1);
                   }),
        BenchScene(0,
                   [](RenderScene& s) {
                       s.SetMedium(kFogScattering * 0.5f, kFogAbsorption * 0.5f, kFogAnisotropy);
                       AddBoxVolume(s, {-30, -30, -30}, {30, 30, 30}, 0.5f);
                   }),
        BenchScene(0, [](RenderScene& s) {
            AddBoxVolume(s, {-2, -1.5f, 0.01f}, {2, 1.5f, 1.3f}, 1);
        })};
    static const char* const labels[] = {"world medium", "a box around the scene (same image)",
                                         "world medium + box, half each", "a box around the spheres"};
    RenderOptions o;
    o.mis = MisMode::Balance;  // what these measure (not the defaults)
    o.light_selection = LightSelection::Power;
    o.techniques = {Technique::Rectangle};
    o.threads = 1;
    uint64_t rays = 0;
    for (auto _ : state) {
        const double t0 = ProcessCpuSeconds();
        Renderer r(scenes[state.range(0)], o);
        r.Render(kSamples);
        state.SetIterationTime(ProcessCpuSeconds() - t0);
        const TechniqueStats st = r.Stats(0);
        rays += st.rays + st.camera_rays;
    }
    state.SetLabel(labels[state.range(0)]);
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["s/sample"] = benchmark::Counter(double(kWidth) * kHeight * kSamples * state.iterations(),
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_MediumKernel)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->ComputeStatistics("min", MinOf);

}  // namespace
}  // namespace sphrect::render

BENCHMARK_MAIN();
