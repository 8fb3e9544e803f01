// Unbiasedness: the irradiance at a point from a unit-radiance rectangle,
// E = int cos+ dw = pi x (point-to-rectangle form factor), estimated with each
// technique (mean of cos / pdf over N independent samples), matches the closed form
// within 4 standard errors, for receivers parallel and perpendicular to the light.
// False-failure probability ~6e-5 per check (normal approximation), ~0.5% for the
// whole file; the seeds are fixed.
#include <gtest/gtest.h>

#include <cstdio>

#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

namespace {

std::vector<LightConfig> Receivers() {
    // Parallel: a 1 x 2 light at height 1 facing down (cross(ex, ey) = -z).
    const RectLight<float> ceiling{{-0.5f, -1.f, 1.f}, {0, 2, 0}, {1, 0, 0}, false};
    // Perpendicular: a light in the plane x = 1 spanning z in [0, 1.5] (above the horizon).
    const RectLight<float> wall{{1.f, -0.5f, 0.f}, {0, 0, 1.5f}, {0, 1, 0}, false};
    return {
        {"parallel_under_centre", ceiling, {0, 0, 0}, {0, 0, 1}},
        {"parallel_under_corner", ceiling, {-0.5f, -1.f, 0}, {0, 0, 1}},
        {"parallel_beside", ceiling, {1.5f, 0.3f, 0}, {0, 0, 1}},
        {"parallel_far", ceiling, {0.2f, 0.1f, -99.f}, {0, 0, 1}},
        {"parallel_close", ceiling, {0.1f, 0.2f, 0.99f}, {0, 0, 1}},
        {"perpendicular_edge", wall, {0, 0, 0}, {0, 0, 1}},
        {"perpendicular_offset", wall, {-0.5f, 0.8f, 0}, {0, 0, 1}},
        {"perpendicular_near", wall, {0.9f, 0.f, 0}, {0, 0, 1}},
    };
}

template <Technique K, class T>
void CheckAll() {
    uint64_t seed = 77 + 100 * uint64_t(K) + sizeof(T);
    for (const LightConfig& r : Receivers()) {
        const RectLight<T> L{Vec3<T>(r.light.corner), Vec3<T>(r.light.ex), Vec3<T>(r.light.ey), r.light.two_sided};
        const Vec3<T> o(r.origin), n(r.normal);
        const double ref = ReferenceIrradiance(o, Vec3d(n), L);
        ASSERT_TRUE((LightSampler<K, T>(o, n, L).Valid())) << r.name;
        const auto [mean, se] = EstimateIrradiance<K, T>(o, n, L, 100000, ++seed);
        std::printf("%-16s %-6s %-22s E %.7f estimate %.7f se %.2e (%+.2f se)\n", TechniqueName(K),
                    sizeof(T) == 4 ? "float" : "double", r.name, ref, mean, se, se > 0 ? (mean - ref) / se : 0.0);
        EXPECT_LE(std::abs(mean - ref), 4 * se + 1e-6 * ref) << TechniqueName(K) << " " << r.name;
    }
}

}  // namespace

// The reference itself against the classic closed form for a parallel rectangle with
// a corner above the receiver: F = 1/(2 pi) [A/sqrt(1+A^2) atan(B/sqrt(1+A^2)) + (A <-> B)].
TEST(FormFactor, ReferenceMatchesClassicParallelFormula) {
    const double a = 2, b = 1, c = 1, A = a / c, B = b / c;
    const double F = (A / std::sqrt(1 + A * A) * std::atan(B / std::sqrt(1 + A * A)) +
                      B / std::sqrt(1 + B * B) * std::atan(A / std::sqrt(1 + B * B))) /
                     (2 * M_PI);
    const RectLight<double> L{{0, 0, 1}, {0, 2, 0}, {1, 0, 0}, false};
    EXPECT_NEAR(ReferenceIrradiance(Vec3d(0, 0, 0), Vec3d(0, 0, 1), L) / M_PI, F, 1e-14);
}

TEST(FormFactor, AreaFloat) { CheckAll<Technique::Area, float>(); }
TEST(FormFactor, AreaDouble) { CheckAll<Technique::Area, double>(); }
TEST(FormFactor, TrianglesFloat) { CheckAll<Technique::Triangles, float>(); }
TEST(FormFactor, TrianglesDouble) { CheckAll<Technique::Triangles, double>(); }
TEST(FormFactor, RectangleFloat) { CheckAll<Technique::Rectangle, float>(); }
TEST(FormFactor, RectangleDouble) { CheckAll<Technique::Rectangle, double>(); }
TEST(FormFactor, RectangleCosineFloat) { CheckAll<Technique::RectangleCosine, float>(); }
TEST(FormFactor, RectangleCosineDouble) { CheckAll<Technique::RectangleCosine, double>(); }
TEST(FormFactor, RectangleProjectedFloat) { CheckAll<Technique::RectangleProjected, float>(); }
TEST(FormFactor, RectangleProjectedDouble) { CheckAll<Technique::RectangleProjected, double>(); }
