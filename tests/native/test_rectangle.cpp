// Technique `rectangle` (rectangle.h): area preservation (finite-difference Jacobian =
// Omega), the inverse round trip over the hard-case suite, and the unbiasedness of its two
// switches (the Newton-refined x-step, the area fallback on both sides of its threshold).
#include <gtest/gtest.h>

#include <cstdio>

#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

namespace {

RectLight<double> ToDouble(const RectLight<float>& L) {
    return {Vec3d(L.corner), Vec3d(L.ex), Vec3d(L.ey), L.two_sided};
}

std::vector<Point2<float>> SuiteUVs() { return GridAndRandomUVs(11, 40); }

}  // namespace

// |d(omega)/du x d(omega)/dv| = Omega: with x = x(u) and y = y(x, v) in the light's
// plane, the solid-angle Jacobian is x'(u) y_v(u, v) h / r^3.  Central differences
// in double on the local coordinates, over [0.01, 0.99]^2, every hard case whose
// setup uses the map (the others use the area fallback, tested below).
TEST(Rectangle, JacobianEqualsSolidAngle) {
    const double us[] = {0.001, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999};
    int checked = 0, fallback = 0;
    double worst = 0;
    std::string worst_case;
    for (const HardCase& hc : HardCaseSuite()) {
        const RectangleSetup<double> sr = MakeRectangleSetup(Vec3d(hc.origin), ToDouble(hc.light));
        if (!sr.valid) continue;
        if (sr.area_fallback) {
            ++fallback;
            continue;
        }
        ++checked;
        for (double u : us)
            for (double v : us) {
                // Central differences with one Richardson step (error O(step^4)); steps of
                // 1% of the distance to the border keep the rounding noise of the map
                // (~1e-11 in u for the hardest setups) far below the tolerance.
                auto xu = [&](double uu) {
                    double x, y;
                    RectangleMapLocal(sr, uu, v, &x, &y);
                    return x;
                };
                auto yv = [&](double vv) {
                    double x, y;
                    RectangleMapLocal(sr, u, vv, &x, &y);
                    return y;
                };
                auto deriv = [](auto f, double t, double step) {
                    const double d1 = (f(t + step) - f(t - step)) / (2 * step);
                    const double d2 = (f(t + step / 2) - f(t - step / 2)) / step;
                    return (4 * d2 - d1) / 3;
                };
                double x, y;
                RectangleMapLocal(sr, u, v, &x, &y);
                const double r2 = x * x + y * y + sr.h * sr.h;
                const double J = deriv(xu, u, 0.01 * std::min(u, 1 - u)) * deriv(yv, v, 0.01 * std::min(v, 1 - v)) *
                                 sr.h / (r2 * std::sqrt(r2));
                const double err = std::abs(J - sr.omega) / sr.omega;
                if (err > worst && sr.error_estimate < 1e-12) {
                    worst = err;
                    worst_case = hc.name;
                }
                // Rounding noise of the map (error_estimate, in u and v) over the step.
                const double noise = 4 * sr.error_estimate / (0.01 * std::min({u, 1 - u, v, 1 - v}));
                EXPECT_LE(err, 1e-4 + noise)
                    << hc.name << " u " << u << " v " << v << " J " << J << " Omega " << sr.omega;
            }
    }
    std::printf(
        "Jacobian: %d setups checked (%d use the area fallback), worst rel. error where the map's noise is < 1e-12: "
        "%.3g (%s)\n",
        checked, fallback, worst, worst_case.c_str());
    EXPECT_GT(checked, 200);
}

// (u, v) -> point -> (u, v) within 1e-4, every case of the suite (no skipping of
// small Omega).  Double path: directly.  Float path: the point is rounded to float,
// which near the foot of a shading point 1e-9 above the light moves it by many
// "heights"; the allowance adds exactly what that rounding moves (u, v) by, measured
// with the double inverse.
TEST(Rectangle, InverseRoundTrip) {
    double worst_d = 0, worst_f = 0;
    int n = 0;
    for (const HardCase& hc : HardCaseSuite()) {
        const RectLight<double> Ld = ToDouble(hc.light);
        const RectangleSetup<double> sd = MakeRectangleSetup(Vec3d(hc.origin), Ld);
        const RectangleSetup<float> sf = MakeRectangleSetup(hc.origin, hc.light);
        ASSERT_EQ(sd.valid, sf.valid);
        if (!sd.valid) continue;
        for (const Point2<float>& uv : SuiteUVs()) {
            ++n;
            const LightSample<double> ld = SampleRectangle(sd, Point2<double>{uv.u, uv.v});
            const Point2<double> bd = InvertRectangle(sd, ld.point);
            const double ed = std::max(std::abs(bd.u - uv.u), std::abs(bd.v - uv.v));
            worst_d = std::max(worst_d, ed);
            EXPECT_LE(ed, 1e-4) << hc.name << " double u " << uv.u << " v " << uv.v;

            const LightSample<float> lf = SampleRectangle(sf, uv);
            const Point2<double> bf_d = InvertRectangle(sf, lf.point);
            const Point2<float> bf{float(bf_d.u), float(bf_d.v)};  // as the float bindings return it
            const Point2<double> rep = InvertRectangle(sd, Vec3d(lf.point));
            const double allowance = std::max(std::abs(rep.u - bd.u), std::abs(rep.v - bd.v));
            const double ef = std::max(std::abs(bf.u - uv.u), std::abs(bf.v - uv.v));
            worst_f = std::max(worst_f, ef - allowance);
            EXPECT_LE(ef, 1e-4 + allowance) << hc.name << " float u " << uv.u << " v " << uv.v;
        }
    }
    std::printf("round trip: %d (u, v); worst error double %.3g, float (beyond point rounding) %.3g\n", n, worst_d,
                worst_f);
}

// `rectangle` (and `rectangle_cosine`, which rides on its setup): the area fallback
// is left only for the y-step of a thin light seen from ~1e6 sizes away, beside it
// in y (the y-offset of the sample cannot be resolved next to the 1e6 coordinate).
// Along that family, just below and just above the switch: both sides estimate the
// closed-form irradiance without bias, and return the pdf of their point.
TEST(Rectangle, FallbackSwitchIsUnbiasedOnBothSides) {
    const RectLight<float> L{{-0.5f, -5e-4f, 0}, {1, 0, 0}, {0, 1e-3f, 0}, false};
    auto at = [](double t) { return Vec3f(0.1f, float(t), float(t)); };
    auto fallback = [&](double t) { return MakeRectangleSetup(at(t), L).area_fallback; };
    const auto [t_lo, t_hi] = FindSwitch(1e4, 1e7, fallback);
    const Vec3f o_lo = at(t_lo), o_hi = at(t_hi);
    ASSERT_FALSE(MakeRectangleSetup(o_lo, L).area_fallback);
    ASSERT_TRUE(MakeRectangleSetup(o_hi, L).area_fallback);
    std::printf("rectangle switches to area sampling between t = %.7g and %.7g\n", t_lo, t_hi);
    const Vec3f n = Normalize(Vec3f(0, -1, -1));
    ExpectUnbiasedAcross<Technique::Rectangle>("switch", o_lo, o_hi, n, L);
    ExpectUnbiasedAcross<Technique::RectangleCosine>("switch", o_lo, o_hi, n, L);
    for (const Vec3f& o : {o_lo, o_hi}) {
        const LightSampler<Technique::Rectangle, float> s(o, n, L);
        for (float u : HardCaseUV())
            for (float v : HardCaseUV()) {
                const LightSample<float> ls = s.Sample({u, v});
                EXPECT_NEAR(s.PDF(ls.point), ls.pdf, 1e-4f * ls.pdf);
            }
    }
}

// Nearly edge-on setups use the Newton-refined x-step (polish_x): unbiased, with the
// closed-form start (error estimate ~26 in u here) being useless on its own.
TEST(Rectangle, NewtonRefinedRegimeIsUnbiased) {
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, false};
    for (const Vec3f& o : {Vec3f(2.f, 0.1f, 1e-9f), Vec3f(1.5f, 1.5f, 1e-7f), Vec3f(0.50001f, 0.2f, 1e-9f)}) {
        const RectangleSetup<float> sr = MakeRectangleSetup(o, L);
        ASSERT_TRUE(sr.valid);
        ASSERT_TRUE(sr.polish_x);
        ASSERT_FALSE(sr.area_fallback);
        const Vec3f n(-1, 0, 0);  // the whole light in front (the reference does not clip)
        ExpectUnbiasedAcross<Technique::Rectangle>("newton", o, o, n, L);
        ExpectUnbiasedAcross<Technique::RectangleCosine>("newton", o, o, n, L);
    }
}
