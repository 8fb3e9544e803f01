// The lobes beyond Principled (render/bsdf.h): Glass and Glossy BSDF, Translucent, and Mix / Add Shader
// materials holding several of them.  For each: sampling against its pdf over the whole sphere (Pearson
// chi-square, so the translucent lobe's lower hemisphere is checked too), the sampling estimate of the
// albedo against quadrature, reciprocity, and a Translucent's closed form.
// Statistical checks use fixed seeds; each chi-square bound is the 1 - 1e-6 quantile, each mean a 6-sigma
// bound: false-failure rate < 2e-5 for the file (14 chi-square tests, 7 means).
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

struct NamedMaterial {
    std::string name;
    Material m;
};

Material Mix(std::initializer_list<std::pair<Material, float>> parts) {
    Material mix = MakeDiffuseMaterial({});
    for (const auto& [part, weight] : parts) MixIntoMaterial(mix, part, weight);
    return mix;
}

std::vector<NamedMaterial> Materials() {
    PrincipledInputs principled;
    principled.base_color = {0.7f, 0.4f, 0.2f};
    principled.roughness = 0.4f;
    principled.clearcoat = 0.5f;
    principled.clearcoat_roughness = 0.3f;  // the default 0.03 is too sharp for the cells' midpoint integration
    return {
        {"glass r=0.2 ior=1.5", MakeGlassMaterial({1, 1, 1}, 0.2f, 1.5f)},
        {"glass beckmann r=0.5", MakeGlassMaterial({0.9f, 0.9f, 1}, 0.5f, 1.45f, true)},
        {"glossy r=0.3", MakeGlossyBsdfMaterial({0.8f, 0.8f, 0.8f}, 0.3f)},
        {"translucent", MakeTranslucentMaterial({0.6f, 0.8f, 0.5f})},
        {"diffuse + glossy", Mix({{MakeDiffuseMaterial({0.5f, 0.5f, 0.5f}), 0.6f},
                                  {MakeGlossyBsdfMaterial({1, 1, 1}, 0.25f), 0.4f}})},
        {"principled + glass + translucent", Mix({{MakePrincipledMaterial(principled), 0.5f},
                                                  {MakeGlassMaterial({1, 1, 1}, 0.3f, 1.5f), 0.3f},
                                                  {MakeTranslucentMaterial({0.9f, 0.9f, 0.9f}), 0.2f}})},
        {"two glossy + translucent + diffuse", Mix({{MakeGlossyBsdfMaterial({1, 1, 1}, 0.2f), 0.3f},
                                                    {MakeGlossyBsdfMaterial({1, 0.5f, 0.5f}, 0.6f), 0.3f},
                                                    {MakeTranslucentMaterial({0.5f, 0.5f, 0.5f}), 0.2f},
                                                    {MakeDiffuseMaterial({0.3f, 0.6f, 0.3f}), 0.2f}})},
    };
}

TEST(BsdfLobes, SamplingMatchesThePdfOverTheSphereChiSquare) {
    // Over the whole sphere (bsdf_chi_square.h), so the translucent lobe's lower hemisphere is binned too.
    PCG32 rng(77);
    for (const NamedMaterial& c : Materials()) {
        for (float co : {0.8f, 0.25f}) {
            const ChiSquare chi2 = BsdfSamplingChiSquare(c.m, SphericalDirection(co, 0.7f), rng, -1, 48, 48, 8, 400000);
            ASSERT_GT(chi2.cells, 20) << c.name;
            EXPECT_LT(chi2.statistic, ChiSquareQuantile(chi2.cells - 1, 4.753))
                << c.name << " cos_o " << co << ", " << chi2.cells << " cells";
        }
    }
}

TEST(BsdfLobes, SamplingEstimatesTheAlbedoOverTheSphere) {
    PCG32 rng(19);
    for (const NamedMaterial& c : Materials()) {
        const Vec3f wo = SphericalDirection(0.6f, 1.0f);
        const double reference =
            IntegrateSphere([&](const Vec3f& wi) { return EvalBsdf<true>(c.m, wo, wi).y * std::abs(wi.z); }, 600, 600);
        const int n = 200000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
            const BsdfSample s = SampleBsdf<true>(c.m, wo, {rng.NextFloat(), rng.NextFloat()});
            const double x = s.pdf > 0 ? s.f.y * std::abs(s.wi.z) / s.pdf : 0.0;
            sum += x;
            sum2 += x * x;
        }
        const double mean = sum / n, sigma = std::sqrt((sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, reference, 6 * sigma + 0.003 * reference) << c.name;
    }
}

TEST(BsdfLobes, TranslucentIsLambertianTransmissionAndConservesEnergy) {
    const Spectrum color{0.6f, 0.8f, 0.5f};
    const Material m = MakeTranslucentMaterial(color);
    const Vec3f wo = SphericalDirection(0.4f, 0.3f);
    // Nothing reflected; colour / pi transmitted; the transmitted albedo is the colour.
    EXPECT_EQ(EvalBsdf<true>(m, wo, SphericalDirection(0.5f, 1.0f)).y, 0.0f);
    EXPECT_FLOAT_EQ(EvalBsdf<true>(m, wo, SphericalDirection(-0.5f, 1.0f)).y, color.y / kPi);
    const double albedo = IntegrateSphere([&](const Vec3f& wi) { return EvalBsdf<true>(m, wo, wi).y * std::abs(wi.z); });
    EXPECT_NEAR(albedo, color.y, 2e-3);
    // Not for the diffuse kernel: kGlossy = false never sees it (a translucent material is 'glossy').
    EXPECT_TRUE(m.glossy);
}

TEST(BsdfLobes, MixesAreReciprocal) {
    for (const NamedMaterial& c : Materials()) {
        if (c.name.find("translucent") != std::string::npos) continue;  // wo below is not evaluated: one-sided
        for (float a : {0.9f, 0.5f, 0.2f})
            for (float b : {0.8f, 0.3f}) {
                const Vec3f wo = SphericalDirection(a, 0.4f), wi = SphericalDirection(b, 2.1f);
                const Spectrum f = EvalBsdf<true>(c.m, wo, wi), g = EvalBsdf<true>(c.m, wi, wo);
                // Glass: its Fresnel is of the view (Cycles' zero-bounce glass), not reciprocal.
                if (c.name.find("glass") != std::string::npos) continue;
                EXPECT_NEAR(f.y, g.y, 1e-5f * (1 + f.y)) << c.name;
            }
    }
}

}  // namespace
}  // namespace sphrect::render
