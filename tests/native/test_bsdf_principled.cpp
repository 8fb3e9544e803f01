// The Principled BSDF (Cycles 3.4, render/bsdf/make_bsdf.h MakePrincipledBsdf): its lobes against
// independent forms of Cycles' formulas, reciprocity, energy (white-furnace style) per lobe, and
// its sampling against its pdf (Pearson chi-square per lobe and for all lobes together).
// Statistical checks use fixed seeds; each chi-square bound is the 1 - 1e-6 quantile, each mean a
// 6-sigma bound: false-failure rate < 2e-5 for the file (16 chi-square tests).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/rng.h"
#include "bsdf_chi_square.h"
#include "direction_quadrature.h"
#include "render/bsdf.h"

namespace sphrect::render {
namespace {

struct NamedInputs {
    std::string name;
    PrincipledInputs in;
};

PrincipledInputs With(float metallic, float specular, float roughness, float sheen = 0, float clearcoat = 0,
                      float clearcoat_roughness = 0.3f, float specular_tint = 0, Spectrum base = {0.8f, 0.5f, 0.3f}) {
    PrincipledInputs in;
    in.base_color = base;
    in.metallic = metallic;
    in.specular = specular;
    in.roughness = roughness;
    in.sheen = sheen;
    in.clearcoat = clearcoat;
    in.clearcoat_roughness = clearcoat_roughness;
    in.specular_tint = specular_tint;
    return in;
}

// Each lobe alone (diffuse: specular 0; specular: metallic 1; sheen on a black base is still made,
// its tint from a black base is white) and all together.
std::vector<NamedInputs> Lobes() {
    return {{"diffuse r=1", With(0, 0, 1)},
            {"diffuse r=0.2", With(0, 0, 0.2f)},
            {"specular metal r=0.3", With(1, 0.5f, 0.3f)},
            {"specular metal r=0.8", With(1, 0.5f, 0.8f)},
            {"sheen", With(0, 0, 0.5f, 1, 0, 0.3f, 0, {0, 0, 0})},
            {"clearcoat r=0.3 on black", With(0, 0, 0.5f, 0, 1, 0.3f, 0, {0, 0, 0})},
            {"clearcoat r=0.8 on black", With(0, 0, 0.5f, 0, 1, 0.8f, 0, {0, 0, 0})},
            {"all", With(0.3f, 0.8f, 0.4f, 0.7f, 0.6f, 0.25f, 0.5f)}};
}

TEST(PrincipledBsdf, BurleyDiffuseIsThe2012FormWithFd90) {
    // Cycles 3.4 splits Burley's (1 + (Fd90 - 1) FL)(1 + (Fd90 - 1) FV), Fd90 = 0.5 + 2 r (wi.h)^2,
    // into a Lambert-like part and a retro-reflection; the sum is the same function.
    for (float r : {0.0f, 0.3f, 1.0f})
        for (float co : {0.1f, 0.5f, 0.95f})
            for (float ci : {0.05f, 0.4f, 0.9f}) {
                const Vec3f wo = SphericalDirection(co, 0.2f), wi = SphericalDirection(ci, 2.5f);
                const Vec3f h = Normalize(wo + wi);
                const float fd90 = 0.5f + 2 * r * Dot(wi, h) * Dot(wi, h);
                const float fl = std::pow(1 - ci, 5.0f), fv = std::pow(1 - co, 5.0f);
                const float reference = (1 + (fd90 - 1) * fl) * (1 + (fd90 - 1) * fv) / kPi;
                EXPECT_NEAR(BurleyDiffuse(wo, wi, r), reference, 2e-6f);
            }
}

TEST(PrincipledBsdf, MaterialHasCyclesWeights) {
    // Roughness 1, specular 0: the diffuse alone; at normal view and light FL = FV = 0, so f = base / pi.
    const Bsdf d = MakePrincipledBsdf(With(0, 0, 1));
    EXPECT_FALSE(d.has_specular || d.has_sheen || d.has_clearcoat);
    const Vec3f n{0, 0, 1};
    EXPECT_NEAR(EvalBsdf<true>(d, n, n).x, 0.8f / kPi, 1e-6f);
    // Grazing view and light, roughness 1: the retro-reflection brightens (Fd90 = 2.5 at wi = wo).
    const Vec3f g = SphericalDirection(0.0001f, 0);
    EXPECT_NEAR(EvalBsdf<true>(d, g, g).x / (0.8f / kPi), 2.5f * 2.5f, 0.01f);
    // Specular 0.5 -> IOR 1.5 (F0 = 0.04), metallic 1 -> no diffuse, cspec0 = base colour.
    const Bsdf s = MakePrincipledBsdf(With(0, 0.5f, 0.5f));
    EXPECT_NEAR(s.specular_ior, 1.5f, 1e-5f);
    EXPECT_NEAR(s.specular_f0, 0.04f, 1e-6f);
    const Bsdf metal = MakePrincipledBsdf(With(1, 0.5f, 0.5f));
    EXPECT_TRUE(IsBlack(metal.diffuse));
    EXPECT_FLOAT_EQ(metal.f0.y, 0.5f);
    // Specular tint 1: F0 = 0.08 specular x base colour / (0.3 r + 0.6 g + 0.1 b).
    const Bsdf tinted = MakePrincipledBsdf(With(0, 1, 0.5f, 0, 0, 0.3f, 1));
    EXPECT_NEAR(tinted.f0.x, 0.08f * 0.8f / (0.3f * 0.8f + 0.6f * 0.5f + 0.1f * 0.3f), 1e-6f);
    // Sheen tint 0.5 (default): sheen x (0.5 + 0.5 base / luminance) x (1 - metallic).
    const Bsdf sh = MakePrincipledBsdf(With(0.5f, 0, 0.5f, 0.8f));
    const float lum = Luminance({0.8f, 0.5f, 0.3f});
    EXPECT_NEAR(sh.sheen.z, 0.8f * 0.5f * (0.5f + 0.5f * 0.3f / lum), 1e-6f);
    EXPECT_NEAR(MakePrincipledBsdf(With(0, 0, 0.5f, 0, 0.6f)).clearcoat, 0.15f, 1e-7f);
}

TEST(PrincipledBsdf, IsReciprocal) {
    for (const NamedInputs& c : Lobes()) {
        const Bsdf m = MakePrincipledBsdf(c.in);
        for (float co : {0.2f, 0.7f})
            for (float ci : {0.1f, 0.5f, 0.9f}) {
                const Vec3f wo = SphericalDirection(co, 0.4f), wi = SphericalDirection(ci, 3.0f);
                const Spectrum a = EvalBsdf<true>(m, wo, wi), b = EvalBsdf<true>(m, wi, wo);
                EXPECT_NEAR(a.x, b.x, 1e-5f * (1 + a.x)) << c.name;
                EXPECT_NEAR(a.z, b.z, 1e-5f * (1 + a.z)) << c.name;
            }
    }
}

// Directional albedo integral f cos dwi (channel x), by importance sampling (the quadrature misses
// lobes as sharp as alpha = 0.01; the sampling is checked against the pdf below): 200k samples
// leave a relative standard error < 0.3% for these lobes.
double Albedo(const Bsdf& m, const Vec3f& wo) {
    PCG32 rng(99);
    const int n = 200000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = SampleBsdf<true>(m, wo, {rng.NextFloat(), rng.NextFloat()});
        if (s.pdf > 0) sum += s.f.x * s.wi.z / s.pdf;
    }
    return sum / n;
}

TEST(PrincipledBsdf, WhiteFurnacePerLobe) {
    const Spectrum white{1, 1, 1};
    for (float co : {0.98f, 0.6f, 0.2f}) {
        const Vec3f wo = SphericalDirection(co, 0);
        // A white metal's single-scatter GGX loses energy to the missing multiple scattering, never gains;
        // measured: 1.00 / 0.83-0.91 / 0.31-0.51 at roughness 0.1 / 0.5 / 1 (Cycles' separable G).
        for (float r : {0.1f, 0.5f, 1.0f}) {
            const double a = Albedo(MakePrincipledBsdf(With(1, 0.5f, r, 0, 0, 0.3f, 0, white)), wo);
            EXPECT_LE(a, 1.005) << "metal r " << r << " cos " << co;
            EXPECT_GT(a, r <= 0.1f ? 0.99 : (r <= 0.5f ? 0.8 : 0.3)) << "metal r " << r << " cos " << co;
        }
        // Burley at roughness 0 keeps below Lambert's 1 (the (1 - F/2) factors only darken).
        const double smooth = Albedo(MakePrincipledBsdf(With(0, 0, 0, 0, 0, 0.3f, 0, white)), wo);
        EXPECT_LE(smooth, 1.0) << co;
        EXPECT_GT(smooth, 0.75) << co;
        // Clearcoat: Fresnel of IOR 1.5 under weight 0.25: albedo within [0.25 * 0.04 * 0.5, 0.25].
        const double coat = Albedo(MakePrincipledBsdf(With(0, 0, 0.5f, 0, 1, 0.3f, 0, {0, 0, 0})), wo);
        EXPECT_LE(coat, 0.25) << co;
        EXPECT_GT(coat, 0.005) << co;
        // Sheen of weight 1 (black base: the tint is white): (1 - wi.h)^5 is large only where wi and wo are
        // nearly opposite, both grazing; albedo < 0.5.
        const double sheen = Albedo(MakePrincipledBsdf(With(0, 0, 0.5f, 1, 0, 0.3f, 0, {0, 0, 0})), wo);
        EXPECT_LE(sheen, 0.5) << co;
        EXPECT_GT(sheen, 0.0) << co;
    }
    // Burley's retro-reflection at roughness 1 adds light at grazing angles: as in Cycles its albedo
    // exceeds the smooth one there (what the 7% was).
    const Vec3f grazing = SphericalDirection(0.2f, 0);
    EXPECT_GT(Albedo(MakePrincipledBsdf(With(0, 0, 1, 0, 0, 0.3f, 0, white)), grazing),
              Albedo(MakePrincipledBsdf(With(0, 0, 0, 0, 0, 0.3f, 0, white)), grazing) + 0.1);
}

TEST(PrincipledBsdf, SamplesReportTheirPDFAndValue) {
    PCG32 rng(5);
    std::vector<NamedInputs> cases = Lobes();
    cases.push_back({"sharp clearcoat (Blender's default 0.03)", With(0, 0.5f, 0.5f, 0, 1, 0.03f)});
    for (const NamedInputs& c : cases) {
        const Bsdf m = MakePrincipledBsdf(c.in);
        for (float co : {0.9f, 0.4f, 0.1f}) {
            const Vec3f wo = SphericalDirection(co, 0.3f);
            for (int i = 0; i < 5000; ++i) {
                const BsdfSample s = SampleBsdf<true>(m, wo, {rng.NextFloat(), rng.NextFloat()});
                if (s.pdf == 0) continue;
                ASSERT_GT(s.wi.z, 0) << c.name;
                EXPECT_NEAR(s.pdf, BsdfPDF<true>(m, wo, s.wi), 1e-3f * s.pdf) << c.name;
                const Spectrum f = EvalBsdf<true>(m, wo, s.wi);
                EXPECT_NEAR(s.f.y, f.y, 1e-4f * (1 + f.y)) << c.name;
            }
        }
    }
}

TEST(PrincipledBsdf, SamplingMatchesThePDFChiSquare) {
    // Over the upper hemisphere (bsdf_chi_square.h); rejected samples (reflected below the horizon) are the
    // pdf's missing mass.
    PCG32 rng(2024);
    for (const NamedInputs& c : Lobes()) {
        const Bsdf m = MakePrincipledBsdf(c.in);
        for (float co : {0.85f, 0.3f}) {
            const ChiSquare chi2 = BsdfSamplingChiSquare(m, SphericalDirection(co, 0.7f), rng, 0, 24, 48, 8, 400000);
            ASSERT_GT(chi2.cells, 20) << c.name;
            EXPECT_LT(chi2.statistic, ChiSquareQuantile(chi2.cells - 1, 4.753))
                << c.name << " cos_o " << co << ", " << chi2.cells << " cells";
        }
    }
}

TEST(PrincipledBsdf, SamplingEstimatesTheAlbedo) {
    PCG32 rng(17);
    for (const NamedInputs& c : Lobes()) {
        const Bsdf m = MakePrincipledBsdf(c.in);
        const Vec3f wo = SphericalDirection(0.6f, 1.0f);
        const double reference =
            IntegrateHemisphere([&](const Vec3f& wi) { return EvalBsdf<true>(m, wo, wi).y * wi.z; });
        const int n = 200000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
            const BsdfSample s = SampleBsdf<true>(m, wo, {rng.NextFloat(), rng.NextFloat()});
            const double x = s.pdf > 0 ? s.f.y * s.wi.z / s.pdf : 0.0;
            sum += x;
            sum2 += x * x;
        }
        const double mean = sum / n, sigma = std::sqrt((sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, reference, 6 * sigma + 0.003 * reference) << c.name;
    }
}

}  // namespace
}  // namespace sphrect::render
