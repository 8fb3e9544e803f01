// ns per sample and per setup of every technique, float and double, with the
// textbook single-precision spherical-rectangle formula (the paper's code as in
// Blender 3.4 Cycles) as the baseline.  The stages and their inputs are
// core/sampler_timing.h, which the study's cost table runs through the module too.
// Ellipse (disk) lights: the same stages for ellipse_technique.h's techniques on the ellipse
// inscribed in sampler_timing's 1 x 1.5 light, seen from the same shading points, named
// "Ellipse<stage>/<technique>/<precision>" (next to the rectangle map's "<stage>/rectangle/...").
//
// The batched rectangle and triangles (core/rectangle_batch.h, core/triangles_batch.h) against the scalar setup + map
// they batch, per point and one sample (as the renderer with one light sample): "SetupAndSample/<technique>/scalar"
// and ".../batch" (the instruction set the batch runs on in its label), over sampler_timing's 64 shading points.
//
// rectangle_ltc (core only, not a Technique yet, so not in sampler_timing's list): the Setup, SetupFromFrame, Sample,
// SampleOffAxis and Pdf stages as there, with wo the mirror direction of the light's centre about n (the GGX lobe's
// peak on the light) and alpha 0.2, named "<stage>/rectangle_ltc/float".
//
//   build/native/bench/bench_sampling [--benchmark_filter=Sample]
#include <benchmark/benchmark.h>

#include <string>

#include <vector>

#include "core/ellipse_technique.h"
#include "core/rectangle_batch.h"
#include "core/rectangle_ltc.h"
#include "core/sampler_timing.h"
#include "core/triangles_batch.h"

namespace {

using namespace sphrect;
using namespace sphrect::sampler_timing;

template <class T>
EllipseLight<T> Ellipse() {
    const RectLight<T> r = Light<T>();
    return {r.corner + r.ex * T(0.5) + r.ey * T(0.5), r.ex * T(0.5), r.ey * T(0.5), true};
}

template <EllipseTechnique K, class T>
auto EllipseSetupStage() {
    return [L = Ellipse<T>()](size_t i) { return EllipseSampler<K, T>(Origins<T>()[i & 63], Vec3<T>(0, 0, 1), L); };
}

template <EllipseTechnique K, class T>
auto EllipseSetupFromFrameStage() {
    return [F = MakeEllipseLightFrame(Ellipse<T>())](size_t i) {
        return EllipseSampler<K, T>(Origins<T>()[i & 63], Vec3<T>(0, 0, 1), F);
    };
}

// Sampling from `origin` (default: the rectangle stages' shading point).
template <EllipseTechnique K, class T>
auto EllipseSampleStage(Vec3<T> origin = Vec3<T>(T(0.2), T(-0.1), T(0.5))) {
    const EllipseSampler<K, T> s(origin, Vec3<T>(0, 0, 1), Ellipse<T>());
    return [s](size_t i) { return s.Sample(UVs<T>()[i & 1023]); };
}

template <EllipseTechnique K, class T>
auto EllipsePDFStage() {
    const EllipseLight<T> L = Ellipse<T>();
    const EllipseSampler<K, T> s(Vec3<T>(T(0.2), T(-0.1), T(0.5)), Vec3<T>(0, 0, 1), L);
    std::vector<Vec3<T>> pts;
    for (const Point2<T>& uv : UVs<T>())
        pts.push_back(L.center + L.axis_u * (uv.u - T(0.5)) + L.axis_v * (uv.v - T(0.5)));
    return [s, pts](size_t i) { return s.PDF(pts[i & 1023]); };
}

template <class F>
void ForEachEllipseStage(F&& f) {
    for (EllipseTechnique t : kAllEllipseTechniques)
        DispatchEllipseTechnique(t, [&](auto tag) {
            constexpr EllipseTechnique K = decltype(tag)::value;
            const std::string name = EllipseTechniqueName(K);
            f("EllipseSetup/" + name + "/float", EllipseSetupStage<K, float>());
            f("EllipseSetup/" + name + "/double", EllipseSetupStage<K, double>());
            f("EllipseSetupFromFrame/" + name + "/float", EllipseSetupFromFrameStage<K, float>());
            f("EllipseSample/" + name + "/float", EllipseSampleStage<K, float>());
            f("EllipseSample/" + name + "/double", EllipseSampleStage<K, double>());
            // Nearly a hemisphere (1e-3 above the interior) and nearly edge-on (1e-4 beside).
            f("EllipseSampleClose/" + name + "/float", EllipseSampleStage<K, float>(Vec3f(0.1f, 0.2f, 2.001f)));
            f("EllipseSampleEdgeOn/" + name + "/float", EllipseSampleStage<K, float>(Vec3f(1.5f, 0.1f, 2.0001f)));
            f("EllipsePdf/" + name + "/float", EllipsePDFStage<K, float>());
        });
}

template <class Stage>
void Register(const std::string& name, Stage stage) {
    benchmark::RegisterBenchmark(name.c_str(), [stage](benchmark::State& state) {
        size_t i = 0;
        for (auto _ : state) {
            auto result = stage(i++);
            benchmark::DoNotOptimize(result);
        }
    });
}

// One setup and one sample per point of a technique, the scalar way (scalar(origin, frame, uv)) and batched
// (batch(frame, origins, n, uv, m, out), returning the points it vectorised).
template <class Scalar, class Batch>
void RegisterSetupAndSampleOf(const std::string& technique, Scalar scalar, Batch batch) {
    const RectLightFrame<float> frame = MakeRectLightFrame(Light<float>());
    const std::vector<Vec3f>& origins = Origins<float>();
    std::vector<Point2<float>> uv;
    for (size_t i = 0; i < origins.size(); ++i) uv.push_back({float((i * 37 % 64) + 0.5f) / 64, float(i + 0.5f) / 64});
    benchmark::RegisterBenchmark(("SetupAndSample/" + technique + "/scalar").c_str(), [=](benchmark::State& state) {
        std::vector<LightSample<float>> out(origins.size());
        for (auto _ : state) {
            for (size_t i = 0; i < origins.size(); ++i) out[i] = scalar(origins[i], frame, uv[i]);
            benchmark::DoNotOptimize(out.data());
        }
        state.SetItemsProcessed(int64_t(state.iterations() * origins.size()));
    });
    benchmark::RegisterBenchmark(("SetupAndSample/" + technique + "/batch").c_str(), [=](benchmark::State& state) {
        std::vector<LightSample<float>> out(origins.size());
        size_t vector_points = 0;
        for (auto _ : state) {
            vector_points = batch(frame, origins.data(), origins.size(), uv.data(), 1, out.data());
            benchmark::DoNotOptimize(out.data());
        }
        state.SetItemsProcessed(int64_t(state.iterations() * origins.size()));
        state.SetLabel(std::string(RectangleBatchTarget()) + ", " + std::to_string(vector_points) + "/" +
                       std::to_string(origins.size()) + " points vectorised");
    });
}

void RegisterSetupAndSample() {
    RegisterSetupAndSampleOf(
        "rectangle",
        [](const Vec3f& o, const RectLightFrame<float>& f, Point2<float> uv) {
            return SampleRectangle(MakeRectangleSetup(o, f), uv);
        },
        SampleRectangleBatch);
    RegisterSetupAndSampleOf(
        "triangles",
        [](const Vec3f& o, const RectLightFrame<float>& f, Point2<float> uv) {
            return SampleTriangles(MakeTrianglesSetup(o, f), uv);
        },
        SampleTrianglesBatch);
}

// wo for rectangle_ltc's stages: the mirror direction of the light's centre about n from o.
Vec3f MirrorOfLightCentre(const Vec3f& o, const Vec3f& n) {
    const RectLight<float> L = Light<float>();
    const Vec3f c = Normalize(L.corner + L.ex * 0.5f + L.ey * 0.5f - o);
    return n * (2 * Dot(c, n)) - c;
}

void RegisterLtcStages() {
    constexpr float kAlpha = 0.2f;
    const Vec3f up(0, 0, 1), tilted = Normalize(Vec3f(1, 0, 0.2f)), o(0.2f, -0.1f, 0.5f);
    std::vector<Vec3f> wo;
    for (const Vec3f& p : Origins<float>()) wo.push_back(MirrorOfLightCentre(p, up));
    Register("Setup/rectangle_ltc/float", [L = Light<float>(), wo](size_t i) {
        return MakeRectangleLtcSetup(Origins<float>()[i & 63], Vec3f(0, 0, 1), wo[i & 63], kAlpha, L);
    });
    Register("SetupFromFrame/rectangle_ltc/float", [F = MakeRectLightFrame(Light<float>()), wo](size_t i) {
        return MakeRectangleLtcSetup(Origins<float>()[i & 63], Vec3f(0, 0, 1), wo[i & 63], kAlpha, F);
    });
    const RectangleLtcSetup<float> s = MakeRectangleLtcSetup(o, up, MirrorOfLightCentre(o, up), kAlpha, Light<float>());
    Register("Sample/rectangle_ltc/float", [s](size_t i) { return SampleRectangleLtc(s, UVs<float>()[i & 1023]); });
    const RectangleLtcSetup<float> off =
        MakeRectangleLtcSetup(o, tilted, MirrorOfLightCentre(o, tilted), kAlpha, Light<float>());
    Register("SampleOffAxis/rectangle_ltc/float",
             [off](size_t i) { return SampleRectangleLtc(off, UVs<float>()[i & 1023]); });
    std::vector<Vec3f> pts;
    const RectLight<float> L = Light<float>();
    for (const Point2<float>& uv : UVs<float>()) pts.push_back(L.corner + L.ex * uv.u + L.ey * uv.v);
    Register("Pdf/rectangle_ltc/float", [s, pts](size_t i) { return RectangleLtcPDF(s, pts[i & 1023]); });
}

}  // namespace

int main(int argc, char** argv) {
    sphrect::sampler_timing::ForEachStage([](const std::string& name, auto stage) { Register(name, stage); });
    ForEachEllipseStage([](const std::string& name, auto stage) { Register(name, stage); });
    RegisterSetupAndSample();
    RegisterLtcStages();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
