// Shared helpers of the C++ sampling tests: the hard-case suite, high-precision
// references (solid angle, irradiance), the chi-square machinery.
#pragma once

#include <quadmath.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

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

// Distance of p from the light's rectangle (in-plane and off-plane), long double.
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

// ---------------------------------------------------------------- the hard-case suite

struct HardCase {
    std::string name;
    RectLight<float> light;  // near the world origin (see below)
    Vec3f origin;
    Vec3f normal;            // a shading normal facing the light (for rectangle_cosine)
    double size;             // the light's larger edge
};

// All cases keep the light near the world origin and move the shading point: with
// float world coordinates, a light 1e6 sizes from the world origin cannot even be
// represented to 1e-5 of its size, so "far" is only meaningful relative to o.
// Coordinates are built in double and rounded to float; the references use the
// rounded values, so every case is exactly the configuration the code sees.
inline std::vector<HardCase> HardCaseSuite() {
    std::vector<HardCase> cases;
    struct LightDef {
        std::string name;
        Vec3d center, ex, ey;
    };
    const double s2 = std::sqrt(0.5);
    // A rotated light: edges along (1,1,0)/sqrt2 and (-1,1,1)/sqrt3 scaled (orthogonal to rounding).
    const Vec3d rx = Vec3d(s2, s2, 0), ry = Normalize(Vec3d(-1, 1, 1));
    const std::vector<LightDef> lights = {
        {"unit", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
        {"rotated", {0.3, -0.2, 0.7}, rx * 0.8, ry * 1.3},
        {"aspect1e3", {0, 0, 0}, {1, 0, 0}, {0, 1e-3, 0}},
        {"aspect1e5", {0, 0, 0}, {0, 1e-5, 0}, {1, 0, 0}},
        {"small", {0.25, 0.5, -0.125}, {1e-3, 0, 0}, {0, 0, 2e-3}},
    };
    for (const LightDef& ld : lights) {
        const Vec3d n = Normalize(Cross(ld.ex, ld.ey));
        const double lx = Length(ld.ex), ly = Length(ld.ey), size = std::max(lx, ly);
        RectLight<float> L{Vec3f(ld.center - ld.ex * 0.5 - ld.ey * 0.5), Vec3f(ld.ex), Vec3f(ld.ey), true};
        const Vec3d xh = ld.ex / lx, yh = ld.ey / ly;
        // (a, b): position in light fractions, z: height in sizes (negative: the other side).
        auto add = [&](const std::string& what, double a, double b, double z) {
            const Vec3d o = ld.center + ld.ex * (a - 0.5) + ld.ey * (b - 0.5) + n * (z * size);
            const Vec3d toward = Normalize(ld.center - o);
            cases.push_back({ld.name + "/" + what, L, Vec3f(o), Vec3f(toward), size});
        };
        for (double d : {1e-6, 1e-3, 1.0, 1e3, 1e6}) {
            add("above_center_d" + std::to_string(d), 0.5, 0.5, d);
            add("below_center_d" + std::to_string(d), 0.5, 0.5, -d);
            const double off = d * size / std::sqrt(3.0);  // diagonal direction, distance d sizes
            const Vec3d o = ld.center + (xh + yh + n) * off;
            cases.push_back({ld.name + "/diagonal_d" + std::to_string(d), L, Vec3f(o),
                             Vec3f(Normalize(ld.center - o)), size});
            add("side_d" + std::to_string(d), 0.5 + d * size / lx, 0.5, 1e-3);
        }
        for (double hgt : {1e-9, 1e-7, 1e-5, 1e-3, 1e-1}) {
            const std::string hs = std::to_string(std::log10(hgt)).substr(0, 3);
            add("interior_h1e" + hs, 0.3, 0.6, hgt);
            add("center_h1e" + hs, 0.5, 0.5, hgt);
            add("edge_h1e" + hs, 1.0, 0.4, hgt);
            add("corner_h1e" + hs, 0.0, 1.0, hgt);
            add("beside_h1e" + hs, 0.5 + 2 * size / lx, 0.5, hgt);
            add("beside_diag_h1e" + hs, 1 + size / lx, 1 + size / ly, hgt);
            add("near_edge_h1e" + hs, 1 + 1e-4, 0.5, hgt);
        }
    }
    return cases;
}

// (u, v) values of the suite: 0, the largest float below 1, 1, and a few interior ones.
inline std::vector<float> EdgeUV() {
    return {0.f, std::nextafter(1.f, 0.f), 1.f, 0.5f, 1e-7f, 0.25f, 0.9f};
}

// ---------------------------------------------------------------- chi-square

// Regularized upper incomplete gamma Q(a, x) (series / continued fraction).
inline double GammaQ(double a, double x) {
    if (x <= 0) return 1;
    const double lg = std::lgamma(a);
    if (x < a + 1) {
        double sum = 1 / a, term = sum;
        for (int n = 1; n < 100000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return 1 - sum * std::exp(-x + a * std::log(x) - lg);
    }
    double b = x + 1 - a, c = 1 / 1e-300, d = 1 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (std::abs(c) < 1e-300) c = 1e-300;
        d = 1 / d;
        const double del = d * c;
        h *= del;
        if (std::abs(del - 1) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - lg) * h;
}

// Adaptive 2D Gauss-Legendre (5x5 nodes) of f over [a0,a1] x [b0,b1]: a cell is
// split into four until the children agree with the parent to `rel` of `scale`.
inline double GL5(const std::function<double(double, double)>& f, double a0, double a1, double b0, double b1) {
    static const double x[5] = {-0.9061798459386640, -0.5384693101056831, 0, 0.5384693101056831,
                                0.9061798459386640};
    static const double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                                0.2369268850561891};
    const double ca = (a0 + a1) / 2, ha = (a1 - a0) / 2, cb = (b0 + b1) / 2, hb = (b1 - b0) / 2;
    double s = 0;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) s += w[i] * w[j] * f(ca + ha * x[i], cb + hb * x[j]);
    return s * ha * hb;
}
inline double AdaptiveIntegrate(const std::function<double(double, double)>& f, double a0, double a1, double b0,
                                double b1, double abs_tol, double whole, int depth = 0) {
    const double am = (a0 + a1) / 2, bm = (b0 + b1) / 2;
    const double k[4] = {GL5(f, a0, am, b0, bm), GL5(f, am, a1, b0, bm), GL5(f, a0, am, bm, b1),
                         GL5(f, am, a1, bm, b1)};
    const double kids = k[0] + k[1] + k[2] + k[3];
    if (depth >= 40 || std::abs(kids - whole) <= abs_tol) return kids;
    return AdaptiveIntegrate(f, a0, am, b0, bm, abs_tol / 2, k[0], depth + 1) +
           AdaptiveIntegrate(f, am, a1, b0, bm, abs_tol / 2, k[1], depth + 1) +
           AdaptiveIntegrate(f, a0, am, bm, b1, abs_tol / 2, k[2], depth + 1) +
           AdaptiveIntegrate(f, am, a1, bm, b1, abs_tol / 2, k[3], depth + 1);
}

struct Chi2Result {
    double p_value = 0;
    double total_expected = 0;  // sum of expected counts / N: the pdf's integral over the light (should be 1)
    int bins = 0;
    int invalid_samples = 0;
    double statistic = 0;
};

// Chi-square goodness of fit of a technique against its own pdf: cells form an
// na x nb grid of the light's fractions (a, b) (point = corner + a ex + b ey); the
// expected count of a cell is N times the integral of the pdf over the cell, in
// solid angle: pdf(p) h / |p - o|^3 dA, by adaptive Gauss-Legendre.  Cells with an
// expectation below 5 are pooled into one bin.
// `sampler`: anything with Sample(Point2<T>) and Pdf(point) for the light, set up at `origin`.
template <class T, class Sampler>
Chi2Result Chi2Sampler(const Sampler& sampler, const Vec3<T>& origin, const RectLight<T>& light, int n_samples,
                       uint64_t seed, int na = 16, int nb = 16) {
    Chi2Result res;
    const Vec3d c(light.corner), ex(light.ex), ey(light.ey), o(origin);
    const double lx2 = Dot(ex, ex), ly2 = Dot(ey, ey);
    const Vec3d n = Normalize(Cross(ex, ey));
    const double h = std::abs(Dot(c - o, n));
    std::vector<double> observed(na * nb, 0.0), expected(na * nb, 0.0);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0, 1);
    for (int i = 0; i < n_samples; ++i) {
        const Point2<T> uv{T(U(rng)), T(U(rng))};
        const LightSample<T> s = sampler.Sample(uv);
        if (!(s.pdf > 0)) { ++res.invalid_samples; continue; }
        const Vec3d q = Vec3d(s.point) - c;
        const int ia = std::min(na - 1, std::max(0, int(Dot(q, ex) / lx2 * na)));
        const int ib = std::min(nb - 1, std::max(0, int(Dot(q, ey) / ly2 * nb)));
        observed[ia + na * ib] += 1;
    }
    // pdf in area measure at the light fractions (a, b).  The point goes through T
    // like the renderer's hit points; the geometric factor is computed in double
    // from the local coordinates (exact for o near the plane).
    const Vec3d xh = ex / std::sqrt(lx2), yh = ey / std::sqrt(ly2);
    const double X0 = Dot(c - o, xh), Y0 = Dot(c - o, yh), area = std::sqrt(lx2 * ly2);
    auto area_pdf = [&](double a, double b) {
        const Vec3<T> p(c + ex * a + ey * b);
        const double X = X0 + a * std::sqrt(lx2), Y = Y0 + b * std::sqrt(ly2);
        const double d2 = X * X + Y * Y + h * h;
        return double(sampler.Pdf(p)) * h / (d2 * std::sqrt(d2)) * area;  // dA = area da db
    };
    for (int ib = 0; ib < nb; ++ib)
        for (int ia = 0; ia < na; ++ia) {
            const double a0 = double(ia) / na, a1 = double(ia + 1) / na, b0 = double(ib) / nb, b1 = double(ib + 1) / nb;
            const double whole = GL5(area_pdf, a0, a1, b0, b1);
            expected[ia + na * ib] =
                AdaptiveIntegrate(area_pdf, a0, a1, b0, b1, 1e-5 / (na * nb), whole) * n_samples;
        }
    double pooled_obs = 0, pooled_exp = 0, chi2 = 0;
    int bins = 0;
    for (int i = 0; i < na * nb; ++i) {
        res.total_expected += expected[i] / n_samples;
        if (expected[i] < 5) {
            pooled_obs += observed[i];
            pooled_exp += expected[i];
            continue;
        }
        chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++bins;
    }
    if (pooled_exp >= 5) {
        chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        ++bins;
    } else if (pooled_obs > 20) {
        chi2 += 1e9;  // many samples where the pdf says almost none can land
    }
    res.bins = bins;
    res.statistic = chi2;
    res.p_value = bins > 1 ? GammaQ((bins - 1) / 2.0, chi2 / 2) : 1;
    return res;
}

template <Technique K, class T>
Chi2Result Chi2Technique(const Vec3<T>& origin, const Vec3<T>& normal, const RectLight<T>& light, int n_samples,
                         uint64_t seed, int na = 16, int nb = 16) {
    return Chi2Sampler(LightSampler<K, T>(origin, normal, light), origin, light, n_samples, seed, na, nb);
}

}  // namespace sphrect_test
