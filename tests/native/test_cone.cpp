// Uniform cone sampling (core/cone.h) and the soft point, spot and sun lights sampled with it
// (render/delta_light.h): the sampler against its pdf (chi-square, bsdf_chi_square.h's harness), its
// inverse, narrow cones, and the lights' estimates of the irradiance on a plane against closed forms and
// quadratures of Cycles 3.4's model, in the hard cases (a light almost touching the plane, a sun of 1e-4 rad
// and of 179 degrees).
// False failures: the chi-square tests fail a correct sampler with probability ~1e-6 each (z = 4.753); the
// estimates are compared at 5 standard errors (~6e-7 each, two-sided); every test has a fixed seed.
#include <gtest/gtest.h>

#include <cmath>

#include "bsdf_chi_square.h"
#include "core/cone.h"
#include "core/rng.h"
#include "render/delta_light.h"

using namespace sphrect;
using namespace sphrect::render;

namespace {

constexpr double kPiD = 3.14159265358979323846;

TEST(Cone, SamplingMatchesThePDFChiSquare) {
    PCG32 rng(2013);
    for (double half_angle : {0.35, 1.4, 2.6}) {  // 20, 80, 150 degrees
        const float omc = float(1 - std::cos(half_angle));
        const float cos_lo = float(std::cos(half_angle));
        const ChiSquare chi2 =
            DirectionSamplingChiSquare([&](const Vec3f& w) { return 1 - w.z <= omc ? UniformConePDF(omc) : 0.0f; },
                                       [&](Point2<float> u, Vec3f* w) {
                                           *w = SampleUniformCone(u, omc);
                                           return true;
                                       },
                                       rng, cos_lo, 32, 32, 4, 300000);
        ASSERT_GT(chi2.cells, 500) << half_angle;
        EXPECT_LT(chi2.statistic, ChiSquareQuantile(chi2.cells - 1, 4.753)) << half_angle << ", " << chi2.cells;
    }
}

TEST(Cone, InvertsItsSamplesAndStaysInsideNarrowCones) {
    PCG32 rng(5);
    for (double half_angle : {5e-5, 1e-3, 0.5, 1.5, 3.0}) {
        const float omc = float(2 * std::pow(std::sin(half_angle / 2), 2));
        ASSERT_GT(omc, 0) << half_angle;
        for (int i = 0; i < 2000; ++i) {
            const Point2<float> u{rng.NextFloat(), rng.NextFloat()};
            const Vec3f w = SampleUniformCone(u, omc);
            EXPECT_NEAR(Length(w), 1, 1e-6);
            // Inside the cone, measured without cancellation.
            EXPECT_LE(OneMinusCosBetween(w, Vec3f(0, 0, 1)), omc * (1 + 1e-5f) + 1e-12f) << half_angle;
            const Point2<float> back = InvertUniformConeSample(w, omc);
            EXPECT_NEAR(back.u, u.u, 2e-4) << half_angle;
            // phi wraps: compare on the circle.
            const double dv = std::remainder(double(back.v) - u.v, 1.0);
            if (std::hypot(w.x, w.y) > 1e-3 * std::sin(half_angle)) {
                EXPECT_NEAR(dv, 0, 2e-4) << half_angle;
            }
        }
        EXPECT_FLOAT_EQ(UniformConePDF(omc) * UniformConeSolidAngle(omc), 1.0f);
    }
    // A 1e-4 rad sun: 1 - cos(5e-5) = 1.25e-9, which a float cosine loses.
    EXPECT_NEAR(OneMinusCosOfDisc(5e-5f, 1.0f), 1.25e-9f, 1e-13f);
}

// The irradiance on the plane of normal n at p from light l: the mean of SampleSoftLight's Le cos / pdf over n
// samples, and its standard error.
std::pair<double, double> EstimateIrradiance(const DeltaLight& l, const Vec3f& p, const Vec3f& n, int count,
                                             uint64_t seed) {
    PCG32 rng(seed);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < count; ++i) {
        const DeltaIllumination di = SampleSoftLight(l, p, {rng.NextFloat(), rng.NextFloat()});
        const double x = di.pdf > 0 ? double(di.li.y) * std::max(0.0f, Dot(di.wi, n)) : 0.0;
        sum += x;
        sum2 += x * x;
    }
    const double mean = sum / count;
    return {mean, std::sqrt(std::max(0.0, sum2 / count - mean * mean) / count)};
}

// The irradiance of Cycles 3.4's model by quadrature in double over the cone (axis a, half-angle theta_max)
// of radiance(cos theta) max(0, n . w): midpoints in (1 - cos theta, phi).
template <class Radiance>
double ConeIrradianceQuadrature(const Vec3d& a, double theta_max, const Vec3d& n, Radiance&& radiance, int nu,
                                int nphi) {
    const Vec3d s = std::abs(a.x) < 0.9 ? Normalize(Cross(a, Vec3d(1, 0, 0))) : Normalize(Cross(a, Vec3d(0, 1, 0)));
    const Vec3d t = Cross(a, s);
    const double omc = 1 - std::cos(theta_max);
    double sum = 0;
    for (int i = 0; i < nu; ++i) {
        const double x = omc * (i + 0.5) / nu, c = 1 - x, sn = std::sqrt(std::max(0.0, x * (2 - x)));
        const double lr = radiance(c);
        for (int j = 0; j < nphi; ++j) {
            const double phi = 2 * kPiD * (j + 0.5) / nphi;
            const Vec3d w = s * (sn * std::cos(phi)) + t * (sn * std::sin(phi)) + a * c;
            sum += lr * std::max(0.0, Dot(w, n));
        }
    }
    return sum * (omc / nu) * (2 * kPiD / nphi);
}

DeltaLight SoftSun(double angle, float irradiance) {
    DeltaLight l;
    l.kind = DeltaKind::Sun;
    l.axis = Normalize(Vec3f(0.3f, -0.2f, 1));
    l.power = {irradiance, irradiance, irradiance};
    l.sun_one_minus_cos = float(2 * std::pow(std::sin(angle / 4), 2));
    return l;
}

// A sun cone over a plane facing it: E (2 / tan^2(alpha)) (1 / cos(alpha) - 1) in Cycles 3.4's model (radiance
// E / (pi tan^2 alpha cos^3 theta)), E for a sharp sun; a tilted plane against the quadrature.
TEST(SoftSun, IrradianceOnAPlaneMatchesTheClosedForm) {
    for (double angle : {1e-4, 0.2, 1.5, 179 * kPiD / 180}) {
        const DeltaLight l = SoftSun(angle, 2.0f);
        const double alpha = angle / 2, tan2 = std::pow(std::tan(alpha), 2);
        const double closed = 2.0 * 2 / tan2 * (1 / std::cos(alpha) - 1);
        const auto [mean, se] = EstimateIrradiance(l, {0, 0, 0}, l.axis, 400000, 11);
        EXPECT_NEAR(mean, closed, 5 * se + 1e-5 * closed) << angle;
        if (angle < 0.01) {
            EXPECT_NEAR(mean, 2.0, 1e-5);  // the sharp sun's
        }
        // A plane tilted by 1 rad from the sun (the cone dips below its horizon past 57 degrees).
        const Vec3f n = Normalize(Vec3f(std::sin(1.0f), 0, std::cos(1.0f)));
        const Frame f = Frame::FromZ(l.axis);
        const Vec3f n_world = f.FromLocal(n);
        const Vec3d a(l.axis.x, l.axis.y, l.axis.z), nd(n_world.x, n_world.y, n_world.z);
        const double ref = ConeIrradianceQuadrature(
            a, alpha, nd, [&](double c) { return 2.0 / (kPiD * tan2 * c * c * c); }, 4000, 400);
        const auto [mean_t, se_t] = EstimateIrradiance(l, {0, 0, 0}, n_world, 400000, 12);
        EXPECT_NEAR(mean_t, ref, 5 * se_t + 1e-4 * ref) << angle;
    }
}

DeltaLight SoftPoint(const Vec3f& position, float radius, float intensity) {
    DeltaLight l;
    l.kind = DeltaKind::Point;
    l.position = position;
    l.radius = radius;
    l.power = {intensity, intensity, intensity};
    return l;
}

// Cycles 3.4's soft point light (a disc facing the shading point, radiance I / (pi r^2)) over the plane z = 0:
// where the whole cone is above the horizon, E = I cos(theta_axis) / (d^2 + r^2) (a uniform cap's
// pi L sin^2(beta) cos); a light almost touching the plane, whose cone the horizon cuts, against the quadrature.
TEST(SoftPointLight, IrradianceOnAPlaneMatchesTheClosedFormAndTheQuadrature) {
    const Vec3f n(0, 0, 1);
    for (float rho : {0.0f, 0.5f, 2.0f}) {
        const DeltaLight l = SoftPoint({0, 0, 1}, 0.25f, 3.0f);
        const Vec3f p(rho, 0, 0);
        const double d2 = 1.0 + rho * rho, d = std::sqrt(d2);
        const double closed = 3.0 * (1 / d) / (d2 + 0.0625);
        const auto [mean, se] = EstimateIrradiance(l, p, n, 200000, 21);
        EXPECT_NEAR(mean, closed, 5 * se + 1e-5 * closed) << rho;
    }
    // Almost touching: the centre 1e-3 above the plane, radius 0.25.
    for (float rho : {0.0f, 0.05f, 0.3f, 1.0f}) {
        const DeltaLight l = SoftPoint({0, 0, 1e-3f}, 0.25f, 3.0f);
        const Vec3f p(rho, 0, 0);
        const Vec3f to = l.position - p;
        const double dist = Length(to);
        const Vec3d a(to.x / dist, to.y / dist, to.z / dist);
        const double ref = ConeIrradianceQuadrature(
            a, std::atan(0.25 / dist), Vec3d(0, 0, 1), [](double) { return 3.0 / (kPiD * 0.0625); }, 2000, 2000);
        const auto [mean, se] = EstimateIrradiance(l, p, n, 400000, 22);
        EXPECT_NEAR(mean, ref, 5 * se + 1e-4 * ref) << rho;
    }
    // A radius of 1e-4: the point light's I cos / d^2.
    const auto [mean, se] = EstimateIrradiance(SoftPoint({0, 0, 1}, 1e-4f, 3.0f), {0.5f, 0, 0}, n, 1000, 23);
    EXPECT_NEAR(mean, 3.0 / std::pow(1.25, 1.5), 1e-5);
}

// What a BSDF ray finds (CrossSoftLight) is what the light sample sent: the same distance, Le and pdf, for a
// soft point, a soft spot (its falloff towards the point) and a sun; directions outside the cone miss.
TEST(SoftLights, RaysFindWhatTheLightSamplesSend) {
    DeltaLight spot = SoftPoint({0.2f, 0.1f, 1.5f}, 0.3f, 4.0f);
    spot.kind = DeltaKind::Spot;
    spot.axis = Normalize(Vec3f(0.1f, 0, -1));
    spot.cos_half_angle = std::cos(0.4f);
    spot.spot_smooth = (1 - spot.cos_half_angle) * 0.5f;
    PCG32 rng(31);
    for (const DeltaLight& l : {SoftPoint({0.2f, 0.1f, 1.5f}, 0.3f, 4.0f), spot, SoftSun(0.2, 2.0f)}) {
        for (int i = 0; i < 500; ++i) {
            const Vec3f p(rng.NextFloat() - 0.5f, rng.NextFloat() - 0.5f, 0);
            const DeltaIllumination di = SampleSoftLight(l, p, {rng.NextFloat(), rng.NextFloat()});
            if (IsBlack(di.li)) continue;
            const SoftLightCrossing x = CrossSoftLight(l, p, di.wi);
            ASSERT_TRUE(x.hit);
            EXPECT_FLOAT_EQ(x.pdf, di.pdf);
            EXPECT_NEAR(x.le.y / x.pdf, di.li.y, 1e-4 * di.li.y);
            if (l.kind != DeltaKind::Sun) {
                EXPECT_NEAR(x.t, di.dist, 1e-5 * di.dist);
                // The end of the shadow ray lies on the disc facing p.
                const Vec3f q = p + di.wi * di.dist, axis = Normalize(l.position - p);
                EXPECT_NEAR(Dot(q - l.position, axis), 0, 1e-5);
                EXPECT_LE(Length(q - l.position), l.radius * (1 + 1e-5f));
            }
        }
        EXPECT_FALSE(CrossSoftLight(l, {0, 0, 0}, Normalize(Vec3f(1, 0, 0.2f))).hit);
    }
}

}  // namespace
