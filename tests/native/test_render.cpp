// Unit tests of the renderer's building blocks (BSDF, phase function, equi-angular sampling,
// lights, camera) and of the Renderer's threading (determinism, cancellation).
// Statistical checks use fixed seeds and 6-sigma bounds (false-failure rate < 1e-8 each).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <cmath>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "direction_quadrature.h"
#include "core/rng.h"
#include "render/bsdf.h"
#include "render/camera.h"
#include "render/integrator/light_sampling_at.h"
#include "render/lights.h"
#include "render/medium.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace sphrect::render {
namespace {

std::vector<Bsdf> TestMaterials() {
    return {MakeDiffuseBsdf({0.7f, 0.5f, 0.3f}), MakeLambertGgxBsdf({0.8f, 0.6f, 0.4f}, 0.5f, 0.0f, 0.5f),
            MakeLambertGgxBsdf({0.9f, 0.7f, 0.3f}, 0.25f, 1.0f, 0.5f),
            MakeLambertGgxBsdf({0.2f, 0.2f, 0.8f}, 0.8f, 0.3f, 1.0f)};
}

TEST(RenderBsdf, PDFIsTheDensityOfItsSamples) {
    // Visible-normal samples reflected below the horizon are rejected (pdf 0), so the pdf over
    // the upper hemisphere integrates to the fraction of accepted samples, not to 1.
    PCG32 rng(7);
    for (const Bsdf& m : TestMaterials()) {
        for (float cos_o : {0.9f, 0.5f, 0.15f}) {
            const Vec3f wo = SphericalDirection(cos_o, 0.3f);
            const double total = IntegrateSphere([&](const Vec3f& wi) { return BsdfPDF<true>(m, wo, wi); }, 800, 400);
            const int n = 20000;
            int accepted = 0;
            for (int i = 0; i < n; ++i) {
                const BsdfSample s = SampleBsdf<true>(m, wo, {rng.NextFloat(), rng.NextFloat()});
                if (s.pdf == 0) continue;
                ++accepted;
                // Sampled directions report the pdf and value the evaluation functions give.
                EXPECT_NEAR(s.pdf, BsdfPDF<true>(m, wo, s.wi), 1e-3f * s.pdf);
                const Spectrum f = EvalBsdf<true>(m, wo, s.wi);
                EXPECT_NEAR(s.f.x, f.x, 1e-4f * (1 + f.x));
            }
            const double fraction = double(accepted) / n;
            EXPECT_LE(total, 1.005);
            EXPECT_NEAR(total, fraction, 6 * 0.5 / std::sqrt(double(n)) + 0.005)
                << "alpha " << m.alpha << " cos_o " << cos_o;
            if (!m.glossy) {
                EXPECT_NEAR(total, 1.0, 0.005);
            }
        }
    }
}

TEST(RenderBsdf, SamplingEstimatesTheAlbedoOfTheQuadrature) {
    // integral f cos over the hemisphere: by quadrature, and by importance sampling f cos / pdf.
    PCG32 rng(11);
    for (const Bsdf& m : TestMaterials()) {
        const Vec3f wo = SphericalDirection(0.6f, 1.0f);
        const double reference = IntegrateSphere(
            [&](const Vec3f& wi) { return wi.z > 0 ? EvalBsdf<true>(m, wo, wi).x * wi.z : 0.0f; }, 800, 400);
        const int n = 200000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
            const BsdfSample s = SampleBsdf<true>(m, wo, {rng.NextFloat(), rng.NextFloat()});
            const double x = s.pdf > 0 ? s.f.x * s.wi.z / s.pdf : 0.0;
            sum += x;
            sum2 += x * x;
        }
        const double mean = sum / n, sigma = std::sqrt((sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, reference, 6 * sigma + 0.005 * reference) << "alpha " << m.alpha;
    }
}

TEST(RenderBsdf, DiffuseKernelIgnoresTheGlossyLobe) {
    const Bsdf m = MakeLambertGgxBsdf({0.5f, 0.5f, 0.5f}, 0.3f, 0.0f, 0.5f);
    const Vec3f wo = SphericalDirection(0.8f, 0), wi = SphericalDirection(0.8f, kPi);
    EXPECT_FLOAT_EQ(EvalBsdf<false>(m, wo, wi).x, m.diffuse.x * kInvPi);
    EXPECT_GT(EvalBsdf<true>(m, wo, wi).x, EvalBsdf<false>(m, wo, wi).x);  // mirror direction: a highlight
}

TEST(RenderMedium, HenyeyGreensteinIsNormalisedAndSampledWithMeanCosineG) {
    PCG32 rng(3);
    const Vec3f axis = Normalize(Vec3f(0.2f, -0.5f, 0.8f));
    for (float g : {-0.6f, 0.0f, 0.3f, 0.85f}) {
        EXPECT_NEAR(IntegrateSphere([&](const Vec3f& w) { return HenyeyGreenstein(w.z, g); }, 4000, 4), 1.0, 2e-3);
        const int n = 100000;
        double sum = 0;
        for (int i = 0; i < n; ++i)
            sum += Dot(SampleHenyeyGreenstein(axis, g, {rng.NextFloat(), rng.NextFloat()}), axis);
        EXPECT_NEAR(sum / n, g, 6 * 0.58 / std::sqrt(double(n)));  // E[cos] = g, sd(cos) <= 1/sqrt(3)
    }
}

TEST(RenderMedium, EquiAngularPDFIsNormalisedAndMatchesItsSamples) {
    const Vec3f o(0, 0, 0), d(1, 0, 0), c(2.0f, 0.7f, -0.2f);
    for (float tmax : {1.0f, 5.0f, kInf}) {
        const EquiAngular e = MakeEquiAngular(o, d, tmax, c);
        ASSERT_TRUE(e.valid);
        const double upper = std::isinf(tmax) ? 2e4 : tmax;
        double integral = 0;
        const int n = 400000;
        for (int i = 0; i < n; ++i) integral += EquiAngularPDF(e, float((i + 0.5) * upper / n)) * upper / n;
        EXPECT_NEAR(integral, 1.0, std::isinf(tmax) ? 2e-3 : 1e-4);  // the tail beyond 2e4 is ~1e-5
        // Inverse cdf: u -> t is monotone and stays in the segment.
        float last = -1;
        for (float u : {0.0f, 0.1f, 0.5f, 0.9f, 0.999f}) {
            const float t = SampleEquiAngular(e, u);
            EXPECT_GE(t, last);
            EXPECT_GE(t, -1e-5f);
            EXPECT_LE(t, tmax);
            last = t;
        }
    }
    EXPECT_FALSE(MakeEquiAngular(o, d, 3.0f, Vec3f(1, 0, 0)).valid);  // centre on the ray
}

TEST(RenderLights, SampledPointsAreFoundByIntersection) {
    PCG32 rng(5);
    const AreaLight rect = MakeRectAreaLight({-1, 2, 3}, {2, 0, 0}, {0, 0, 1.5f}, {1, 1, 1}, false, true);
    const AreaLight ellipse = MakeEllipseAreaLight({0, 0, 4}, {0.5f, 0, 0}, {0, 0.8f, 0}, {1, 1, 1}, true, true);
    const Vec3f origin(0.2f, -0.3f, 0.1f);
    for (int i = 0; i < 1000; ++i) {
        const Point2<float> u{rng.NextFloat(), rng.NextFloat()};
        const LightSample<float> s = SampleEllipseArea(ellipse, origin, u);
        ASSERT_GT(s.pdf, 0);
        EXPECT_NEAR(IntersectAreaLight(ellipse, origin, s.dir, kInf), s.dist, 1e-4f * s.dist);
        EXPECT_NEAR(EllipseAreaPDF(ellipse, origin, s.point), s.pdf, 1e-3f * s.pdf);
        const Vec3f p = rect.frame.light.corner + rect.frame.light.ex * u.u + rect.frame.light.ey * u.v;
        const Vec3f w = Normalize(p - origin);
        EXPECT_NEAR(IntersectAreaLight(rect, origin, w, kInf), Length(p - origin), 1e-4f);
    }
    // One-sided: cross(ex, ey) = (0, -3, 0) faces -y, the origin's side.
    EXPECT_FALSE(IsBlack(EmittedRadiance(rect, origin - rect.center)));
    EXPECT_TRUE(IsBlack(EmittedRadiance(rect, rect.center - origin)));
    EXPECT_EQ(IntersectAreaLight(rect, origin, Vec3f(0, 0, 1), kInf), kInf);
}

// Emissive triangles sampled by solid angle (spherical triangle map, area fallback when tiny): in the
// ordinary and the hard cases every valid sample lies on the triangle (found by intersection at its
// distance), its pdf is the one TriangleSolidAnglePDF gives the returned point, and E[1 / pdf] is the
// triangle's solid angle (each branch unbiased; 64 x 64 stratified points, tolerance 1%).  A point in
// the triangle's plane sees no solid angle: pdf 0, no sample.
TEST(RenderLights, TriangleLightSamplesBySolidAngleInHardCases) {
    struct Case {
        const char* name;
        Vec3f v0, v1, v2, origin;
    };
    const Case cases[] = {
        {"ordinary", {-1, 0.5f, 2}, {1, -0.3f, 2.2f}, {0.2f, 1, 1.8f}, {0.1f, 0.2f, 0}},
        {"tiny", {0, 0, 1}, {1e-4f, 0, 1}, {0, 1e-4f, 1}, {0.3f, 0, 0}},                // ~5e-9 sr: area fallback
        {"small", {0, 0, 1}, {1e-3f, 0, 1}, {0, 1e-3f, 1}, {0.3f, 0, 0}},               // ~5e-7 sr: Arvo's map
        {"distant", {-1, -1, 1e4f}, {1, -0.5f, 1e4f}, {0, 1, 1e4f}, {0, 0, 0}},         // ~1e-8 sr: area fallback
        {"grazing", {0, -1, 1e-3f}, {0, 1, 1e-3f}, {0, 0, 1}, {1e-3f, 0.1f, 0.2f}},     // origin 1e-3 off its plane
        {"near", {-1, -1, 1e-3f}, {1, -1, 1e-3f}, {0, 1, 1e-3f}, {0, 0, 0}},            // nearly a hemisphere
        {"edge-on", {-1, -1, 1e-6f}, {1, -1, 1e-6f}, {0, 1, 1e-6f}, {0.1f, -1.2f, 0}},  // beside an edge
        {"edge-on far", {-1, -1, 1e-6f}, {1, -1, 1e-6f}, {0, 1, 1e-6f}, {30, -40, 0}},
        {"under an edge", {-1, -1, 1e-6f}, {1, -1, 1e-6f}, {0, 1, 1e-6f}, {0.1f, -1, 0}},  // ~pi sr
        {"under a vertex", {-1, -1, 1e-7f}, {1, -1, 1e-7f}, {0, 1, 1e-7f}, {1, -1, 0}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const AreaLight l = MakeTriangleAreaLight(c.v0, c.v1, c.v2, {1, 1, 1});
        const TriangleSolidAngleSetup setup = MakeTriangleSolidAngleSetup(l, c.origin);
        ASSERT_TRUE(setup.valid);
        // Only seen edge-on with ~pi sr is the solid angle recomputed in the plane's frame (area_error 0).
        EXPECT_EQ(setup.tri.area_error == 0, std::string(c.name) == "under an edge");
        const Vec3d o(c.origin);
        const Vec3d a = Vec3d(c.v0) - o, b = Vec3d(c.v1) - o, d = Vec3d(c.v2) - o;
        const double omega = SphericalTriangleSolidAngle(a, b, d, Length(a), Length(b), Length(d));
        double inv_pdf_sum = 0;
        const int n = 64;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                const Point2<float> u{(i + 0.5f) / n, (j + 0.5f) / n};
                const LightSample<float> s = SampleTriangleSolidAngle(setup, l, c.origin, u);
                ASSERT_GT(s.pdf, 0);
                ASSERT_TRUE(std::isfinite(s.pdf));
                EXPECT_EQ(TriangleSolidAnglePDF(setup, l, c.origin, s.point), s.pdf);
                EXPECT_NEAR(IntersectAreaLight(l, c.origin, s.dir, kInf), s.dist, 1e-3f * s.dist);
                inv_pdf_sum += 1.0 / s.pdf;
            }
        EXPECT_NEAR(inv_pdf_sum / (n * n), omega, 1e-2 * omega);
        EXPECT_NEAR(setup.tri.area, omega, 1e-6 * omega);  // (the light's edges are rounded to float)
    }
    const AreaLight flat = MakeTriangleAreaLight({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1});
    const TriangleSolidAngleSetup in_plane = MakeTriangleSolidAngleSetup(flat, {2, 3, 0});
    EXPECT_FALSE(in_plane.valid);
    EXPECT_EQ(SampleTriangleSolidAngle(in_plane, flat, {2, 3, 0}, {0.5f, 0.5f}).pdf, 0);
    EXPECT_EQ(TriangleSolidAnglePDF(in_plane, flat, {2, 3, 0}, {0.2f, 0.2f, 0}), 0);
}

// A scene's emissive quad that is an exact rectangle is one rectangle light; a non-rectangular one two
// triangles; a zero-area emissive triangle is skipped with one warning; non-emissive scenes get none.
TEST(RenderLights, EmissiveMeshesBecomeAreaLights) {
    auto scene_with = [](const std::vector<float>& v, const std::vector<int32_t>& t) {
        auto s = std::make_unique<RenderScene>();
        CameraModel camera;
        camera.width = camera.height = 4;
        camera.half_width = camera.half_height = 0.4f;
        s->SetCamera(camera);
        s->AddMaterial(DiffuseMaterial({0.5f, 0.5f, 0.5f}));
        s->AddMaterial(DiffuseMaterial({0, 0, 0}, {3, 3, 3}));
        const std::vector<int32_t> ids(t.size() / 3, 1);
        s->AddMesh("m", v.data(), v.size() / 3, t.data(), t.size() / 3, nullptr, ids.data());
        s->Commit();
        return s;
    };
    const std::vector<int32_t> quad = {0, 1, 2, 0, 2, 3};
    auto rect = scene_with({0, 0, 2, 2, 0, 2, 2, 1, 2, 0, 1, 2}, quad);
    ASSERT_EQ(rect->area_lights.size(), 1u);
    EXPECT_EQ(rect->area_lights[0].shape, AreaShape::Rectangle);
    EXPECT_NEAR(rect->area_lights[0].area, 2.0f, 1e-6f);
    EXPECT_TRUE(rect->area_lights[0].on_mesh && rect->area_lights[0].two_sided);
    EXPECT_EQ(rect->meshes[0].triangle_light, (std::vector<int32_t>{0, 0}));
    auto kite = scene_with({0, 0, 2, 2, 0, 2, 2.5f, 1, 2, 0, 1, 2}, quad);
    ASSERT_EQ(kite->area_lights.size(), 2u);
    EXPECT_EQ(kite->area_lights[1].shape, AreaShape::Triangle);
    auto degenerate = scene_with({0, 0, 2, 1, 0, 2, 2, 0, 2, 0, 1, 2}, {0, 1, 2, 0, 1, 3});
    EXPECT_EQ(degenerate->area_lights.size(), 1u);
    ASSERT_EQ(degenerate->warnings.size(), 1u);
    EXPECT_NE(degenerate->warnings[0].find("1 emissive triangle with zero area"), std::string::npos);
    EXPECT_EQ(degenerate->meshes[0].triangle_light, (std::vector<int32_t>{-1, 0}));
}

TEST(RenderLights, SpotFalloffFollowsCycles) {
    DeltaLight s;
    s.kind = DeltaKind::Spot;
    s.axis = {0, 0, -1};
    s.cos_half_angle = std::cos(0.5f);
    s.spot_smooth = (1 - s.cos_half_angle) * 0.2f;
    EXPECT_FLOAT_EQ(SpotAttenuation(s, {0, 0, -1}), 1.0f);
    EXPECT_EQ(SpotAttenuation(s, SphericalDirection(-std::cos(0.55f), 0)), 0.0f);  // outside the cone
    const float c = std::cos(0.2f);                                                // inside, not blended
    EXPECT_NEAR(SpotAttenuation(s, SphericalDirection(-c, 1)), c, 1e-6f);
    const float edge = SpotAttenuation(s, SphericalDirection(-std::cos(0.49f), 0));
    EXPECT_GT(edge, 0);
    EXPECT_LT(edge, std::cos(0.49f) * 0.5f);  // faded near the edge
}

TEST(RenderCamera, ThinLensRaysMeetOnTheFocusPlane) {
    CameraModel c;
    c.width = 100;
    c.height = 50;
    c.half_width = 0.36f;
    c.half_height = 0.18f;
    c.aperture_radius = 0.1f;
    c.focus_distance = 4;
    const Ray pin = GenerateCameraRay<false>(c, 30.5f, 10.5f, {});
    const Vec3f focus = pin.o + pin.d * (4 / -pin.d.z);
    for (float u : {0.1f, 0.5f, 0.9f}) {
        const Ray r = GenerateCameraRay<true>(c, 30.5f, 10.5f, {u, 1 - u});
        const Vec3f p = r.o + r.d * ((-4 - r.o.z) / r.d.z);
        EXPECT_NEAR(Length(p - focus), 0, 1e-5f);
        EXPECT_LE(Length(r.o), 0.1f + 1e-6f);
    }
    const Ray centre = GenerateCameraRay<false>(c, 50, 25, {});
    EXPECT_NEAR(centre.d.z, -1, 1e-6f);
}

// A ground plane with a box on it, lit by a rectangle: the Renderer-level tests' scene.
std::shared_ptr<RenderScene> TestScene(int w, int h, bool medium) {
    auto s = std::make_shared<RenderScene>();
    CameraModel c;
    c.width = w;
    c.height = h;
    c.half_width = 0.4f;
    c.half_height = 0.4f * h / w;
    const float m[3][4] = {{1, 0, 0, 0}, {0, 0.8f, -0.6f, -4}, {0, 0.6f, 0.8f, 3}};
    std::copy(&m[0][0], &m[0][0] + 12, &c.to_world[0][0]);
    s->SetCamera(c);
    s->AddMaterial(DiffuseMaterial({0.5f, 0.5f, 0.5f}));
    const float v[] = {-5, -5, 0, 5, -5, 0, 5, 5, 0, -5, 5, 0, -.3f, -.3f, 0, .3f, -.3f, 0, 0, .3f, 0, 0, 0, 0.6f};
    const int32_t t[] = {0, 1, 2, 0, 2, 3, 4, 5, 7, 5, 6, 7, 6, 4, 7};
    s->AddMesh("scene", v, 8, t, 5, nullptr, nullptr);
    EXPECT_EQ(s->AddRectLight({-0.5f, 0.6f, 0.05f}, {1, 0, 0}, {0, 0, 1}, {3, 3, 3}, true, false), "");
    if (medium) s->SetMedium({0.1f, 0.1f, 0.1f}, {0.02f, 0.02f, 0.02f}, 0.2f);
    s->Commit();
    return s;
}

std::vector<float> RenderImage(std::shared_ptr<RenderScene> scene, RenderOptions o, int samples) {
    Renderer r(scene, o);
    EXPECT_TRUE(r.Render(samples));
    std::vector<float> img(size_t(r.width()) * r.height() * 4);
    r.Image(0, img.data());
    return img;
}

TEST(Renderer, IdenticalForAnyThreadCountAndTileSize) {
    for (bool medium : {false, true}) {
        auto scene = TestScene(40, 30, medium);
        RenderOptions o;
        o.mis = MisMode::Balance;  // what these measure (not the defaults)
        o.light_selection = LightSelection::Power;
        o.techniques = {Technique::Triangles};
        o.threads = 1;
        const auto reference = RenderImage(scene, o, 3);
        for (auto [threads, tile] : {std::pair{2, 16}, std::pair{4, 7}, std::pair{3, 1}}) {
            o.threads = threads;
            o.tile_size = tile;
            EXPECT_EQ(RenderImage(scene, o, 3), reference) << threads << " threads, tile " << tile;
        }
    }
}

TEST(Renderer, TechniquesShareCameraSamples) {
    // Rendered together or alone, a technique produces the same image.
    auto scene = TestScene(24, 16, false);
    RenderOptions both;
    both.mis = MisMode::Balance;  // what these measure (not the defaults)
    both.light_selection = LightSelection::Power;
    both.techniques = {Technique::Area, Technique::Rectangle};
    Renderer r(scene, both);
    ASSERT_TRUE(r.Render(4));
    std::vector<float> img(24 * 16 * 4);
    r.Image(1, img.data());
    RenderOptions alone;
    alone.mis = MisMode::Balance;  // what these measure (not the defaults)
    alone.light_selection = LightSelection::Power;
    alone.techniques = {Technique::Rectangle};
    EXPECT_EQ(RenderImage(scene, alone, 4), img);
}

TEST(Renderer, CancelFromAnotherThreadReturnsPartialImage) {
    auto scene = TestScene(128, 96, true);
    RenderOptions o;
    o.mis = MisMode::Balance;  // what these measure (not the defaults)
    o.light_selection = LightSelection::Power;
    o.threads = 2;
    o.tile_size = 8;
    o.light_samples = 4;
    Renderer r(scene, o);
    std::atomic<int> progress_calls{0};
    std::thread canceller([&] {
        while (progress_calls.load() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        r.Cancel();
    });
    const bool complete = r.Render(512, 0, [&](int done, int) { progress_calls.fetch_add(done > 0); });
    canceller.join();
    EXPECT_FALSE(complete);
    EXPECT_EQ(r.Stats(0).samples, 0u);
    std::vector<float> img(size_t(128) * 96 * 4);
    r.Image(0, img.data());
    size_t lit = 0;
    for (size_t i = 0; i < img.size(); i += 4) lit += img[i] > 0;
    EXPECT_GT(lit, 0u);
    EXPECT_LT(lit, size_t(128) * 96);
}

TEST(Renderer, RejectsBadInput) {
    RenderScene s;
    CameraModel c;
    c.width = 0;
    EXPECT_THROW(s.SetCamera(c), std::invalid_argument);
    c.width = 10;
    s.SetCamera(c);
    const float v[] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
    const int32_t t[] = {0, 1, 2};
    EXPECT_THROW(s.AddMesh("nan", v, 3, t, 1, nullptr, nullptr), std::invalid_argument);
    const float ok[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int32_t bad[] = {0, 1, 3};
    EXPECT_THROW(s.AddMesh("index", ok, 3, bad, 1, nullptr, nullptr), std::invalid_argument);
    EXPECT_NE(s.AddRectLight({0, 0, 1}, {0, 0, 0}, {1, 0, 0}, {1, 1, 1}, false, true), "");  // skipped
    EXPECT_THROW(s.Commit(), std::invalid_argument);                                         // empty scene
    auto scene = TestScene(8, 8, false);
    RenderOptions o;
    o.mis = MisMode::Balance;  // what these measure (not the defaults)
    o.light_selection = LightSelection::Power;
    o.light_samples = 0;
    EXPECT_THROW(Renderer(scene, o), std::invalid_argument);
}

TEST(RenderOptions, ValidationNamesTheBadOption) {
    auto message = [](const RenderOptions& o) {
        try {
            ValidateOptions(o);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    RenderOptions o;
    o.mis = MisMode::Balance;  // what these measure (not the defaults)
    o.light_selection = LightSelection::Power;
    EXPECT_EQ(message(o), "");
    o.techniques = {Technique::Area, Technique::Rectangle, Technique::Area};
    EXPECT_EQ(message(o), "technique 'area' listed twice");
    o = {};
    o.tile_size = 0;
    EXPECT_EQ(message(o), "tile_size must be positive");
    EXPECT_THROW(ValidateRenderCall(RenderOptions{}, 0), std::invalid_argument);
    RenderOptions many;
    many.mis = MisMode::Balance;  // what these measure (not the defaults)
    many.light_selection = LightSelection::Power;
    many.light_samples = kMaxLightSamples;
    EXPECT_NO_THROW(ValidateRenderCall(many, (1 << kMaxPatternPointsPerCallLog2) / kMaxLightSamples));
    EXPECT_THROW(ValidateRenderCall(many, (1 << kMaxPatternPointsPerCallLog2) / kMaxLightSamples + 1),
                 std::invalid_argument);
}

TEST(RenderOptions, EveryEnumValueHasItsOwnName) {
    auto distinct = [](const auto& values, auto name_of) {
        std::set<std::string> names;
        for (auto v : values) {
            const std::string n = name_of(v);
            if (n == "?" || !names.insert(n).second) return false;
        }
        return true;
    };
    EXPECT_TRUE(distinct(kAllMisModes, MisModeName));
    EXPECT_TRUE(distinct(kAllMediumSamplings, MediumSamplingName));
    EXPECT_TRUE(distinct(kAllLightSelections, LightSelectionName));
}

// Commit builds the light tree over the area lights (tree emitter i = area light i) and the point and
// spot lights; the sun stays outside.  At a receiver, the tree's choice (LightSamplingAt::Choose) and the
// pmf the MIS weights read (PDF / point pdf) agree, and the pmfs of all emitters sum to 1.
// The part of a light test's scene that does not matter to it: a 4 x 4 camera, one grey material.
void SetTinyCameraAndGreyMaterial(RenderScene& s) {
    CameraModel camera;
    camera.width = camera.height = 4;
    s.SetCamera(camera);
    s.AddMaterial(DiffuseMaterial({0.5f, 0.5f, 0.5f}));
}

TEST(RenderLights, LightTreeOverTheScenesEmitters) {
    RenderScene s;
    SetTinyCameraAndGreyMaterial(s);
    EXPECT_EQ(s.AddRectLight({-1, -1, 2}, {0, 2, 0}, {2, 0, 0}, {1, 1, 1}, false, false), "");
    EXPECT_EQ(s.AddRectLight({3, 0, 1}, {0, 0.2f, 0}, {0.2f, 0, 0}, {9, 9, 9}, true, false), "");
    EXPECT_EQ(s.AddEllipseLight({0, 3, 1}, {0.3f, 0, 0}, {0, 0.3f, 0}, {2, 2, 2}, true, false), "");
    s.AddPointLight({0, 0, 1}, {1, 1, 1});
    s.AddSunLight({0, 0, -1}, {1, 1, 1});
    s.AddSpotLight({1, 1, 3}, {0, 0, -1}, {5, 5, 5}, 1.0f, 0.2f);
    // More point lights than stay beside the tree: all of them are tree emitters.
    for (size_t i = 0; i < kMaxDeltaLightsBesideTree; ++i) s.AddPointLight({-4.0f + i, 5, 2}, {0.5f, 0.5f, 0.5f});
    s.Commit();
    EXPECT_EQ(s.light_tree().NumEmitters(), 0);  // built for the first Renderer that selects by tree
    s.BuildLightTree();
    const int emitters = int(3 + 2 + kMaxDeltaLightsBesideTree);
    ASSERT_EQ(s.light_tree().NumEmitters(), emitters);
    ASSERT_EQ(s.light_tree_refs().size(), size_t(emitters));
    for (int i = 0; i < 3; ++i) EXPECT_EQ(s.light_tree_refs()[i].kind, TreeEmitterKind::Area);
    EXPECT_EQ(s.light_tree_refs()[3].kind, TreeEmitterKind::Delta);
    EXPECT_EQ(s.light_tree_refs()[3].index, 0);                       // the point light
    EXPECT_EQ(s.light_tree_refs()[4].index, 2);                       // the spot (delta light 1 is the sun)
    EXPECT_EQ(s.delta_lights_beside_tree, std::vector<uint32_t>{1});  // the sun
    const std::vector<int> delta_emitter = DeltaTreeEmitters(3, s.delta_lights, DeltaLightsInTree(s.delta_lights));

    const Vec3f p{0.2f, -0.1f, 0}, n{0, 0, 1};
    LightSamplingAt<Technique::Rectangle> at(s, LightSelection::Tree, p, n, n, 4);
    std::vector<int> count(size_t(emitters), 0);
    constexpr int kN = 20000;
    double pmf_sum = 0;
    for (int i = 0; i < emitters; ++i) pmf_sum += s.light_tree().PMF(p, n, i);
    EXPECT_NEAR(pmf_sum, 1.0, 1e-5);
    for (int k = 0; k < kN; ++k) {
        const ChosenLight c = at.Choose({0.5f, (k + 0.5f) / kN});
        ASSERT_TRUE(c.pmf > 0);
        ASSERT_NE(c.index >= 0, c.delta >= 0);  // one of the two
        const int emitter = c.index >= 0 ? c.index : delta_emitter[size_t(c.delta)];
        EXPECT_EQ(c.pmf, s.light_tree().PMF(p, n, emitter));
        ++count[size_t(emitter)];
        if (c.index >= 0) {  // PDF of the sampled point = tree pmf x its point pdf
            const LightSample<float> ls = at.Sample(c.index, c.u);
            if (ls.pdf > 0) {
                EXPECT_NEAR(at.PDF(c.index, ls.point) / (c.pmf * ls.pdf), 1.0f, 1e-3f);
            }
        }
    }
    // A stratified v: each emitter's count is its pmf x kN up to the traversal's rounding (in each of the mixture's
    // two halves, light_tree.h kTreeFluxShare).
    for (int i = 0; i < emitters; ++i) EXPECT_NEAR(count[size_t(i)], s.light_tree().PMF(p, n, i) * kN, 3.0) << i;
}

// With few point and spot lights (up to kMaxDeltaLightsBesideTree) the tree holds the area lights only, and the point
// and spot lights are evaluated at every light sample beside it, with the suns, as "power" evaluates them.
TEST(RenderLights, FewPointLightsStayBesideTheTree) {
    RenderScene s;
    SetTinyCameraAndGreyMaterial(s);
    EXPECT_EQ(s.AddRectLight({-1, -1, 2}, {0, 2, 0}, {2, 0, 0}, {1, 1, 1}, false, false), "");
    for (size_t i = 0; i < kMaxDeltaLightsBesideTree; ++i) s.AddPointLight({-4.0f + i, 5, 2}, {0.5f, 0.5f, 0.5f});
    s.AddSunLight({0, 0, -1}, {1, 1, 1});
    s.Commit();
    s.BuildLightTree();
    EXPECT_EQ(s.light_tree().NumEmitters(), 1);
    EXPECT_EQ(s.delta_lights_beside_tree.size(), kMaxDeltaLightsBesideTree + 1);
    for (int e : DeltaTreeEmitters(1, s.delta_lights, DeltaLightsInTree(s.delta_lights))) EXPECT_EQ(e, -1);
    std::vector<uint32_t> seen;
    ForEachDeltaLightEvaluatedOnce(s, LightSelection::Tree,
                                   [&](const DeltaLight& d) { seen.push_back(uint32_t(&d - s.delta_lights.data())); });
    EXPECT_EQ(seen, s.delta_lights_beside_tree);
}

// LightSamplingAt keeps the samplers of the last kKeptSamplers (4) rectangle lights it set up, for
// their samples and pdfs: whatever the order of the calls over more lights than it keeps (some
// replaced, set up again), every Sample and PDF equals a fresh sampler's, bit for bit.
template <Technique K>
void ExpectKeptSamplersMatchFreshOnes() {
    RenderScene s;
    SetTinyCameraAndGreyMaterial(s);
    constexpr int kLights = 6;
    for (int i = 0; i < kLights; ++i)
        EXPECT_EQ(s.AddRectLight({-3.0f + i, -0.5f, 1.0f + 0.3f * i}, {0.4f + 0.1f * i, 0, 0}, {0, 0.7f, 0.1f * i},
                                 {1, 1, 1}, i % 2 == 1, false),
                  "");
    s.Commit();
    const Vec3f p{0.2f, -0.1f, 0}, n = Normalize(Vec3f{0.1f, 0, 1});
    LightSamplingAt<K> at(s, LightSelection::Power, p, n, n, 4);
    PCG32 rng(5);
    int valid = 0;
    for (int k = 0; k < 200; ++k) {
        const int i = int(rng.NextU32() % kLights);
        const LightSampler<K, float> fresh(p, n, s.area_lights[i].frame);
        const Point2<float> u{rng.NextFloat(), rng.NextFloat()};
        const LightSample<float> a = at.Sample(i, u);
        const LightSample<float> b = fresh.Valid() ? fresh.Sample(u) : LightSample<float>{};
        EXPECT_EQ(a.pdf, b.pdf) << "light " << i;
        EXPECT_EQ(a.point.x, b.point.x);
        EXPECT_EQ(a.point.y, b.point.y);
        EXPECT_EQ(a.point.z, b.point.z);
        if (!(b.pdf > 0)) continue;
        ++valid;
        // The pdf of a point of another light (a BSDF ray's), then of this one.
        const int j = int(rng.NextU32() % kLights);
        const LightSampler<K, float> fresh_j(p, n, s.area_lights[j].frame);
        const RectLight<float>& r = s.area_lights[j].frame.light;
        const Vec3f q = r.corner + r.ex * rng.NextFloat() + r.ey * rng.NextFloat();
        EXPECT_EQ(at.PDF(j, q), fresh_j.Valid() ? s.light_selector.pmf[j] * fresh_j.PDF(q) : 0.0f) << "light " << j;
        EXPECT_EQ(at.PDF(i, b.point), s.light_selector.pmf[i] * fresh.PDF(b.point));
    }
    EXPECT_GT(valid, 60);  // the even lights are one-sided, facing away: invalid samplers, pdf 0
}

TEST(RenderLights, KeptSamplersMatchFreshOnes) {
    ExpectKeptSamplersMatchFreshOnes<Technique::Rectangle>();
    ExpectKeptSamplersMatchFreshOnes<Technique::RectangleCosine>();
    ExpectKeptSamplersMatchFreshOnes<Technique::Triangles>();
}

// Ellipse lights under each ellipse technique: LightSamplingAt's Sample and PDF (its kept spherical
// ellipse setups, over more lights than it keeps) equal a fresh EllipseSampler's bit for bit, area
// fallback included (a light whose plane passes 3e-9 of its distance above the point), or the
// renderer's area sampling where spherical_ellipse chooses it (core/ellipse_map_choice.h), and the pdf
// of a returned point is that of the sample.
template <EllipseTechnique E>
void ExpectEllipseSamplingMatchesFreshSamplers() {
    RenderScene s;
    SetTinyCameraAndGreyMaterial(s);
    constexpr int kLights = 7;
    for (int i = 0; i < kLights - 3; ++i)  // the odd ones one-sided facing away (pdf 0)
        EXPECT_EQ(s.AddEllipseLight({-2.0f + i, 0.3f * i, 1.0f + 0.5f * i}, {0.3f + 0.1f * i, 0, 0},
                                    {0, 0.2f, 0.1f * i}, {1, 1, 1}, i % 2 == 0, false),
                  "");
    // Two close to the point, where spherical_ellipse takes the map (the four above it samples by area).
    EXPECT_EQ(s.AddEllipseLight({0.3f, 0, 0.15f}, {0.3f, 0, 0}, {0, 0.3f, 0}, {1, 1, 1}, true, false), "");
    EXPECT_EQ(s.AddEllipseLight({-0.1f, -0.3f, 0.2f}, {0, 0.25f, 0}, {0.2f, 0, 0}, {1, 1, 1}, false, false), "");
    EXPECT_EQ(s.AddEllipseLight({0.8f, 0.1f, 2e-9f}, {0.5f, 0, 0}, {0, 0.4f, 0}, {1, 1, 1}, true, false), "");
    s.Commit();
    const Vec3f p{0.2f, -0.1f, 0}, n{0, 0, 1};
    LightSamplingAt<Technique::Rectangle> at(s, LightSelection::Power, p, n, n, 4, E);
    auto fresh = [&](int i) { return EllipseSampler<E, float>(p, n, s.area_lights[i].ellipse_frame); };
    auto by_area = [&](int i) {
        return E == EllipseTechnique::Area || EllipseAreaSamplingSuffices(p, s.area_lights[i].ellipse_frame);
    };
    if constexpr (E == EllipseTechnique::SphericalEllipse) {
        EXPECT_TRUE(fresh(kLights - 1).Valid() && fresh(kLights - 1).r.area_fallback && !by_area(kLights - 1));
        for (int i : {4, 5}) EXPECT_TRUE(fresh(i).Valid() && !fresh(i).r.area_fallback && !by_area(i));
        for (int i : {0, 2}) EXPECT_TRUE(by_area(i) && fresh(i).Valid());
    }
    PCG32 rng(7);
    int valid = 0;
    for (int k = 0; k < 300; ++k) {
        const int i = int(rng.NextU32() % kLights);
        const float pmf = s.light_selector.pmf[i];
        const Point2<float> u{rng.NextFloat(), rng.NextFloat()};
        const LightSample<float> a = at.Sample(i, u);
        if (!by_area(i)) {
            const auto f = fresh(i);
            const LightSample<float> b = f.Valid() ? f.Sample(u) : LightSample<float>{};
            EXPECT_EQ(a.pdf, b.pdf) << "light " << i;
            EXPECT_EQ(a.point.x, b.point.x);
            EXPECT_EQ(a.point.y, b.point.y);
            EXPECT_EQ(a.point.z, b.point.z);
            if (b.pdf > 0) {
                EXPECT_EQ(at.PDF(i, b.point), pmf * f.PDF(b.point)) << "light " << i;
            }
        } else {  // the renderer's area sampling (the former one, bit-identical images)
            const LightSample<float> b = SampleEllipseArea(s.area_lights[i], p, u);
            EXPECT_EQ(a.pdf, b.pdf);
            EXPECT_EQ(a.point.x, b.point.x);
        }
        if (!(a.pdf > 0)) continue;
        ++valid;
        // The pdf of the returned point is the sample's (exactly on the map, to rounding on the area fallback).
        EXPECT_NEAR(at.PDF(i, a.point) / (pmf * a.pdf), 1.0f, 1e-4f) << "light " << i;
        // A BSDF ray's point on another light, then this one's again.
        const int j = int(rng.NextU32() % kLights);
        const AreaLight& l = s.area_lights[j];
        const float r = std::sqrt(rng.NextFloat()), phi = 6.2831853f * rng.NextFloat();
        const Vec3f q = l.center + l.ax * (r * std::cos(phi)) + l.ay * (r * std::sin(phi));
        const auto fj = fresh(j);
        const float expected = by_area(j) ? EllipseAreaPDF(l, p, q) : fj.Valid() ? fj.PDF(q) : 0.0f;
        EXPECT_EQ(at.PDF(j, q), s.light_selector.pmf[j] * expected) << "light " << j;
    }
    EXPECT_GT(valid, 100);
}

TEST(RenderLights, EllipseSamplingMatchesFreshSamplers) {
    ExpectEllipseSamplingMatchesFreshSamplers<EllipseTechnique::Area>();
    ExpectEllipseSamplingMatchesFreshSamplers<EllipseTechnique::SphericalEllipse>();
}

TEST(RenderOptions, EllipseTechniqueIsValidated) {
    RenderOptions o;
    o.mis = MisMode::Balance;  // what these measure (not the defaults)
    o.light_selection = LightSelection::Power;
    EXPECT_EQ(o.ellipse_technique, EllipseTechnique::SphericalEllipse);
    EXPECT_NO_THROW(ValidateOptions(o));
    o.ellipse_technique = EllipseTechnique(7);
    EXPECT_THROW(ValidateOptions(o), std::invalid_argument);
}

}  // namespace
}  // namespace sphrect::render
