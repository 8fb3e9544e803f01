// The lobes beyond Principled (render/bsdf.h): Glass, Glossy and Anisotropic BSDF, Principled Anisotropic,
// Translucent, and Mix / Add Shader materials holding several of them.  For each: sampling against its pdf over the
// whole sphere (Pearson chi-square, so the translucent lobe's lower hemisphere is checked too), the sampling estimate
// of the albedo against quadrature, reciprocity, and a Translucent's closed form. Statistical checks use fixed seeds;
// each chi-square bound is the 1 - 1e-6 quantile, each mean a 6-sigma bound: false-failure rate < 3e-5 for the file (20
// chi-square tests, 10 means).
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
    Bsdf m;
};

Bsdf Mix(std::initializer_list<std::pair<Bsdf, float>> parts) {
    Bsdf mix = MakeDiffuseBsdf({});
    for (const auto& [part, weight] : parts) MixIntoBsdf(mix, part, weight);
    return mix;
}

// An anisotropic material with the hit's tangent at `angle` radians in the shading frame (SetHitTangent).
Bsdf WithTangent(Bsdf m, float angle) {
    SetHitTangent(m, {std::cos(angle), std::sin(angle), 0});
    return m;
}

PrincipledInputs AnisotropicPrincipled() {
    PrincipledInputs p;
    p.base_color = {0.8f, 0.6f, 0.3f};
    p.metallic = 0.7f;
    p.roughness = 0.35f;
    p.anisotropic = 0.8f;
    p.anisotropic_rotation = 0.1f;
    return p;
}

std::vector<NamedMaterial> Materials() {
    PrincipledInputs principled;
    principled.base_color = {0.7f, 0.4f, 0.2f};
    principled.roughness = 0.4f;
    principled.clearcoat = 0.5f;
    principled.clearcoat_roughness = 0.3f;  // the default 0.03 is too sharp for the cells' midpoint integration
    return {
        {"glass r=0.2 ior=1.5", MakeGlassBsdf({1, 1, 1}, 0.2f, 1.5f)},
        {"glass beckmann r=0.5", MakeGlassBsdf({0.9f, 0.9f, 1}, 0.5f, 1.45f, true)},
        {"glossy r=0.3", MakeGlossyBsdf({0.8f, 0.8f, 0.8f}, 0.3f)},
        {"translucent", MakeTranslucentBsdf({0.6f, 0.8f, 0.5f})},
        {"diffuse + glossy",
         Mix({{MakeDiffuseBsdf({0.5f, 0.5f, 0.5f}), 0.6f}, {MakeGlossyBsdf({1, 1, 1}, 0.25f), 0.4f}})},
        {"principled + glass + translucent", Mix({{MakePrincipledBsdf(principled), 0.5f},
                                                  {MakeGlassBsdf({1, 1, 1}, 0.3f, 1.5f), 0.3f},
                                                  {MakeTranslucentBsdf({0.9f, 0.9f, 0.9f}), 0.2f}})},
        {"anisotropic glossy a=0.6", WithTangent(MakeGlossyBsdf({0.9f, 0.9f, 0.9f}, 0.4f, false, 0.6f, 0.15f), 0.5f)},
        {"principled anisotropic 0.8", WithTangent(MakePrincipledBsdf(AnisotropicPrincipled()), -1.0f)},
        {"diffuse + anisotropic glossy a=-0.5",
         WithTangent(
             Mix({{MakeDiffuseBsdf({0.4f, 0.4f, 0.4f}), 0.5f}, {MakeGlossyBsdf({1, 1, 1}, 0.3f, false, -0.5f), 0.5f}}),
             2.0f)},
        {"two glossy + translucent + diffuse", Mix({{MakeGlossyBsdf({1, 1, 1}, 0.2f), 0.3f},
                                                    {MakeGlossyBsdf({1, 0.5f, 0.5f}, 0.6f), 0.3f},
                                                    {MakeTranslucentBsdf({0.5f, 0.5f, 0.5f}), 0.2f},
                                                    {MakeDiffuseBsdf({0.3f, 0.6f, 0.3f}), 0.2f}})},
    };
}

TEST(BsdfLobes, SamplingMatchesThePDFOverTheSphereChiSquare) {
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
    const Bsdf m = MakeTranslucentBsdf(color);
    const Vec3f wo = SphericalDirection(0.4f, 0.3f);
    // Nothing reflected; colour / pi transmitted; the transmitted albedo is the colour.
    EXPECT_EQ(EvalBsdf<true>(m, wo, SphericalDirection(0.5f, 1.0f)).y, 0.0f);
    EXPECT_FLOAT_EQ(EvalBsdf<true>(m, wo, SphericalDirection(-0.5f, 1.0f)).y, color.y / kPi);
    const double albedo =
        IntegrateSphere([&](const Vec3f& wi) { return EvalBsdf<true>(m, wo, wi).y * std::abs(wi.z); });
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

TEST(BsdfLobes, AnisotropicGgxDistributionIsNormalised) {
    // Integral of D(h) cos(theta_h) over the hemisphere of normals is 1 (Walter et al. 2007, eq. 4).
    for (auto [ax, ay] : {std::pair{0.3f, 0.3f}, {0.2f, 0.6f}, {0.9f, 0.25f}}) {
        const double integral = IntegrateSphere(
            [&](const Vec3f& h) { return h.z > 0 ? GgxAnisotropicD(h, ax, ay) * h.z : 0.0f; }, 800, 800);
        EXPECT_NEAR(integral, 1.0, 3e-3) << ax << " " << ay;
    }
}

TEST(BsdfLobes, AnisotropicGgxReducesToIsotropicAndTurnsWithItsTangent) {
    const Vec3f wo = SphericalDirection(0.7f, 0.3f), wi = SphericalDirection(0.4f, 2.4f), h = Normalize(wo + wi);
    // Equal roughnesses: the isotropic lobe, whatever the tangent.
    EXPECT_NEAR(GgxAnisotropicDG(wo, wi, h, 0.3f, 0.3f, std::cos(1.1f), std::sin(1.1f)),
                GgxD(h, 0.3f) * SmithG1Ggx(wo.z, 0.3f) * SmithG1Ggx(wi.z, 0.3f), 1e-4f);
    // A tangent turned by a quarter turn swaps the roughnesses; by half a turn changes nothing.
    const float a = GgxAnisotropicDG(wo, wi, h, 0.2f, 0.6f, std::cos(0.4f), std::sin(0.4f));
    const float quarter = GgxAnisotropicDG(wo, wi, h, 0.6f, 0.2f, std::cos(0.4f + kPi / 2), std::sin(0.4f + kPi / 2));
    const float half = GgxAnisotropicDG(wo, wi, h, 0.2f, 0.6f, std::cos(0.4f + kPi), std::sin(0.4f + kPi));
    EXPECT_NEAR(quarter, a, 1e-4f * a);
    EXPECT_NEAR(half, a, 1e-4f * a);
    // The Anisotropic BSDF's rotation input turns the lobe as its tangent does.
    const Bsdf turned = WithTangent(MakeGlossyBsdf({1, 1, 1}, 0.4f, false, 0.6f, 0.25f), 0.3f);
    const Bsdf tangent_turned = WithTangent(MakeGlossyBsdf({1, 1, 1}, 0.4f, false, 0.6f, 0.0f), 0.3f + kPi / 2);
    EXPECT_NEAR(EvalBsdf<true>(turned, wo, wi).y, EvalBsdf<true>(tangent_turned, wo, wi).y, 1e-5f);
    // Anisotropy changes the lobe (the test above can fail).
    const Bsdf iso = MakeGlossyBsdf({1, 1, 1}, 0.4f);
    EXPECT_GT(std::abs(EvalBsdf<true>(turned, wo, wi).y - EvalBsdf<true>(iso, wo, wi).y),
              0.05f * EvalBsdf<true>(iso, wo, wi).y);
}

TEST(BsdfLobes, AnisotropyFollowsCyclesRoughnessMapping) {
    // svm_node_closure_bsdf: Principled aspect = sqrt(1 - 0.9 a), alpha_x = r^2 / aspect, alpha_y = r^2 aspect;
    // Anisotropic BSDF a >= 0: alpha_x = r^2 (1 - a), alpha_y = r^2 / (1 - a).
    const Bsdf p = MakePrincipledBsdf(AnisotropicPrincipled());
    const float r2 = 0.35f * 0.35f, aspect = std::sqrt(1 - 0.9f * 0.8f);
    EXPECT_FLOAT_EQ(p.alpha, r2 / aspect);
    EXPECT_FLOAT_EQ(p.specular_alpha_y, r2 * aspect);
    EXPECT_TRUE(p.anisotropic);
    const Bsdf g = MakeGlossyBsdf({1, 1, 1}, 0.5f, false, 0.6f);
    EXPECT_FLOAT_EQ(g.lobes[0].alpha, 0.25f * 0.4f);
    EXPECT_FLOAT_EQ(g.lobes[0].alpha_y, 0.25f / 0.4f);
    EXPECT_FALSE(MakeGlossyBsdf({1, 1, 1}, 0.5f, true, 0.6f).anisotropic);  // Beckmann: isotropic
}

// Albedo of the multiple-scattering GGX with a white Fresnel (cspec0 = 1), the walk from the view or Cycles' shallower
// direction, by midpoint quadrature over the hemisphere (each direction one walk: the walk's noise averages out).
double MultiscatterAlbedo(float alpha, float cos_o, bool from_view) {
    const Vec3f wo(std::sqrt(1 - cos_o * cos_o), 0, cos_o);
    const int n = 300;
    double sum = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float z = (i + 0.5f) / n, r = std::sqrt(1 - z * z), phi = 2 * kPi * (j + 0.5f) / n;
            const Vec3f wi(r * std::cos(phi), r * std::sin(phi), z);
            sum += MultiscatterGgxEval(wo, wi, alpha, alpha, 1.5f, {1, 1, 1}, from_view).y * z;
        }
    return sum * 2 * kPi / (double(n) * n);
}

TEST(BsdfLobes, MultiscatterGgxConservesEnergyFromTheView) {
    // Heitz et al. 2016: with no absorption the microsurface reflects everything; single scattering alone loses up to
    // ~60% at roughness 1 (separable G: the 'ggx' specular).  The quadrature's noise and the 10-order cap: < 1%.
    for (float alpha : {0.1f, 0.4f, 1.0f})
        for (float cos_o : {0.9f, 0.5f}) {
            EXPECT_NEAR(MultiscatterAlbedo(alpha, cos_o, true), 1.0, 0.01) << alpha << " " << cos_o;
            const double cycles_eval = MultiscatterAlbedo(alpha, cos_o, false);
            EXPECT_LE(cycles_eval, 1.01) << alpha << " " << cos_o;
            EXPECT_GT(cycles_eval, 0.85) << alpha << " " << cos_o;
        }
    // Cycles' evaluation from the shallower direction loses energy at roughness 1 (the walk restarts upward rays at
    // the top): what its MIS mixes with the sampling walk (multiscatter_ggx.h).
    EXPECT_LT(MultiscatterAlbedo(1.0f, 0.8f, false), 0.95);
}

TEST(BsdfLobes, PrincipledMultiscatterAboveCyclesRoughnessSwitch) {
    PrincipledInputs in;
    in.metallic = 1;
    in.multiscatter = true;
    in.roughness = 0.07f;
    EXPECT_FALSE(MakePrincipledBsdf(in).multiscatter);  // Cycles: single-scatter GGX at roughness <= 0.075
    in.roughness = 0.6f;
    const Bsdf m = MakePrincipledBsdf(in);
    ASSERT_TRUE(m.multiscatter);
    in.multiscatter = false;
    const Bsdf single = MakePrincipledBsdf(in);
    // Brighter than single scattering at a rough metal, and one evaluation is a fixed function of the directions.
    const Vec3f wo = SphericalDirection(0.6f, 0.2f), wi = SphericalDirection(0.5f, 2.9f);
    EXPECT_EQ(EvalBsdf<true>(m, wo, wi).y, EvalBsdf<true>(m, wo, wi).y);
    double multi = 0, one = 0;
    for (int k = 0; k < 64; ++k) {
        const Vec3f w = SphericalDirection(0.2f + 0.7f * k / 64, 0.1f * k);
        multi += EvalBsdf<true>(m, wo, w).y;
        one += EvalBsdf<true>(single, wo, w).y;
    }
    EXPECT_GT(multi, 1.1 * one);
}

// Ray visibility (render/ray_visibility.h): a light lighting only the diffuse or only the glossy closures gets the
// lobes of that class, whose values and pdfs (each lobe at its own probability) sum to the whole BSDF's; SampledRayKind
// names the sampled lobe's ray kind (translucent: diffuse and transmission, below the surface).
TEST(BsdfLobes, ClosureClassesSplitTheBsdfAndItsPdf) {
    PrincipledInputs sheen_coat;
    sheen_coat.sheen = 0.8f;
    sheen_coat.clearcoat = 0.6f;
    sheen_coat.clearcoat_roughness = 0.2f;
    std::vector<NamedMaterial> materials = Materials();
    materials.push_back({"principled sheen clearcoat", MakePrincipledBsdf(sheen_coat)});
    materials.push_back({"lambert + ggx", MakeLambertGgxBsdf({0.5f, 0.4f, 0.3f}, 0.3f, 0.2f, 0.5f)});
    PCG32 rng(0x7151b1u, 3);
    for (const auto& [name, m] : materials) {
        for (int i = 0; i < 2000; ++i) {
            const Vec3f wo = SampleCosineHemisphere({rng.NextFloat(), rng.NextFloat()});
            Vec3f wi = SampleCosineHemisphere({rng.NextFloat(), rng.NextFloat()});
            if (i % 4 == 0) wi.z = -wi.z;
            if (!(wo.z > 1e-3f) || !(std::abs(wi.z) > 1e-3f)) continue;
            const float all = BsdfPDF<true>(m, wo, wi);
            EXPECT_EQ(BsdfPDFOfClasses<true>(m, wo, wi, kRayAll), all) << name;
            const float diffuse = BsdfPDFOfClasses<true>(m, wo, wi, kRayAll & ~kRayGlossy);
            const float glossy = BsdfPDFOfClasses<true>(m, wo, wi, kRayAll & ~kRayDiffuse);
            EXPECT_NEAR(diffuse + glossy, all, 1e-5f * all + 1e-7f) << name;
            const Spectrum f = EvalBsdf<true>(m, wo, wi);
            const Spectrum split = EvalBsdf<true>(LobesLitBy(m, kRayAll & ~kRayGlossy), wo, wi) +
                                   EvalBsdf<true>(LobesLitBy(m, kRayAll & ~kRayDiffuse), wo, wi);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(split[c], f[c], 1e-4f * f[c] + 1e-7f) << name;
        }
        for (int i = 0; i < 2000; ++i) {
            const Vec3f wo = SampleCosineHemisphere({rng.NextFloat(), rng.NextFloat()});
            const Point2<float> u{rng.NextFloat(), rng.NextFloat()};
            const BsdfSample s = SampleBsdf<true>(m, wo, u);
            if (!(s.pdf > 0)) continue;
            const uint8_t ray = SampledRayKind<true>(m, u);
            if (s.wi.z < 0) {
                EXPECT_EQ(ray, kRayDiffuse | kRayTransmission) << name;
            } else {
                EXPECT_TRUE(ray == kRayDiffuse || ray == kRayGlossy) << name;
                // The lobe it came from is of that class: the class's pdf is positive there.
                EXPECT_GT(BsdfPDFOfClasses<true>(m, wo, s.wi, ray), 0.0f) << name;
            }
        }
    }
}

}  // namespace
}  // namespace sphrect::render
