// Singular lobes (render/bsdf/singular.h): the mirror and refracted directions and their weights against Snell's law
// and the Fresnel equations written out here, total internal reflection, the Principled's Fresnel blend, and which
// materials the Make*Bsdf functions give one (Cycles 3.4's alpha_x alpha_y <= 1e-7 test).  Deterministic.
#include <gtest/gtest.h>

#include <cmath>

#include "render/bsdf.h"

namespace sphrect::render {
namespace {

// The unpolarised reflectance of a dielectric interface (relative IOR eta) at incidence cos_i, from its
// s and p amplitudes; 1 past the critical angle.
double FresnelReference(double cos_i, double eta) {
    const double sin_t2 = (1 - cos_i * cos_i) / (eta * eta);
    if (sin_t2 >= 1) return 1;
    const double cos_t = std::sqrt(1 - sin_t2);
    const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

Vec3f ViewAt(float cos_theta, float phi) {
    const float s = std::sqrt(1 - cos_theta * cos_theta);
    return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

TEST(SingularLobes, GlassReflectsAndRefractsWithFresnel) {
    const Spectrum color(0.9f, 0.7f, 0.5f);
    const SingularLobe glass{color, color, 1.5f, SingularFresnel::kDielectric, {}};
    for (const float eta : {1.5f, 2.4f}) {
        SingularLobe l = glass;
        l.ior = eta;
        for (const float cos_i : {1.0f, 0.8f, 0.5f, 0.2f, 0.05f}) {
            const Vec3f wo = ViewAt(cos_i, 0.7f);
            const SingularScatter s = ScatterSingular(l, wo);
            const double f = FresnelReference(cos_i, eta);
            EXPECT_NEAR(s.reflect_weight.y, 0.7 * f, 2e-6) << eta << " " << cos_i;
            EXPECT_NEAR(s.reflect_dir.x, -wo.x, 1e-6);
            EXPECT_NEAR(s.reflect_dir.y, -wo.y, 1e-6);
            EXPECT_NEAR(s.reflect_dir.z, wo.z, 1e-6);
            ASSERT_TRUE(s.refracts);
            EXPECT_NEAR(s.refract_weight.x, 0.9 * (1 - f), 2e-6);
            // Snell: unit, below the surface, opposite the view in the plane of incidence, sin_t = sin_i / eta.
            EXPECT_NEAR(Length(s.refract_dir), 1, 1e-5);
            EXPECT_LT(s.refract_dir.z, 0);
            EXPECT_NEAR(s.refract_dir.x * wo.y - s.refract_dir.y * wo.x, 0, 1e-6);
            EXPECT_LE(s.refract_dir.x * wo.x + s.refract_dir.y * wo.y, 0);
            const double sin_i = std::sqrt(1.0 - double(cos_i) * cos_i);
            EXPECT_NEAR(std::hypot(s.refract_dir.x, s.refract_dir.y), sin_i / eta, 1e-6);
        }
    }
    // At normal incidence, IOR 1.5: 4% reflected, 96% refracted, straight through.
    const SingularScatter n = ScatterSingular(glass, {0, 0, 1});
    EXPECT_NEAR(n.reflect_weight.x, 0.9 * 0.04, 1e-6);
    EXPECT_NEAR(n.refract_weight.x, 0.9 * 0.96, 1e-6);
    EXPECT_NEAR(n.refract_dir.z, -1, 1e-6);
}

TEST(SingularLobes, TotalInternalReflection) {
    // Seen from inside (relative IOR 1 / 1.5): the critical angle's cosine is sqrt(1 - 1/2.25) = 0.745.
    const Spectrum color(1, 1, 1);
    const SingularLobe inside{color, color, 1 / 1.5f, SingularFresnel::kDielectric, {}};
    const SingularScatter beyond = ScatterSingular(inside, ViewAt(0.6f, 0.3f));
    EXPECT_FALSE(beyond.refracts);
    EXPECT_EQ(beyond.reflect_weight.x, 1.0f);
    const SingularScatter before = ScatterSingular(inside, ViewAt(0.9f, 0.3f));
    ASSERT_TRUE(before.refracts);
    EXPECT_NEAR(before.reflect_weight.x, FresnelReference(0.9, 1 / 1.5), 2e-6);
    // Leaving the denser medium the ray bends away from the normal: sin_t = 1.5 sin_i.
    EXPECT_NEAR(std::hypot(before.refract_dir.x, before.refract_dir.y), 1.5 * std::sqrt(1 - 0.81), 1e-5);
}

TEST(SingularLobes, MirrorWeights) {
    // A Glossy BSDF: its colour at every angle; no refraction.
    const SingularLobe mirror{{0.8f, 0.6f, 0.4f}, {}, 1, SingularFresnel::kNone, {}};
    for (const float c : {1.0f, 0.3f}) {
        const SingularScatter s = ScatterSingular(mirror, ViewAt(c, 1));
        EXPECT_EQ(s.reflect_weight.x, 0.8f);
        EXPECT_FALSE(s.refracts);
    }
    // The Principled specular: cspec0 at normal incidence, rising towards white with the Fresnel of its IOR.
    const Spectrum cspec0(0.9f, 0.5f, 0.2f);
    const SingularLobe metal{{1, 1, 1}, {}, 1.5f, SingularFresnel::kBlend, cspec0};
    const SingularScatter head_on = ScatterSingular(metal, {0, 0, 1});
    EXPECT_NEAR(head_on.reflect_weight.z, 0.2, 1e-6);
    const double rise = (FresnelReference(0.1, 1.5) - 0.04) / 0.96;
    EXPECT_NEAR(ScatterSingular(metal, ViewAt(0.1f, 0)).reflect_weight.z, 0.2 * (1 - rise) + rise, 1e-5);
}

TEST(SingularLobes, MadeWhereCyclesIsSingular) {
    // roughness^4 <= 1e-7: roughness up to 0.0177.
    EXPECT_TRUE(IsSingularRoughness(0));
    EXPECT_TRUE(IsSingularRoughness(0.017f));
    EXPECT_FALSE(IsSingularRoughness(0.019f));
    const Bsdf glass = MakeGlassBsdf({1, 1, 1}, 0, 2.4f, true);
    EXPECT_EQ(glass.num_lobes, 0);
    ASSERT_EQ(glass.num_singular, 1);
    EXPECT_TRUE(glass.has_dielectric);  // a back face takes 1 / IOR
    EXPECT_EQ(glass.singular[0].ior, 2.4f);
    const Bsdf rough = MakeGlassBsdf({1, 1, 1}, 0.2f, 1.5f);
    EXPECT_EQ(rough.num_singular, 0);
    EXPECT_EQ(rough.num_lobes, 1);
    const Bsdf sharp_glossy = MakeGlossyBsdf({0.5f, 0.5f, 0.5f}, 0.01f, false, 0, 0, true);
    ASSERT_EQ(sharp_glossy.num_singular, 1);
    EXPECT_FALSE(sharp_glossy.has_dielectric);
    EXPECT_TRUE(IsBlack(sharp_glossy.singular[0].refract));
    // A Principled metal of roughness 0: its specular singular (cspec0 = base colour), no microfacet lobe.
    PrincipledInputs metal;
    metal.base_color = {0.9f, 0.6f, 0.3f};
    metal.metallic = 1;
    metal.roughness = 0;
    const Bsdf p = MakePrincipledBsdf(metal);
    EXPECT_FALSE(p.has_specular);
    ASSERT_EQ(p.num_singular, 1);
    EXPECT_EQ(p.singular[0].fresnel, SingularFresnel::kBlend);
    EXPECT_NEAR(p.singular[0].cspec0.y, 0.6f, 1e-6);
    // Principled transmission 1: a white reflection, the refraction tinted by the base colour.
    PrincipledInputs clear;
    clear.base_color = {0.2f, 0.8f, 0.4f};
    clear.transmission = 1;
    clear.roughness = 0;
    const Bsdf c = MakePrincipledBsdf(clear);
    ASSERT_EQ(c.num_singular, 1);
    EXPECT_EQ(c.singular[0].reflect.x, 1.0f);
    EXPECT_NEAR(c.singular[0].refract.y, 0.8f, 1e-6);
    // Mixes scale and merge equal lobes.
    Bsdf mix = MakeEmptyMixBsdf();
    MixIntoBsdf(mix, sharp_glossy, 0.25f);
    MixIntoBsdf(mix, sharp_glossy, 0.5f);
    MixIntoBsdf(mix, glass, 0.25f);
    ASSERT_EQ(mix.num_singular, 2);
    EXPECT_NEAR(mix.singular[0].reflect.x, 0.375f, 1e-6);
    EXPECT_NEAR(mix.singular[1].refract.x, 0.25f, 1e-6);
    EXPECT_TRUE(mix.has_dielectric);
}

}  // namespace
}  // namespace sphrect::render
