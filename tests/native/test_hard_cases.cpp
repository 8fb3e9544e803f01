// The hard-case suite (issue 2, "Numerical stability"), for every technique, in
// the float path the renderer uses and in double:
//  - no NaN / Inf for any case and any (u, v) including 0, the largest float below 1, 1;
//  - sample points on the light within 1e-5 of its size;
//  - Omega within 1e-5 relative error of a __float128 reference;
// (the suite is core/hard_cases.h, which the study's accuracy table measures too);
//  - the pdf returned with a sample equals PDF(point);
//  - `triangles` returns 1 / Omega everywhere, `rectangle` wherever it does not fall back to
//    area sampling (thin lights 1e4 sizes away and more: counted and printed).
// And the degenerate inputs: pdf 0, invalid, no NaN.
#include <gtest/gtest.h>

#include <cstdio>

#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

namespace {

template <Technique K, class T>
double SamplerSolidAngle(const LightSampler<K, T>& s) {
    if constexpr (K == Technique::Rectangle)
        return s.r.solid_angle;
    else if constexpr (K == Technique::Triangles)
        return T(s.r.omega);
    else if constexpr (K == Technique::RectangleCosine)
        return s.r.rect.solid_angle;
    else if constexpr (K == Technique::RectangleProjected)
        return s.r.use_rectangle ? s.r.rect.solid_angle : -1;
    else
        return -1;  // area: no solid angle
}

template <class T>
bool Finite(const LightSample<T>& s) {
    return IsFinite(s.point) && IsFinite(s.dir) && std::isfinite(s.dist) && std::isfinite(s.pdf);
}

struct SuiteStats {
    double max_omega_err = 0;
    int cases = 0, valid = 0, samples = 0, pdf_checked = 0;
    double max_uniform_err = 0;  // |pdf Omega - 1| of the solid-angle-uniform techniques
    int fallback_setups = 0;     // setups that sample (part of) the light by area instead
};

// Relative tolerance of pdf = 1 / Omega for `triangles` (everywhere) and `rectangle` (where it
// does not fall back to area sampling): Omega's own rounding (the suite's worst is 6e-8 in
// float) and the float rounding of the pdf.
constexpr double kUniformPDFTolerance = 2e-7;

template <Technique K, class T>
void RunHardCase(const HardCase& hc, SuiteStats* st) {
    const RectLight<T> L{Vec3<T>(hc.light.corner), Vec3<T>(hc.light.ex), Vec3<T>(hc.light.ey), hc.light.two_sided};
    const Vec3<T> o(hc.origin), n(hc.normal);
    const double ref = ReferenceSolidAngle(o, L);
    const LightSampler<K, T> s(o, n, L);
    const LightSampler<K, double> sd(Vec3d(o), Vec3d(n),
                                     RectLight<double>{Vec3d(L.corner), Vec3d(L.ex), Vec3d(L.ey), L.two_sided});
    SCOPED_TRACE(hc.name + " " + TechniqueName(K) + (sizeof(T) == 4 ? " float" : " double"));
    ++st->cases;
    ASSERT_EQ(s.Valid(), ref > 0) << "reference Omega " << ref;
    if (!s.Valid()) return;
    ++st->valid;
    const double omega = SamplerSolidAngle(s);
    if (omega >= 0) {
        const double err = std::abs(omega - ref) / ref;
        st->max_omega_err = std::max(st->max_omega_err, err);
        EXPECT_LE(err, 1e-5) << "Omega " << omega << " reference " << ref;
    }
    // Does the setup sample some part of the light by area (so that its pdf is not 1 / Omega there)?
    bool fallback = false;
    if constexpr (K == Technique::Rectangle) fallback = s.r.area_fallback;
    constexpr bool uniform = K == Technique::Rectangle || K == Technique::Triangles;
    st->fallback_setups += fallback;
    std::vector<Point2<T>> uvs;
    for (float u : HardCaseUV())
        for (float v : HardCaseUV()) uvs.push_back({T(u), T(v)});
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(0, 1);
    for (int i = 0; i < 30; ++i) uvs.push_back({T(U(rng)), T(U(rng))});
    for (const Point2<T>& uv : uvs) {
        const LightSample<T> ls = s.Sample(uv);
        ++st->samples;
        ASSERT_TRUE(Finite(ls)) << "u " << uv.u << " v " << uv.v;
        if ((K == Technique::RectangleCosine || K == Technique::RectangleProjected) && ls.pdf == 0) {
            // Only allowed where the density is 0: a corner below the horizon, whose weight is 0
            // (rectangle_cosine), a point on the horizon (rectangle_projected).
            EXPECT_LE(double(Dot(ls.dir, n)) / double(Length(n)), 1e-6) << "u " << uv.u << " v " << uv.v;
            continue;
        }
        ASSERT_GT(ls.pdf, 0) << "u " << uv.u << " v " << uv.v;
        ASSERT_GT(ls.dist, 0);
        EXPECT_NEAR(double(Length(ls.dir)), 1.0, 1e-5);
        EXPECT_LE(DistanceToLight(ls.point, L), 1e-5 * hc.size) << "u " << uv.u << " v " << uv.v;
        const T pdf = s.PDF(ls.point);
        ASSERT_TRUE(std::isfinite(pdf));
        if (uniform && !fallback) {
            const double err = std::abs(double(ls.pdf) * ref - 1);
            st->max_uniform_err = std::max(st->max_uniform_err, err);
            EXPECT_LE(err, kUniformPDFTolerance)
                << "pdf " << ls.pdf << " 1/Omega " << 1 / ref << " u " << uv.u << " v " << uv.v;
        }
        // rectangle_cosine: the pdf is a bilinear factor in [0, 4] times the rectangle's pdf;
        // where the factor is ~0 (corners at the horizon) compare against that scale.
        double scale = 0;
        if constexpr (K == Technique::RectangleCosine) scale = 4 * double(RectanglePDF(s.r.rect, ls.point));
        // rectangle_projected: pdf = cos / E at the point, and the point's own rounding (eps_T times
        // the light's coordinates) moves cos by that over the distance: near the horizon and near o
        // a relative change of that over cos.  The allowance 1e-7 * scale is 8 times that change.
        if constexpr (K == Technique::RectangleProjected) {
            const double c = double(Dot(ls.dir, n)) / double(Length(n));
            const double coords = double(Length(L.corner) + Length(L.ex) + Length(L.ey));
            scale = 1e7 * double(ls.pdf) * 8 * double(std::numeric_limits<T>::epsilon()) * coords /
                    (double(ls.dist) * std::max(c, 1e-300));
        }
        bool constant_pdf = false;
        if constexpr (K == Technique::Rectangle) constant_pdf = !s.r.area_fallback;
        if constexpr (K == Technique::Triangles) constant_pdf = true;
        if (constant_pdf) {
            EXPECT_EQ(pdf, ls.pdf);
            ++st->pdf_checked;
        } else if (sizeof(T) == 8) {
            EXPECT_NEAR(double(pdf), double(ls.pdf), 1e-6 * double(ls.pdf) + 1e-7 * scale)
                << "u " << uv.u << " v " << uv.v;
            ++st->pdf_checked;
        } else {
            // A varying pdf at a float point: compare where rounding the point to float
            // does not itself change the true density (checked with the double path).
            const Vec3d pd = Vec3d(sd.Sample({double(uv.u), double(uv.v)}).point);
            const double exact = sd.PDF(pd), rounded = sd.PDF(Vec3d(ls.point));
            if (std::abs(exact - rounded) <= 1e-5 * exact) {
                EXPECT_NEAR(double(pdf), double(ls.pdf), 2e-4 * double(ls.pdf) + 1e-6 * scale)
                    << "u " << uv.u << " v " << uv.v;
                ++st->pdf_checked;
            }
        }
    }
}

template <Technique K, class T>
void RunSuite() {
    SuiteStats st;
    for (const HardCase& hc : HardCaseSuite()) {
        RunHardCase<K, T>(hc, &st);
        if (::testing::Test::HasFatalFailure()) return;
    }
    std::printf(
        "%-16s %-6s cases %d valid %d samples %d pdf-checked %d max Omega rel. err %.3g fallback setups %d"
        " max |pdf Omega - 1| %.3g\n",
        TechniqueName(K), sizeof(T) == 4 ? "float" : "double", st.cases, st.valid, st.samples, st.pdf_checked,
        st.max_omega_err, st.fallback_setups, st.max_uniform_err);
}

}  // namespace

TEST(HardCases, AreaFloat) { RunSuite<Technique::Area, float>(); }
TEST(HardCases, AreaDouble) { RunSuite<Technique::Area, double>(); }
TEST(HardCases, TrianglesFloat) { RunSuite<Technique::Triangles, float>(); }
TEST(HardCases, TrianglesDouble) { RunSuite<Technique::Triangles, double>(); }
TEST(HardCases, RectangleFloat) { RunSuite<Technique::Rectangle, float>(); }
TEST(HardCases, RectangleDouble) { RunSuite<Technique::Rectangle, double>(); }
TEST(HardCases, RectangleCosineFloat) { RunSuite<Technique::RectangleCosine, float>(); }
TEST(HardCases, RectangleCosineDouble) { RunSuite<Technique::RectangleCosine, double>(); }
TEST(HardCases, RectangleProjectedFloat) { RunSuite<Technique::RectangleProjected, float>(); }
TEST(HardCases, RectangleProjectedDouble) { RunSuite<Technique::RectangleProjected, double>(); }

// ---------------------------------------------------------------- degenerate input

template <Technique K, class T>
void ExpectInvalid(const Vec3<T>& o, const Vec3<T>& n, const RectLight<T>& L, const char* what) {
    SCOPED_TRACE(std::string(what) + " " + TechniqueName(K));
    const LightSampler<K, T> s(o, n, L);
    EXPECT_FALSE(s.Valid());
    for (float u : HardCaseUV())
        for (float v : HardCaseUV()) {
            const LightSample<T> ls = s.Sample({T(u), T(v)});
            EXPECT_EQ(ls.pdf, 0);
            EXPECT_FALSE(ls.Valid());
            EXPECT_FALSE(std::isnan(ls.pdf));
            EXPECT_TRUE(std::isfinite(ls.dist));
        }
    EXPECT_EQ(s.PDF(L.corner + L.ex * T(0.5)), 0);
}

template <class T>
void DegenerateForAll() {
    const RectLight<T> ok{{-0.5, -0.5, 0}, {1, 0, 0}, {0, 1, 0}, false};
    const Vec3<T> up(0, 0, 1), above(0.1, 0.2, 1), below(0.1, 0.2, -1);
    auto all = [&](const Vec3<T>& o, const Vec3<T>& n, const RectLight<T>& L, const char* what) {
        ExpectInvalid<Technique::Area>(o, n, L, what);
        ExpectInvalid<Technique::Triangles>(o, n, L, what);
        ExpectInvalid<Technique::Rectangle>(o, n, L, what);
        ExpectInvalid<Technique::RectangleCosine>(o, n, L, what);
        ExpectInvalid<Technique::RectangleProjected>(o, n, L, what);
    };
    RectLight<T> zero_x = ok;
    zero_x.ex = {0, 0, 0};
    all(above, -up, zero_x, "zero-length edge x");
    RectLight<T> zero_y = ok;
    zero_y.ey = {0, 0, 0};
    all(above, -up, zero_y, "zero-length edge y");
    all(Vec3<T>(0.1, 0.2, 0), up, ok, "origin in the light's plane (inside)");
    all(Vec3<T>(3, 0.2, 0), up, ok, "origin in the light's plane (beside)");
    all(below, up, ok, "behind a one-sided light");
    RectLight<T> nan_light = ok;
    nan_light.corner.x = std::numeric_limits<T>::quiet_NaN();
    all(above, -up, nan_light, "NaN corner");
    all(Vec3<T>(std::numeric_limits<T>::infinity(), 0, 1), -up, ok, "infinite origin");
    // rectangle_cosine only: the light wholly below the shading point's horizon.
    ExpectInvalid<Technique::RectangleCosine>(above, up, ok, "light below the horizon");
    ExpectInvalid<Technique::RectangleProjected>(above, up, ok, "light below the horizon");
    // Two-sided: the back side is valid.
    RectLight<T> two = ok;
    two.two_sided = true;
    EXPECT_TRUE((LightSampler<Technique::Rectangle, T>(below, up, two).Valid()));
}

TEST(Degenerate, Float) { DegenerateForAll<float>(); }
TEST(Degenerate, Double) { DegenerateForAll<double>(); }

// No NaN or Inf for any finite input: random lights and shading points with
// coordinates and edge lengths over 60 orders of magnitude (and zeros), shading
// points on or 1e-6 off the light's plane, random normals (including zero).
TEST(Fuzz, NoNaNOrInfForAnyFiniteInput) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> U(0, 1), E(-30, 30);
    auto coord = [&]() {
        const float sign = U(rng) < 0.5f ? -1.f : 1.f;
        return U(rng) < 0.1f ? 0.f : sign * std::pow(10.f, E(rng));
    };
    int valid = 0;
    for (int it = 0; it < 20000; ++it) {
        const Vec3f c(coord(), coord(), coord()), n(coord(), coord(), coord());
        Vec3f o(coord(), coord(), coord());
        Vec3f ex(0, 0, 0), ey(0, 0, 0);
        const int ax = int(rng() % 3), ay = (ax + 1 + int(rng() % 2)) % 3;
        (ax == 0 ? ex.x : ax == 1 ? ex.y : ex.z) = std::pow(10.f, E(rng));
        (ay == 0 ? ey.x : ay == 1 ? ey.y : ey.z) = std::pow(10.f, E(rng));
        if (U(rng) < 0.3f) {
            o = c + ex * U(rng) + ey * U(rng);
            o.z += coord() * 1e-6f;
        }
        const RectLight<float> L{c, ex, ey, rng() % 2 == 0};
        for (Technique t : kAllTechniques)
            DispatchTechnique(t, [&](auto K) {
                const LightSampler<decltype(K)::value, float> s(o, n, L);
                valid += s.Valid();
                for (float u : {0.f, 0.3f, std::nextafter(1.f, 0.f), 1.f})
                    for (float v : {0.f, 0.7f, 1.f}) {
                        const LightSample<float> ls = s.Sample({u, v});
                        const float p = s.PDF(ls.point);
                        ASSERT_TRUE(std::isfinite(ls.pdf) && ls.pdf >= 0) << TechniqueName(t) << " it " << it;
                        ASSERT_TRUE(std::isfinite(p) && p >= 0) << TechniqueName(t) << " it " << it;
                        if (ls.pdf > 0) {
                            ASSERT_TRUE(IsFinite(ls.point) && IsFinite(ls.dir) && std::isfinite(ls.dist))
                                << TechniqueName(t) << " it " << it;
                        }
                    }
            });
        if (HasFatalFailure()) return;
    }
    EXPECT_GT(valid, 10000);  // the inputs exercise valid setups, not only rejections
}
