// The renderer's choice between the spherical ellipse map and area sampling (core/ellipse_map_choice.h,
// render/integrator/ellipse_sampling_at.h): the spread bound is a bound (and exact where it should be),
// the switch falls where the bound crosses kEllipseAreaMaxSpread, and on both sides of it Sample and PDF
// follow the same technique, bit for bit that of a fresh sampler, with the pdf of the returned point.
// (Unbiasedness of renders across the switch: tests/python/test_ellipse_render_choice.py.)  Deterministic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/ellipse_map_choice.h"
#include "core/rng.h"
#include "render/area_light.h"
#include "render/integrator/ellipse_sampling_at.h"

namespace sphrect::render {
namespace {

// The bound S^(2/3) >= d_max^2 / d_min^2 of core/ellipse_map_choice.h in its direct form: the ellipse of
// largest semi-axis r whose centre is at in-plane offset rho and height h from o.
double DistanceSpread2(const Vec3d& o, const EllipseLightFrame<float>& f) {
    const Vec3d d = f.center - o;
    const double rho = std::hypot(Dot(d, f.uh), Dot(d, f.vh)), h2 = Dot(d, f.n) * Dot(d, f.n), r = std::max(f.a, f.b);
    const double near = std::max(rho - r, 0.0), far = rho + r;
    return (h2 + far * far) / (h2 + near * near);
}

// The spread d_max^3 / d_min^3 of area sampling's solid-angle density over the ellipse, measured on a
// dense polar grid of its points (the extremes of the distance lie on the rim or at the foot of o).
double MeasuredSpread(const Vec3d& o, const EllipseLightFrame<float>& f) {
    double lo = 1e300, hi = 0;
    for (int i = 0; i <= 64; ++i)
        for (int j = 0; j < 720; ++j) {
            const double r = i / 64.0, phi = 2 * 3.14159265358979323846 * j / 720;
            const Vec3d p = f.center + f.uh * (f.a * r * std::cos(phi)) + f.vh * (f.b * r * std::sin(phi));
            const double d = Length(p - o);
            lo = std::min(lo, d);
            hi = std::max(hi, d);
        }
    return std::pow(hi / lo, 3);
}

TEST(EllipseMapChoice, SpreadBoundHoldsAndIsExactOnTheAxisOfADisk) {
    const EllipseLightFrame<float> disk =
        MakeEllipseLightFrame(EllipseLight<float>{{0, 0, 1}, {0.5f, 0, 0}, {0, 0.5f, 0}});
    const EllipseLightFrame<float> ellipse =
        MakeEllipseLightFrame(EllipseLight<float>{{0.2f, -0.1f, 1.3f}, {0.6f, 0, 0.3f}, {0, 0.2f, 0}});
    PCG32 rng(3);
    for (const auto* f : {&disk, &ellipse})
        for (int k = 0; k < 40; ++k) {
            const Vec3d o(4 * rng.NextFloat() - 2, 4 * rng.NextFloat() - 2, 2 * rng.NextFloat() - 0.5);
            EXPECT_GE(std::pow(DistanceSpread2(o, *f), 1.5) * (1 + 1e-12), MeasuredSpread(o, *f))
                << o.x << " " << o.y << " " << o.z;
        }
    // Under the centre of a disk of radius r at height h: S = ((h^2 + r^2) / h^2)^(3/2) exactly.
    for (double h : {0.05, 0.3, 1.0, 4.0})
        EXPECT_NEAR(std::pow(DistanceSpread2(Vec3d(0, 0, 1 - h), disk), 1.5), MeasuredSpread(Vec3d(0, 0, 1 - h), disk),
                    1e-9 * std::pow(1 + 0.25 / (h * h), 1.5));
}

// The square-root-free test of the core is the direct bound against the threshold, S^(2/3) <= 4.
TEST(EllipseMapChoice, ChoiceIsTheBoundAgainstTheThreshold) {
    static_assert(EllipseAreaMaxDistanceRatio2(8.0) - 4.0 < 1e-15 && 4.0 - EllipseAreaMaxDistanceRatio2(8.0) < 1e-15);
    EXPECT_NEAR(EllipseAreaMaxDistanceRatio2(kEllipseAreaMaxSpread),
                std::cbrt(kEllipseAreaMaxSpread * kEllipseAreaMaxSpread), 1e-15);
    const double k = EllipseAreaMaxDistanceRatio2(kEllipseAreaMaxSpread);
    const EllipseLightFrame<float> ellipse =
        MakeEllipseLightFrame(EllipseLight<float>{{0.2f, -0.1f, 1.3f}, {0.6f, 0, 0.3f}, {0, 0.2f, 0}, false});
    PCG32 rng(5);
    int by_area = 0, near_boundary = 0;
    for (int i = 0; i < 100000; ++i) {
        const float s = std::pow(10.0f, 3 * rng.NextFloat() - 1);  // 0.1 .. 100 sizes away
        const Vec3f o(s * (2 * rng.NextFloat() - 1), s * (2 * rng.NextFloat() - 1),
                      1.3f + s * (2 * rng.NextFloat() - 1));
        const double b = DistanceSpread2(Vec3d(o), ellipse);
        if (std::abs(b / k - 1) < 1e-9) {
            ++near_boundary;
            continue;
        }
        const bool area = EllipseAreaSamplingSuffices(o, ellipse);
        EXPECT_EQ(area, b <= k) << o.x << " " << o.y << " " << o.z << " bound " << b;
        by_area += area;
    }
    EXPECT_GT(by_area, 10000);
    EXPECT_LT(by_area, 90000);
    EXPECT_LT(near_boundary, 10);
}

// Under the centre of a disk of radius 1 the switch is at h* = 1 / sqrt(S^(2/3) - 1).
TEST(EllipseMapChoice, SwitchesWhereTheBoundCrossesTheThreshold) {
    const EllipseLightFrame<float> disk = MakeEllipseLightFrame(EllipseLight<float>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    const double h_switch = 1 / std::sqrt(EllipseAreaMaxDistanceRatio2(kEllipseAreaMaxSpread) - 1);
    EXPECT_TRUE(EllipseAreaSamplingSuffices(Vec3f(0, 0, float(-1.01 * h_switch)), disk));
    EXPECT_FALSE(EllipseAreaSamplingSuffices(Vec3f(0, 0, float(-0.99 * h_switch)), disk));
    EXPECT_TRUE(EllipseAreaSamplingSuffices(Vec3f(0, 0, float(1.01 * h_switch)), disk));  // the other side
    // Far away, by area; close, beside the rim or in the plane over it, by the map.
    EXPECT_TRUE(EllipseAreaSamplingSuffices(Vec3f(0.5f, 0, 1e4f), disk));
    EXPECT_TRUE(EllipseAreaSamplingSuffices(Vec3f(30, 0, 1e-6f), disk));
    EXPECT_FALSE(EllipseAreaSamplingSuffices(Vec3f(1.5f, 0, 0.1f), disk));
    EXPECT_FALSE(EllipseAreaSamplingSuffices(Vec3f(0.5f, 0, 0), disk));
    EXPECT_FALSE(EllipseAreaSamplingSuffices(Vec3f(0.5f, 0, 1e-3f), disk));
    // The largest semi-axis counts: a thin ellipse seen along its major axis.
    const EllipseLightFrame<float> thin =
        MakeEllipseLightFrame(EllipseLight<float>{{0, 0, 0}, {0, 0.01f, 0}, {1, 0, 0}});
    EXPECT_FALSE(EllipseAreaSamplingSuffices(Vec3f(1.5f, 0, 0.1f), thin));
    EXPECT_TRUE(EllipseAreaSamplingSuffices(
        Vec3f(0, 1.5f, 0.1f), MakeEllipseLightFrame(EllipseLight<float>{{0, 0, 0}, {0, 0.01f, 0}, {0.01f, 0, 0}})));
    // Degenerate input: the map's (invalid) setup answers.
    EXPECT_FALSE(EllipseAreaSamplingSuffices(Vec3f(std::nanf(""), 0, 1), disk));
}

// EllipseSamplingAt under spherical_ellipse at shading points straddling the switch: each light is
// sampled and its pdf answered by the technique the choice names (bit for bit a fresh area sampler or
// spherical ellipse setup), and the pdf of the returned point is the sample's.
TEST(EllipseMapChoice, SampleAndPDFFollowTheChoiceOnBothSides) {
    const float r = 0.5f;
    // (one-sided, facing down: cross(axis_u, axis_v) = -z)
    const AreaLight disk = MakeEllipseAreaLight({0, 0, 2}, {0, r, 0}, {r, 0, 0}, {1, 1, 1}, false, false);
    const AreaLight tilted =
        MakeEllipseAreaLight({1, 0.5f, 1.5f}, {0.4f, 0, 0.2f}, {0, 0.25f, 0}, {1, 1, 1}, true, false);
    const double h_switch = r / std::sqrt(EllipseAreaMaxDistanceRatio2(kEllipseAreaMaxSpread) - 1);
    int by_area = 0, by_map = 0;
    PCG32 rng(11);
    for (double f : {0.5, 0.9, 0.98, 1.02, 1.1, 2.0, 40.0}) {
        // Under the disk's centre at f times the switch height, and beside the tilted ellipse.
        const Vec3f o(0.01f, -0.02f, float(2 - f * h_switch));
        EllipseSamplingAt at(EllipseTechnique::SphericalEllipse);
        for (int k = 0; k < 50; ++k) {
            const int index = k % 2;
            const AreaLight& l = index == 0 ? disk : tilted;
            const bool area = EllipseAreaSamplingSuffices(o, l.ellipse_frame);
            if (k < 2) (area ? by_area : by_map) += 1;
            const Point2<float> u{rng.NextFloat(), rng.NextFloat()};
            const LightSample<float> s = at.Sample(l, index, o, u);
            const SphericalEllipseSetup<float> fresh = MakeSphericalEllipseSetup(o, l.ellipse_frame);
            const LightSample<float> e = area ? SampleEllipseArea(l, o, u) : SampleSphericalEllipse(fresh, u);
            EXPECT_EQ(s.pdf, e.pdf) << "f " << f << " light " << index;
            EXPECT_EQ(s.point.x, e.point.x);
            EXPECT_EQ(s.point.y, e.point.y);
            EXPECT_EQ(s.point.z, e.point.z);
            ASSERT_GT(s.pdf, 0);
            const float pdf = at.PDF(l, index, o, s.point);
            EXPECT_EQ(pdf, area ? EllipseAreaPDF(l, o, s.point) : SphericalEllipsePDF(fresh, s.point));
            EXPECT_EQ(pdf, area ? s.pdf : fresh.pdf);  // the map: 1 / Omega for every point
        }
    }
    EXPECT_GE(by_area, 4);
    EXPECT_GE(by_map, 4);
}

// ellipse_technique = area ignores the choice: area sampling everywhere, also where the map would be chosen.
TEST(EllipseMapChoice, AreaTechniqueIsAreaSamplingEverywhere) {
    const AreaLight disk = MakeEllipseAreaLight({0, 0, 0.1f}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}, true, false);
    const Vec3f o(0.2f, 0.1f, 0);
    ASSERT_FALSE(EllipseAreaSamplingSuffices(o, disk.ellipse_frame));
    EllipseSamplingAt at(EllipseTechnique::Area);
    const LightSample<float> s = at.Sample(disk, 0, o, {0.3f, 0.7f});
    const LightSample<float> e = SampleEllipseArea(disk, o, {0.3f, 0.7f});
    EXPECT_EQ(s.pdf, e.pdf);
    EXPECT_EQ(s.point.x, e.point.x);
    EXPECT_EQ(at.PDF(disk, 0, o, s.point), EllipseAreaPDF(disk, o, s.point));
}

}  // namespace
}  // namespace sphrect::render
