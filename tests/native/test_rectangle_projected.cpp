// Technique `rectangle_projected` (rectangle_projected.h): directions uniform in projected solid
// angle, so that cos / pdf is the projected solid angle E for every sample (zero variance for a
// Lambertian receiver under an unoccluded light).  Checked here over the hard-case suite
// (core/hard_cases.h) and the horizon cases (the light clipped by the tangent plane):
//  - Lambert's formula (RectangleProjectedSolidAngle) against a __float128 reference;
//  - the zero-variance property: every single sample's cos / pdf equals the reference E within
//    1e-5 (so their spread is below 1e-4), in the float path;
//  - the inverse round trip within 1e-4;
//  - the switch to `rectangle` (where the sweep cannot be resolved) is followed by PDF and Invert.
// Its distribution is checked by the chi-square harness (tests/python/test_rectangle_projected.py).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "sampling_test_util.h"

using namespace sphrect;
using namespace sphrect_test;

namespace {

std::vector<Point2<float>> SuiteUVs() { return GridAndRandomUVs(13, 40); }

// The horizon cases: a unit light below a shading point whose tangent plane cuts it -- through
// a corner exactly, or leaving a sliver of it above (or below) the horizon -- and normals almost
// in the light's plane.
std::vector<HardCase> HorizonCases() {
    std::vector<HardCase> cases;
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, true};
    const Vec3d o(0.2, 0.1, 1.0);
    // n(alpha) = (sin alpha, 0.3 sin alpha, -cos alpha): the horizon tilts as alpha grows and
    // passes through corner k where n . (c_k - o) = 0.
    const Vec3d corners[4] = {{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}};
    for (int k = 0; k < 4; ++k) {
        const Vec3d d = corners[k] - o;
        const double p = d.x + 0.3 * d.y;  // n . d = sin(alpha) p - cos(alpha) d.z
        const double alpha = std::atan2(d.z, p);
        const double a = alpha < 0 ? alpha + M_PI : alpha;
        for (double delta : {-1e-3, -1e-6, 0.0, 1e-6, 1e-3}) {
            const Vec3d n = Normalize(Vec3d(std::sin(a + delta), 0.3 * std::sin(a + delta), -std::cos(a + delta)));
            cases.push_back(
                {"corner" + std::to_string(k) + "_delta" + HardCaseNumber(delta), L, Vec3f(o), Vec3f(n), 1});
        }
    }
    for (double eps : {1e-7, 1e-4, 1e-2})  // normal almost in the light's plane
        for (const Vec3d& t : {Vec3d(1, 0, 0), Vec3d(0.6, -0.8, 0)})
            cases.push_back(
                {"in_plane_normal_" + HardCaseNumber(eps), L, Vec3f(o), Vec3f(Normalize(t + Vec3d(0, 0, -eps))), 1});
    // Shading points just above the light's plane, the light half above the horizon.
    for (double h : {1e-7, 1e-4})
        cases.push_back(
            {"low_h" + HardCaseNumber(h), L, Vec3f(0.1f, 0.2f, float(h)), Vec3f(Normalize(Vec3d(1, 0, -0.2))), 1});
    return cases;
}

struct ZeroVarianceStats {
    int setups = 0, switched = 0, samples = 0, zero_pdf = 0, near_horizon = 0;
    double max_rel_err = 0, max_spread = 0, max_e_err = 0, max_e_err_switched = 0;
};

// Every sample's cos / pdf against the reference E; the setup's spread (max - min) / E.
template <class T>
void CheckZeroVariance(const HardCase& hc, ZeroVarianceStats* st, bool allow_switch) {
    const RectLight<T> L{Vec3<T>(hc.light.corner), Vec3<T>(hc.light.ex), Vec3<T>(hc.light.ey), hc.light.two_sided};
    const Vec3<T> o(hc.origin), n(hc.normal);
    const Vec3d nd = Normalize(Vec3d(n));
    const double ref = ReferenceProjectedSolidAngle(o, nd, L);
    const LightSampler<Technique::RectangleProjected, T> s(o, n, L);
    const LightSampler<Technique::RectangleProjected, double> sd(
        Vec3d(o), Vec3d(n), RectLight<double>{Vec3d(L.corner), Vec3d(L.ex), Vec3d(L.ey), L.two_sided});
    SCOPED_TRACE(hc.name + (sizeof(T) == 4 ? " float" : " double"));
    if (!s.Valid()) {
        // Invalid only where nothing of the light is above the horizon (or the setup is degenerate).
        EXPECT_LE(ref, 1e-12 * RectangleSolidAngle(Vec3d(o), RectLight<double>{Vec3d(L.corner), Vec3d(L.ex),
                                                                               Vec3d(L.ey), L.two_sided}));
        return;
    }
    ++st->setups;
    // Lambert's formula of the core (double) against the __float128 reference.
    // Bound: the rectangle's standard for Omega (1e-5); the worst of the suite is a light of aspect
    // 1e5 seen from 1e6 sizes away, where the terms of the sum are 1e11 times E.
    // (Plus 1e-15 Omega absolute: a light crossing the horizon by a sliver of E ~ 1e-26 is not
    // resolved in double, nor needs to be.)
    const double omega =
        RectangleSolidAngle(Vec3d(o), RectLight<double>{Vec3d(L.corner), Vec3d(L.ex), Vec3d(L.ey), L.two_sided});
    const double E = RectangleProjectedSolidAngle(o, n, L), e_err = std::abs(E - ref) / ref;
    EXPECT_LE(std::abs(E - ref), 1e-5 * ref + 1e-15 * omega) << "E " << E << " reference " << ref;
    if (s.r.use_rectangle) {
        ++st->switched;
        st->max_e_err_switched = std::max(st->max_e_err_switched, e_err);
        EXPECT_TRUE(allow_switch) << "switched to rectangle, error estimate " << s.r.error_estimate;
        return;
    }
    st->max_e_err = std::max(st->max_e_err, e_err);
    // The sweep's own total area (what u is measured against) is as accurate as its error
    // estimate says (+1e-8: the float light's edges are orthogonal only to rounding, which the
    // reference, built from its corners, sees).
    EXPECT_LE(std::abs(s.r.swept - ref), (s.r.error_estimate + 1e-8) * ref) << "swept " << s.r.swept << " E " << ref;
    double lo = INFINITY, hi = -INFINITY;
    for (const Point2<float>& uv : SuiteUVs()) {
        const LightSample<T> ls = s.Sample({T(uv.u), T(uv.v)});
        ++st->samples;
        ASSERT_TRUE(IsFinite(ls.point) && IsFinite(ls.dir) && std::isfinite(ls.pdf) && std::isfinite(ls.dist));
        if (ls.pdf == 0) {  // allowed only on the horizon (cos ~ 0), where the density vanishes
            ++st->zero_pdf;
            EXPECT_LE(double(Dot(ls.dir, n)), 1e-5) << "u " << uv.u << " v " << uv.v;
            continue;
        }
        EXPECT_LE(DistanceToLight(ls.point, L), 1e-5 * hc.size) << "u " << uv.u << " v " << uv.v;
        // The one-sample irradiance estimate cos / pdf, with cos of the sample's direction.  The
        // direction is stored in T, whose rounding (<= 2 eps_T) changes cos by up to 2 eps_T, i.e.
        // by 2 eps_T / cos relative: near the horizon (cos -> 0) that is the output's own limit, so
        // the bound adds it, and the spread is taken over the samples where it is below 1e-5.
        const double cos_theta = double(Dot(Vec3d(ls.dir), nd));
        const double estimate = cos_theta / double(ls.pdf);
        const double representable = 2 * double(std::numeric_limits<T>::epsilon()) / std::max(cos_theta, 1e-300);
        const double err = std::abs(estimate - ref) / ref;
        EXPECT_LE(err, 1e-5 + representable)
            << "u " << uv.u << " v " << uv.v << " cos/pdf " << estimate << " E " << ref;
        if (representable <= 1e-5) {
            st->max_rel_err = std::max(st->max_rel_err, err);
            lo = std::min(lo, estimate);
            hi = std::max(hi, estimate);
        } else {
            ++st->near_horizon;
        }
        // PDF of the returned point: the same formula at the point rounded to T; compared where
        // that rounding does not itself change the density (checked with the double path).
        // Beyond that, close to o the point's own rounding (eps_T |p|, against its distance)
        // moves cos by up to that ratio: the allowance, relative to cos.
        const Vec3d pd = Vec3d(sd.Sample({double(uv.u), double(uv.v)}).point);
        const double exact = sd.PDF(pd), rounded = sd.PDF(Vec3d(ls.point));
        const double p_max =
            std::max({std::abs(double(ls.point.x)), std::abs(double(ls.point.y)), std::abs(double(ls.point.z))});
        const double moved =
            4 * double(std::numeric_limits<T>::epsilon()) * p_max / double(ls.dist) / std::max(cos_theta, 1e-300);
        if (std::abs(exact - rounded) <= 1e-5 * exact) {
            EXPECT_NEAR(double(s.PDF(ls.point)), double(ls.pdf), (2e-4 + moved) * double(ls.pdf))
                << "u " << uv.u << " v " << uv.v;
        }
    }
    if (hi >= lo) st->max_spread = std::max(st->max_spread, (hi - lo) / ref);
}

template <class T>
void ZeroVarianceOver(const std::vector<HardCase>& cases, const char* what, bool allow_switch) {
    ZeroVarianceStats st;
    for (const HardCase& hc : cases) {
        CheckZeroVariance<T>(hc, &st, allow_switch);
        if (::testing::Test::HasFatalFailure()) return;
    }
    std::printf(
        "%s %s: setups %d switched to rectangle %d samples %d (pdf 0 on the horizon: %d, within the output's rounding "
        "of it: %d);"
        " max |cos/pdf - E| / E %.3g, max spread %.3g; E rel. error %.3g (switched setups %.3g)\n",
        what, sizeof(T) == 4 ? "float" : "double", st.setups, st.switched, st.samples, st.zero_pdf, st.near_horizon,
        st.max_rel_err, st.max_spread, st.max_e_err, st.max_e_err_switched);
    EXPECT_LE(st.max_spread, 1e-4);
}

}  // namespace

TEST(RectangleProjected, ZeroVarianceOverHardCasesFloat) {
    ZeroVarianceOver<float>(HardCaseSuite(), "hard cases", true);
}
TEST(RectangleProjected, ZeroVarianceOverHardCasesDouble) {
    ZeroVarianceOver<double>(HardCaseSuite(), "hard cases", true);
}
TEST(RectangleProjected, ZeroVarianceOverHorizonCasesFloat) {
    ZeroVarianceOver<float>(HorizonCases(), "horizon", true);
}
TEST(RectangleProjected, ZeroVarianceOverHorizonCasesDouble) {
    ZeroVarianceOver<double>(HorizonCases(), "horizon", true);
}

// The switch: where it happens the light's projected solid angle is tiny against the sweep's
// rounding, i.e. the light spans a tiny angle; `rectangle` is followed by Sample, PDF and Invert,
// and its cos / pdf is then E within the light's angular extent.
TEST(RectangleProjected, SwitchIsFollowedEverywhere) {
    int switched = 0;
    for (const HardCase& hc : HardCaseSuite()) {
        const LightSampler<Technique::RectangleProjected, float> s(hc.origin, hc.normal, hc.light);
        if (!s.Valid() || !s.r.use_rectangle) continue;
        ++switched;
        SCOPED_TRACE(hc.name);
        const LightSampler<Technique::Rectangle, float> r(hc.origin, hc.normal, hc.light);
        for (const Point2<float>& uv : SuiteUVs()) {
            const LightSample<float> a = s.Sample(uv), b = r.Sample(uv);
            EXPECT_EQ(a.point.x, b.point.x);
            EXPECT_EQ(a.point.y, b.point.y);
            EXPECT_EQ(a.point.z, b.point.z);
            EXPECT_EQ(a.pdf, b.pdf);
            EXPECT_EQ(s.PDF(a.point), r.PDF(a.point));
            const Point2<double> ia = InvertRectangleProjected(s.r, a.point), ib = InvertRectangle(r.r, a.point);
            EXPECT_EQ(ia.u, ib.u);
            EXPECT_EQ(ia.v, ib.v);
        }
        // Where it switches, cos / pdf under `rectangle` is still E to 1e-4 (the light spans a tiny angle).
        const double ref = ReferenceProjectedSolidAngle(hc.origin, Normalize(Vec3d(hc.normal)), hc.light);
        for (const Point2<float>& uv : SuiteUVs()) {
            const LightSample<float> a = s.Sample(uv);
            if (a.pdf > 0) {
                EXPECT_LE(std::abs(double(Dot(Vec3d(a.dir), Normalize(Vec3d(hc.normal)))) / a.pdf - ref), 1e-4 * ref);
            }
        }
    }
    std::printf("hard-case setups switched to rectangle: %d\n", switched);
    // A zero normal also switches.
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, true};
    const LightSampler<Technique::RectangleProjected, float> z(Vec3f(0.1f, 0.2f, 1), Vec3f(0, 0, 0), L);
    EXPECT_TRUE(z.Valid() && z.r.use_rectangle);
}

// (u, v) -> point -> (u, v) within 1e-4 over the hard-case and horizon suites (double path; in
// float the allowance is what rounding the point to float moves (u, v) by, measured in double).
TEST(RectangleProjected, InverseRoundTrip) {
    double worst_d = 0, worst_f = 0;
    int n = 0, not_one_to_one = 0, at_apex = 0, thin_strips = 0;
    double worst_strip = 0;
    std::vector<HardCase> cases = HardCaseSuite();
    for (const HardCase& hc : HorizonCases()) cases.push_back(hc);
    for (const HardCase& hc : cases) {
        const RectLight<double> Ld{Vec3d(hc.light.corner), Vec3d(hc.light.ex), Vec3d(hc.light.ey), hc.light.two_sided};
        const RectangleProjectedSetup<double> sd = MakeRectangleProjectedSetup(Vec3d(hc.origin), Vec3d(hc.normal), Ld);
        const RectangleProjectedSetup<float> sf = MakeRectangleProjectedSetup(hc.origin, hc.normal, hc.light);
        if (!sd.valid || !sf.valid) continue;
        SCOPED_TRACE(hc.name);
        // A light seen edge-on with n through it (star case) projects to a strip through the disk's
        // centre as thin as the smallest sweep rate: azimuths inside it are not resolved in double
        // when it is thinner than 1e-6 of its length (the suite's lights 1e-9 sizes above their
        // plane, E ~ 1e-10 ... 1e-15).  There a failed round trip is counted apart (and the
        // direction Sample(Invert(p)) checked instead; in float not at all).
        double min_rate = INFINITY, max_radius = 0;
        for (int k = 0; k < sd.num_arcs; ++k) min_rate = std::min(min_rate, sd.arcs[k].sweep_rate);
        for (int j = 0; j < sd.num_pieces; ++j)
            max_radius = std::max(max_radius, std::hypot(sd.pieces[j].from.x, sd.pieces[j].from.y));
        const bool thin = sd.star && !sd.use_rectangle && 2 * min_rate < 1e-6 * max_radius;
        bool thin_failed = false;
        for (const Point2<float>& uv : SuiteUVs()) {
            const LightSample<double> ld = SampleRectangleProjected(sd, Point2<double>{uv.u, uv.v});
            if (!(ld.pdf > 0)) continue;  // on the horizon
            ++n;
            const Point2<double> bd = InvertRectangleProjected(sd, ld.point);
            // In the star case the sweep goes once around n: u = 0 and u = 1 are the same azimuth.
            auto u_error = [&](double u) {
                const double e = std::abs(u - uv.u);
                return sd.star && !sd.use_rectangle ? std::min(e, 1 - e) : e;
            };
            const double ed = std::max(u_error(bd.u), std::abs(bd.v - uv.v));
            // At the apexes of a near/far sweep (u within 1e-6 of 0 or 1) its two arcs meet: the
            // gap between them, over which v runs, vanishes like the square root of u's distance,
            // and v is resolved only to eps over that gap (1e-4 at u = 1e-7 for a light seen
            // edge-on).  Counted apart (and not checked: u's own rounding moves such a point by
            // up to 1e-5 rad there).
            const bool apex = !sd.star && !sd.use_rectangle && (uv.u < 1e-6 || uv.u > 1 - 1e-6);
            if (ed > 1e-4 || apex) {
                // Where the map is not one-to-one -- the centre of a star-case sweep (v = 0: every u
                // gives the direction n), the apex of a near/far sweep, where the two arcs meet and
                // v is not resolved across their vanishing gap -- any (u, v) that maps to the same
                // direction is a correct inverse.
                const LightSample<double> again = SampleRectangleProjectedAt(sd, bd.u, bd.v);
                // (To the direction's resolution through the double point, built from the corner
                // and the edges: eps (|corner| + |ex| + |ey|) / dist; and 1e-8 rad: at the apex of a
                // near/far sweep the area grows as s^2, so u's own rounding, 1e-16, moves s by 1e-8.)
                const double p_max = Length(Ld.corner) + Length(Ld.ex) + Length(Ld.ey);
                const double resolution = 1e-8 + 8 * std::numeric_limits<double>::epsilon() * p_max / ld.dist;
                if (apex) {
                    ++at_apex;
                    continue;
                }
                if (Length(again.dir - ld.dir) <= resolution) {
                    ++not_one_to_one;
                    continue;
                }
                if (thin) {
                    thin_failed = true;
                    worst_strip = std::max(worst_strip, Length(again.dir - ld.dir));
                    continue;
                }
            }
            worst_d = std::max(worst_d, ed);
            EXPECT_LE(ed, 1e-4) << "double u " << uv.u << " v " << uv.v << " back " << bd.u << " " << bd.v
                                << " dir moved " << Length(SampleRectangleProjectedAt(sd, bd.u, bd.v).dir - ld.dir);
            const LightSample<float> lf = SampleRectangleProjected(sf, uv);
            if (!(lf.pdf > 0) || sf.use_rectangle != sd.use_rectangle || thin) continue;
            const Point2<double> bf = InvertRectangleProjected(sf, lf.point);
            const Point2<double> rep = InvertRectangleProjected(sd, Vec3d(lf.point));
            const double allowance = std::max(std::abs(rep.u - bd.u), std::abs(rep.v - bd.v));
            const double ef = std::max(u_error(bf.u), std::abs(bf.v - uv.v));
            worst_f = std::max(worst_f, ef - allowance);
            EXPECT_LE(ef, 1e-4 + allowance) << "float u " << uv.u << " v " << uv.v;
        }
        thin_strips += thin_failed;
    }
    std::printf(
        "round trip: %d (u, v), of which %d where the map is not one-to-one and %d at a sweep's apex; worst"
        " error double %.3g, float (beyond point rounding) %.3g; %d thin-strip setups missed (u, v), direction moved "
        "by up to"
        " %.3g\n",
        n, not_one_to_one, at_apex, worst_d, worst_f, thin_strips, worst_strip);
    EXPECT_LE(thin_strips, 10);
    EXPECT_LE(worst_strip, 1e-2);
    EXPECT_GT(n, 1000);
    EXPECT_LT(not_one_to_one, n / 10);
}

// A light wholly below the horizon is invalid; a light wholly above it has the unclipped E.
TEST(RectangleProjected, HorizonValidity) {
    const RectLight<float> L{{-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0}, true};
    const Vec3f o(0.1f, 0.2f, 1);
    EXPECT_FALSE((LightSampler<Technique::RectangleProjected, float>(o, Vec3f(0, 0, 1), L).Valid()));
    const Vec3f down(0, 0, -1);
    const LightSampler<Technique::RectangleProjected, float> s(o, down, L);
    ASSERT_TRUE(s.Valid());
    EXPECT_NEAR(s.r.E, ReferenceIrradiance(o, Vec3d(down), L), 1e-12);
}

// ArcTan2 (the arcs' angles) against std::atan2: within 2 ulp over ratios from 1e-60 to 1e60, both
// signs, near the reduction's boundary tan(pi/8) and near the diagonal; the special values
// (zeros, infinities, NaN, subnormals) as std::atan2's within 1 ulp.
TEST(RectangleProjected, ArcTan2MatchesStd) {
    auto ulps = [](double a, double b) {
        if (a == b) return 0.0;
        const double ulp = std::nextafter(std::abs(b), INFINITY) - std::abs(b);
        return std::abs(a - b) / ulp;
    };
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(-1, 1), Exp(-30, 30);
    double worst = 0;
    for (int i = 0; i < 400000; ++i) {
        double y = U(rng) * std::pow(10.0, i % 3 == 0 ? Exp(rng) : 0.0);
        double x = U(rng) * std::pow(10.0, i % 5 == 0 ? Exp(rng) : 0.0);
        if (i % 7 == 0) x = y * (1 + 1e-3 * U(rng));
        if (i % 11 == 0) y = x * 0.41421356237309503 * (1 + 1e-6 * U(rng));
        worst = std::max(worst, ulps(ArcTan2(y, x), std::atan2(y, x)));
        ASSERT_LE(worst, 2.0) << "y " << y << " x " << x;
    }
    std::printf("ArcTan2: worst %.2f ulp from std::atan2\n", worst);
    const double special[] = {0.0, -0.0, 1.0, -1.0, INFINITY, -INFINITY, 1e-320, -1e-320, 1e300};
    for (double y : special)
        for (double x : special) {
            const double a = ArcTan2(y, x), b = std::atan2(y, x);
            EXPECT_LE(ulps(a, b), 1.0) << "y " << y << " x " << x;
            EXPECT_EQ(std::signbit(a), std::signbit(b)) << "y " << y << " x " << x;
        }
    EXPECT_TRUE(std::isnan(ArcTan2(NAN, 1.0)));
    EXPECT_TRUE(std::isnan(ArcTan2(1.0, NAN)));
}

namespace {

// Ordinary configurations (a 1 x 1.5 light seen from shading points around and below it, normals
// up and tilted) followed by the hard-case and horizon suites.
std::vector<HardCase> MapAccuracyCases() {
    std::vector<HardCase> cases;
    const RectLight<float> L{{-0.5f, -0.75f, 2}, {1, 0, 0}, {0, 1.5f, 0}, true};
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int i = 0; i < 200; ++i) {
        const Vec3f o(float(2 * U(rng)), float(2 * U(rng)), float(1.7 - 3 * std::abs(U(rng))));
        const Vec3d n = i % 2 ? Vec3d(0, 0, 1) : Normalize(Vec3d(U(rng), U(rng), U(rng) + 0.5));
        cases.push_back({"ordinary" + std::to_string(i), L, o, Vec3f(n), 1});
    }
    for (const HardCase& hc : HardCaseSuite()) cases.push_back(hc);
    for (const HardCase& hc : HorizonCases()) cases.push_back(hc);
    return cases;
}

// Where the map's (u, v) falls in a near/far piece: |the area swept up to its solution - alpha|
// in u (-1 in a star piece), and the solution's point against ArcPoint at its angle.
template <class T>
double MapResidual(const RectangleProjectedSetup<T>& s, double u, double* point_error) {
    using namespace projected_detail;
    const double target = u * s.swept;
    int j = 0;
    while (j + 1 < s.num_pieces && s.pieces[j + 1].cdf <= target) ++j;
    const ProjectedPiece& pc = s.pieces[j];
    if (pc.inner < 0) return -1;
    const ProjectedArc& F = s.arcs[pc.outer];
    const ProjectedArc& N = s.arcs[pc.inner];
    const double alpha = ClampNaN(target - pc.cdf, 0, pc.area);
    const NearFarSolution sol = SolveNearFar<T>(pc, F, N, alpha, s.error_estimate * s.swept);
    *point_error = Length(sol.wf - ArcPoint(F, sol.sf));
    return std::abs(PieceArea(pc, F, N, sol.sf, sol.wf) - alpha) / s.swept;
}

// The sample's Newton steps stop where u is met within kProjectedNewtonTolerance<T>^2 of the piece's
// area (float 1e-12, double 1e-16): on the ordinary configurations the residual is within `bound`
// beyond the rounding of the sweep's own areas (its error estimate, in u).  In the suites the
// residual's own evaluation is ill-conditioned (thin or edge-on projections: an azimuth's rounding
// moves the inner arc's angle far), and u is met within the sweep's accepted error,
// kProjectedMaxError.
template <class T>
void CheckMapAccuracy(double bound) {
    double worst_ordinary = 0, worst_suites = 0, worst_point = 0;
    int near_far = 0;
    for (const HardCase& hc : MapAccuracyCases()) {
        const RectLight<T> L{Vec3<T>(hc.light.corner), Vec3<T>(hc.light.ex), Vec3<T>(hc.light.ey), hc.light.two_sided};
        const RectangleProjectedSetup<T> s = MakeRectangleProjectedSetup(Vec3<T>(hc.origin), Vec3<T>(hc.normal), L);
        if (!s.valid || s.use_rectangle) continue;
        SCOPED_TRACE(hc.name);
        const bool ordinary = hc.name.rfind("ordinary", 0) == 0;
        for (const Point2<float>& uv : SuiteUVs()) {
            double point_error = 0;
            const double r = MapResidual(s, uv.u, &point_error);
            if (r < 0) continue;
            ++near_far;
            EXPECT_LE(point_error, 1e-14) << "u " << uv.u;
            worst_point = std::max(worst_point, point_error);
            if (ordinary) {
                EXPECT_LE(r, bound + s.error_estimate) << "u " << uv.u;
                worst_ordinary = std::max(worst_ordinary, r - s.error_estimate);
            } else {
                EXPECT_LE(r, kProjectedMaxError) << "u " << uv.u;
                worst_suites = std::max(worst_suites, r);
            }
        }
    }
    std::printf(
        "map accuracy (%s): %d near/far samples; |u error| beyond the sweep's error estimate worst %.3g on the"
        " ordinary setups, in the suites %.3g; point off its arc angle by %.3g\n",
        sizeof(T) == 4 ? "float" : "double", near_far, worst_ordinary, worst_suites, worst_point);
    EXPECT_GT(near_far, 10000);
}

}  // namespace

TEST(RectangleProjected, MapAccuracyFloat) { CheckMapAccuracy<float>(1e-10); }
TEST(RectangleProjected, MapAccuracyDouble) { CheckMapAccuracy<double>(1e-14); }

// The helpers of the near/far sweep: z^2 of an arc at an azimuth (algebraic) against the arc's
// point there, and the small-step rotation against ArcPoint, over the arcs of the ordinary setups.
TEST(RectangleProjected, ArcHelpers) {
    using namespace projected_detail;
    double worst_z2 = 0, worst_rot = 0;
    int arcs = 0;
    for (const HardCase& hc : MapAccuracyCases()) {
        if (hc.name.rfind("ordinary", 0) != 0) continue;
        const RectangleProjectedSetup<double> s = MakeRectangleProjectedSetup(
            Vec3d(hc.origin), Vec3d(hc.normal),
            RectLight<double>{Vec3d(hc.light.corner), Vec3d(hc.light.ex), Vec3d(hc.light.ey), true});
        if (!s.valid || s.use_rectangle) continue;
        for (int k = 0; k < s.num_arcs; ++k) {
            const ProjectedArc& arc = s.arcs[k];
            ++arcs;
            for (int i = 0; i <= 16; ++i) {
                const double sa = arc.arc_length * i / 16;
                const Vec3d w = ArcPoint(arc, sa);
                // (z^2 moves with the azimuth as 1 / |g_z|: w's own rounding, relative.)
                worst_z2 = std::max(worst_z2, std::abs(ArcZ2AtAzimuth(arc, w.x, w.y) - w.z * w.z) * std::abs(arc.g.z));
                for (double step : {1e-2, -3e-3, 1e-5, -1e-9}) {
                    Vec3d wr = w, tr = arc.t * std::cos(sa) - arc.a * std::sin(sa);
                    RotateOnArc(&wr, &tr, step);
                    worst_rot = std::max(worst_rot, Length(wr - ArcPoint(arc, sa + step)));
                }
            }
        }
    }
    std::printf("arc helpers over %d arcs: z^2 at an azimuth worst %.3g, rotation worst %.3g\n", arcs, worst_z2,
                worst_rot);
    EXPECT_GT(arcs, 300);
    EXPECT_LE(worst_z2, 1e-14);
    EXPECT_LE(worst_rot, 1e-15);
}
