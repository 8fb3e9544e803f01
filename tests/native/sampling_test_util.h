// Shared helpers of the C++ sampling tests: high-precision references (solid angle,
// irradiance, distance to the light) and the irradiance estimate.  The hard-case suite is
// core/hard_cases.h (shared with the study); the chi-square harness is tests/python/chi2.py.
#pragma once

#include <gtest/gtest.h>
#include <quadmath.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/hard_cases.h"
#include "core/technique.h"

namespace sphrect_test {

// A light seen from one shading point (with its normal), named for test messages.
struct LightConfig {
    const char* name;
    sphrect::RectLight<float> light;
    sphrect::Vec3f origin, normal;
};

using namespace sphrect;
using Q = __float128;

// ---------------------------------------------------------------- references

struct Vec3q {
    Q x, y, z;
};
inline Vec3q ToQ(double x, double y, double z) { return {Q(x), Q(y), Q(z)}; }
inline Q DotQ(const Vec3q& a, const Vec3q& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3q CrossQ(const Vec3q& a, const Vec3q& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Q LenQ(const Vec3q& a) { return sqrtq(DotQ(a, a)); }

// Corners of the light relative to o, in quad precision, from the inputs converted exactly.
template <class T>
inline void CornersQ(const Vec3<T>& o, const RectLight<T>& L, Vec3q c[4]) {
    for (int k = 0; k < 4; ++k) {
        const Q a = (k == 1 || k == 2) ? 1 : 0, b = k >= 2 ? 1 : 0;
        c[k] = {Q(L.corner.x) + a * Q(L.ex.x) + b * Q(L.ey.x) - Q(o.x),
                Q(L.corner.y) + a * Q(L.ex.y) + b * Q(L.ey.y) - Q(o.y),
                Q(L.corner.z) + a * Q(L.ex.z) + b * Q(L.ey.z) - Q(o.z)};
    }
}

// Reference solid angle (Van Oosterom & Strackee on two triangles, __float128).
// 113-bit arithmetic: the known weak spot of this formula (relative error eps/h for a
// foot of o on the diagonal) stays below 1e-20 for every case of the suite.
template <class T>
inline double ReferenceSolidAngle(const Vec3<T>& o, const RectLight<T>& L) {
    Vec3q c[4];
    CornersQ(o, L, c);
    auto tri = [](const Vec3q& a, const Vec3q& b, const Vec3q& cc) {
        const Q num = fabsq(DotQ(a, CrossQ(b, cc)));
        const Q la = LenQ(a), lb = LenQ(b), lc = LenQ(cc);
        const Q den = la * lb * lc + DotQ(a, b) * lc + DotQ(a, cc) * lb + DotQ(b, cc) * la;
        return 2 * atan2q(num, den);
    };
    if (DotQ(c[0], CrossQ(c[1], c[2])) == 0) return 0;  // o in the light's plane (or a zero edge)
    return double(tri(c[0], c[1], c[2]) + tri(c[0], c[2], c[3]));
}

// Irradiance at o (normal n) from the light at unit radiance, E = int cos+ dw, by
// Lambert's contour formula E = 1/2 sum_i angle(v_i, v_i+1) n . normalize(v_i x v_i+1)
// (polygon entirely above the horizon of n; the tests choose such setups).  The form
// factor is E / pi.
template <class T>
inline double ReferenceIrradiance(const Vec3<T>& o, const Vec3d& n, const RectLight<T>& L) {
    Vec3q c[4];
    CornersQ(o, L, c);
    const Vec3q nq = ToQ(n.x, n.y, n.z);
    Q sum = 0;
    for (int i = 0; i < 4; ++i) {
        const Vec3q& a = c[i];
        const Vec3q& b = c[(i + 1) % 4];
        const Vec3q cr = CrossQ(a, b);
        const Q angle = atan2q(LenQ(cr), DotQ(a, b));
        sum += angle * DotQ(nq, cr) / LenQ(cr);
    }
    return double(fabsq(sum) / 2);
}

// Projected solid angle of the light above the horizon of n (any n): the polygon clipped by
// n . w >= 0 in __float128, then Lambert's formula.  The irradiance at unit radiance.
template <class T>
inline double ReferenceProjectedSolidAngle(const Vec3<T>& o, const Vec3d& n, const RectLight<T>& L) {
    Vec3q c[4];
    CornersQ(o, L, c);
    if (DotQ(c[0], CrossQ(c[1], c[2])) == 0) return 0;  // o in the light's plane (or a zero edge)
    const Vec3q nq = ToQ(n.x, n.y, n.z);
    Vec3q poly[5];
    int m = 0;
    for (int i = 0; i < 4; ++i) {
        const Vec3q& a = c[i];
        const Vec3q& b = c[(i + 1) % 4];
        const Q za = DotQ(nq, a), zb = DotQ(nq, b);
        if (za >= 0) poly[m++] = a;
        if ((za >= 0) != (zb >= 0)) {
            const Q f = za / (za - zb);
            poly[m++] = {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z)};
        }
    }
    if (m < 3) return 0;
    Q sum = 0;
    for (int i = 0; i < m; ++i) {
        const Vec3q& a = poly[i];
        const Vec3q& b = poly[(i + 1) % m];
        const Vec3q cr = CrossQ(a, b);
        const Q len = LenQ(cr);
        if (len == 0) continue;
        sum += atan2q(len, DotQ(a, b)) * DotQ(nq, cr) / len;
    }
    return double(fabsq(sum) / (2 * LenQ(nq)));
}

// Irradiance estimate of technique K with N independent samples (uniform doubles rounded to T,
// from mt19937_64(seed)): (mean of cos / pdf, its standard error).
template <Technique K, class T>
std::pair<double, double> EstimateIrradiance(const Vec3<T>& o, const Vec3<T>& n, const RectLight<T>& L, int N,
                                             uint64_t seed) {
    const LightSampler<K, T> s(o, n, L);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0, 1);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < N; ++i) {
        const LightSample<T> ls = s.Sample({T(U(rng)), T(U(rng))});
        const double f = ls.pdf > 0 ? std::max(0.0, double(Dot(ls.dir, n))) / double(ls.pdf) : 0.0;
        sum += f;
        sum2 += f * f;
    }
    const double mean = sum / N;
    return {mean, std::sqrt(std::max(0.0, sum2 / N - mean * mean) / N)};
}

// Distance of p from the light's rectangle (in-plane and off-plane), long double.
template <class T>
inline double DistanceToLight(const Vec3<T>& p, const RectLight<T>& L) {
    using R = long double;
    const R dx = R(p.x) - R(L.corner.x), dy = R(p.y) - R(L.corner.y), dz = R(p.z) - R(L.corner.z);
    const R exx = L.ex.x, exy = L.ex.y, exz = L.ex.z, eyx = L.ey.x, eyy = L.ey.y, eyz = L.ey.z;
    const R lx2 = exx * exx + exy * exy + exz * exz, ly2 = eyx * eyx + eyy * eyy + eyz * eyz;
    R a = (dx * exx + dy * exy + dz * exz) / lx2, b = (dx * eyx + dy * eyy + dz * eyz) / ly2;
    const R ac = std::min(std::max(a, R(0)), R(1)), bc = std::min(std::max(b, R(0)), R(1));
    const R rx = dx - ac * exx - bc * eyx, ry = dy - ac * exy - bc * eyy, rz = dz - ac * exz - bc * eyz;
    return double(std::sqrt(rx * rx + ry * ry + rz * rz));
}

// The suite's 9 x 9 grid of (u, v) (core/hard_cases.h) and random_count uniform points from mt19937(seed).
inline std::vector<Point2<float>> GridAndRandomUVs(uint32_t seed, int random_count) {
    std::vector<Point2<float>> uvs;
    for (float u : HardCaseUV())
        for (float v : HardCaseUV()) uvs.push_back({u, v});
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0, 1);
    for (int i = 0; i < random_count; ++i) uvs.push_back({U(rng), U(rng)});
    return uvs;
}

// ---------------------------------------------------------------- switches

// Bisection (in log space) of the parameter where `fallback(p)` switches.
template <class F>
std::pair<double, double> FindSwitch(double lo, double hi, F fallback) {
    EXPECT_NE(fallback(lo), fallback(hi));
    for (int i = 0; i < 60 && hi / lo > 1 + 1e-4; ++i) {
        const double mid = std::sqrt(lo * hi);
        (fallback(mid) == fallback(lo) ? lo : hi) = mid;
    }
    return {lo, hi};
}

// At the shading points just below and above a switch, the technique estimates the
// closed-form irradiance without bias.
template <Technique K>
void ExpectUnbiasedAcross(const char* what, const Vec3f& o_lo, const Vec3f& o_hi, const Vec3f& n,
                          const RectLight<float>& L) {
    for (const Vec3f& o : {o_lo, o_hi}) {
        const double ref = ReferenceIrradiance(o, Vec3d(n), L);
        const auto [mean, se] = EstimateIrradiance<K, float>(o, n, L, 200000, 5);
        std::printf("%s %s: o = (%.9g %.9g %.9g) E = %.9g estimate %.9g +- %.3g\n", what, TechniqueName(K), o.x, o.y,
                    o.z, ref, mean, se);
        // 4 standard errors: false-failure probability ~6e-5 per check (normal approx.).
        EXPECT_LE(std::abs(mean - ref), 4 * se + 1e-6 * ref) << what << " " << TechniqueName(K);
    }
}

}  // namespace sphrect_test
