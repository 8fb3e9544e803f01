// The ellipse techniques in C++ (the statistical tests are tests/python/test_ellipse_sampling.py):
// our Carlson R_J against Boost.Math's, the float path's pdf being that of the point returned,
// the area fallback followed by Sample, PDF and Invert, and closed forms.
#include <gtest/gtest.h>

#include <boost/math/special_functions/ellint_rj.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "core/ellipse_technique.h"

using namespace sphrect;

namespace {

EllipseLight<float> Ellipse(float b = 0.4f) { return {{0, 0, 0}, {1, 0, 0}, {0, b, 0}, true}; }

// Shading points from far away to nearly in the plane, above the interior, the rim and beside.
std::vector<Vec3f> HardOrigins() {
    std::vector<Vec3f> o;
    for (float d : {1e-6f, 1e-3f, 1.f, 1e3f, 1e6f}) o.push_back({0.3f * d, 0.1f * d, d});
    for (float h : {1e-9f, 1e-6f, 1e-3f, 1e-1f}) {
        o.push_back({0.4f, 0.1f, h});
        o.push_back({1.f, 0.f, h});
        o.push_back({1.5f, 0.2f, h});
    }
    return o;
}

}  // namespace

TEST(SphericalEllipse, CarlsonRJMatchesBoost) {
    // The map's arguments (sigma^2, 1, sigma^2 + w Q, sigma^2 + w R) over A in [1e-6, 1e6], A / B up
    // to 1e5 (ellipse_carlson.h quotes this bound).
    using Policy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> U(0, 1);
    double worst = 0;
    for (int i = 0; i < 100000; ++i) {
        const double s = -U(rng), w = (1 - std::abs(s)) * (1 + std::abs(s));
        const double A = std::pow(10.0, 12 * U(rng) - 6), B = A * std::pow(10.0, -5 * U(rng)), pB = 1 + B * B;
        const double x = s * s, z = x + w * (1 + A * A) / pB, p = x + w / pB;
        const double ours = CarlsonRJ(x, 1, z, p), boost = boost::math::ellint_rj(x, 1.0, z, p, Policy());
        worst = std::max(worst, std::abs(ours - boost) / boost);
    }
    EXPECT_LT(worst, 2e-15);
}

TEST(SphericalEllipse, FloatSamplesCarryThePDFOfTheirPoint) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(0, 1);
    for (const Vec3f& o : HardOrigins()) {
        for (EllipseTechnique t : kAllEllipseTechniques)
            DispatchEllipseTechnique(t, [&](auto tag) {
                const EllipseSampler<decltype(tag)::value, float> s(o, {0, 0, -1}, Ellipse());
                ASSERT_TRUE(s.Valid());
                for (int i = 0; i < 256; ++i) {
                    const LightSample<float> ls = s.Sample({U(rng), U(rng)});
                    ASSERT_TRUE(IsFinite(ls.point) && IsFinite(ls.dir) && std::isfinite(ls.pdf) && ls.pdf > 0);
                    EXPECT_EQ(s.PDF(ls.point), ls.pdf) << EllipseTechniqueName(t) << " o.z " << o.z;
                    const float p = ls.point.x, q = ls.point.y / 0.4f;
                    EXPECT_LE(p * p + q * q, 1 + 1e-5f);
                    EXPECT_EQ(ls.point.z, 0.f);
                }
            });
    }
}

TEST(SphericalEllipse, FallbackIsFollowedBySamplePDFAndInvert) {
    // Beside the ellipse at h = 1e-9 (a sliver too thin for the map) and far away: area sampling.
    const EllipseLight<double> light{{0, 0, 0}, {1, 0, 0}, {0, 0.4, 0}, true};
    const SphericalEllipseSetup<double> se = MakeSphericalEllipseSetup(Vec3d(1.5, 0.2, 1e-9), light);
    ASSERT_TRUE(se.valid);
    ASSERT_TRUE(se.area_fallback) << se.error_estimate;
    for (double u : {0.0, 0.1, 0.5, 0.9, 1.0})
        for (double v : {0.0, 0.3, 1.0}) {
            const LightSample<double> ls = SampleSphericalEllipseAt(se, u, v);
            const LightSample<double> area = SampleEllipseAreaAt(se.plane, u, v);
            EXPECT_EQ(ls.point.x, area.point.x);
            EXPECT_EQ(ls.pdf, area.pdf);
            EXPECT_EQ(SphericalEllipsePDF(se, ls.point), EllipseAreaPDF(se.plane, ls.point));
            const Point2<double> back = InvertSphericalEllipse(se, ls.point);
            if (u > 0 && u < 1 && v > 0 && v < 1) {  // (the concentric map's edges meet on the rim)
                EXPECT_NEAR(back.u, u, 1e-9);
                EXPECT_NEAR(back.v, v, 1e-9);
            }
        }
    // An ordinary setup does not fall back.
    EXPECT_FALSE(MakeSphericalEllipseSetup(Vec3d(0.2, 0.1, 1.0), light).area_fallback);
}

TEST(SphericalEllipse, SolidAngleClosedForms) {
    // A disk of radius R on its axis at height H: 2 pi (1 - H / sqrt(H^2 + R^2)).
    for (double R : {0.5, 1.0, 3.0})
        for (double H : {1e-6, 0.3, 1.0, 1e4}) {
            const EllipseLight<double> disk{{0, 0, 0}, {R, 0, 0}, {0, R, 0}, true};
            const double exact = 2 * M_PI * R * R / (H * H + R * R + H * std::sqrt(H * H + R * R));
            EXPECT_NEAR(EllipseSolidAngle(Vec3d(0, 0, H), disk), exact, 1e-13 * exact);
        }
    // Just above the interior: a hemisphere, 2 pi.
    EXPECT_NEAR(EllipseSolidAngle(Vec3d(0.3, 0.1, 1e-12), EllipseLight<double>{{0, 0, 0}, {1, 0, 0}, {0, 0.4, 0}}),
                2 * M_PI, 1e-9);
}

TEST(SphericalEllipse, MapEndsAndMiddle) {
    // u = 1/2 is the major axis' plane; v = 0 and v = 1 are the rim; u = 0 and u = 1 the minor axis' ends.
    const EllipseLight<double> light{{0, 0, 0}, {1, 0, 0}, {0, 0.4, 0}, true};
    const SphericalEllipseSetup<double> se = MakeSphericalEllipseSetup(Vec3d(0, 0, 1), light);
    const LightSample<double> tip = SampleSphericalEllipseAt(se, 0.0, 0.7);
    EXPECT_NEAR(std::abs(tip.point.y), 0.4, 1e-12);
    EXPECT_NEAR(tip.point.x, 0, 1e-12);
    const LightSample<double> end = SampleSphericalEllipseAt(se, 0.5, 1.0);
    EXPECT_NEAR(std::abs(end.point.x), 1, 1e-12);
    EXPECT_NEAR(end.point.y, 0, 1e-12);
    const LightSample<double> center = SampleSphericalEllipseAt(se, 0.5, 0.5);
    EXPECT_NEAR(center.point.x, 0, 1e-12);
    EXPECT_NEAR(center.point.y, 0, 1e-12);
}

TEST(EllipseArea, ConcentricMapRoundTrip) {
    for (double u = 0.03125; u < 1; u += 0.0625)
        for (double v = 0.03125; v < 1; v += 0.0625) {
            const Point2<double> d = ConcentricDisk(u, v);
            EXPECT_LE(d.u * d.u + d.v * d.v, 1 + 1e-15);
            const Point2<double> back = InvertConcentricDisk(d.u, d.v);
            EXPECT_NEAR(back.u, u, 1e-14);
            EXPECT_NEAR(back.v, v, 1e-14);
        }
}
