// Pearson chi-square of a sampler against its pdf: a direction sampler -- a material's BSDF sampling (the BSDF tests),
// the uniform cone (test_cone.cpp) -- samples binned on
// a (cos theta, phi) grid over cos theta in [cos_lo, 1] against the pdf integrated over each cell (sub x sub
// midpoint points); cells expecting < 5 pooled (Pearson's rule), and samples without a direction (pdf 0) are
// the pdf's missing mass, pooled too; and a sampler of a distance on an interval (IntervalSamplingChiSquare: the
// medium's distance sampling, test_medium_stretches.cpp), binned likewise.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "direction_quadrature.h"
#include "render/bsdf.h"

namespace sphrect::render {

struct ChiSquare {
    double statistic = 0;
    int cells = 0;
};

// Wilson-Hilferty approximation of the chi-square quantile for k degrees of freedom at normal score z.
inline double ChiSquareQuantile(int k, double z) {
    const double a = 2.0 / (9.0 * k);
    return k * std::pow(1 - a + z * std::sqrt(a), 3);
}

// Pearson's statistic of observed against expected counts, cells expecting < 5 pooled with the missing mass
// (expected `missing`, observed `rejected`: samples without a value).
inline ChiSquare PooledPearson(const std::vector<double>& expected, const std::vector<double>& observed, double missing,
                               double rejected) {
    ChiSquare r;
    double pool_e = std::max(0.0, missing), pool_o = rejected;
    for (size_t k = 0; k < expected.size(); ++k) {
        if (expected[k] < 5) {
            pool_e += expected[k];
            pool_o += observed[k];
            continue;
        }
        r.statistic += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
        ++r.cells;
    }
    if (pool_e >= 5) {
        r.statistic += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        ++r.cells;
    }
    return r;
}

// Any direction sampler: pdf(wi) its solid-angle density, sample(u, &wi) false for a sample without a direction.
template <class PDF, class Sample>
inline ChiSquare DirectionSamplingChiSquare(PDF&& pdf, Sample&& sample, PCG32& rng, float cos_lo, int n_theta,
                                            int n_phi, int sub, int samples) {
    std::vector<double> expected(size_t(n_theta) * n_phi, 0.0), observed(expected.size(), 0.0);
    const float cos_range = 1 - cos_lo;
    double expected_total = 0;
    for (int i = 0; i < n_theta; ++i)
        for (int j = 0; j < n_phi; ++j) {
            double sum = 0;
            for (int a = 0; a < sub; ++a)
                for (int b = 0; b < sub; ++b) {
                    const float ct = cos_lo + cos_range * (i + (a + 0.5f) / sub) / n_theta;
                    const float phi = 2 * kPi * (j + (b + 0.5f) / sub) / n_phi;
                    sum += pdf(SphericalDirection(ct, phi));
                }
            const double cell_area = 2 * M_PI * cos_range / (double(n_theta) * n_phi);
            expected[size_t(i) * n_phi + j] = sum / (sub * sub) * cell_area * samples;
            expected_total += expected[size_t(i) * n_phi + j];
        }
    double rejected = 0;
    for (int n = 0; n < samples; ++n) {
        Vec3f wi;
        if (!sample(Point2<float>{rng.NextFloat(), rng.NextFloat()}, &wi)) {
            ++rejected;
            continue;
        }
        const int i = std::clamp(int((wi.z - cos_lo) / cos_range * n_theta), 0, n_theta - 1);
        float phi = std::atan2(wi.y, wi.x);
        if (phi < 0) phi += 2 * kPi;
        const int j = std::min(int(phi / (2 * kPi) * n_phi), n_phi - 1);
        observed[size_t(i) * n_phi + j] += 1;
    }
    return PooledPearson(expected, observed, samples - expected_total, rejected);
}

// Any sampler of a distance on [edges.front(), edges.back()): pdf(t) its density, sample(u, &t) false for no sample
// (the pdf's missing mass); each bin's expected count by the midpoint rule on `sub` points.
template <class PDF, class Sample>
inline ChiSquare IntervalSamplingChiSquare(PDF&& pdf, Sample&& sample, PCG32& rng, const std::vector<double>& edges,
                                           int sub, int samples) {
    const size_t bins = edges.size() - 1;
    std::vector<double> expected(bins, 0.0), observed(bins, 0.0);
    double expected_total = 0;
    for (size_t k = 0; k < bins; ++k) {
        const double h = (edges[k + 1] - edges[k]) / sub;
        for (int a = 0; a < sub; ++a) expected[k] += pdf(float(edges[k] + (a + 0.5) * h)) * h;
        expected[k] *= samples;
        expected_total += expected[k];
    }
    double rejected = 0;
    for (int n = 0; n < samples; ++n) {
        float t;
        if (!sample(rng.NextFloat(), &t)) {
            ++rejected;
            continue;
        }
        const size_t k = size_t(std::upper_bound(edges.begin(), edges.end(), double(t)) - edges.begin());
        observed[std::clamp<size_t>(k, 1, bins) - 1] += 1;
    }
    return PooledPearson(expected, observed, samples - expected_total, rejected);
}

inline ChiSquare BsdfSamplingChiSquare(const Bsdf& m, const Vec3f& wo, PCG32& rng, float cos_lo, int n_theta, int n_phi,
                                       int sub, int samples) {
    return DirectionSamplingChiSquare([&](const Vec3f& wi) { return BsdfPDF<true>(m, wo, wi); },
                                      [&](Point2<float> u, Vec3f* wi) {
                                          const BsdfSample s = SampleBsdf<true>(m, wo, u);
                                          *wi = s.wi;
                                          return s.pdf != 0;
                                      },
                                      rng, cos_lo, n_theta, n_phi, sub, samples);
}

}  // namespace sphrect::render
