// Image lookups (texture.h) against hand-computed texels, and textured materials (material.h):
// a recipe evaluated with its lookups at constant images equals the material made from those constants.
#include <gtest/gtest.h>

#include <cmath>

#include "render/texture.h"
#include "render/material.h"

namespace sphrect::render {
namespace {

// A 2 x 2 grey image, texels (x, y): (0,0) = 0, (1,0) = 0.25, (0,1) = 0.5, (1,1) = 1 (row 0 at the bottom).
Image Grey2x2() {
    const float texels[] = {0.0f, 0.25f, 0.5f, 1.0f};
    return MakeImage("grey", 2, 2, 1, nullptr, texels, false);
}

float Grey(const Image& im, float u, float v, TextureInterpolation i, TextureExtension e) {
    return LookupImage(im, u, v, i, e).r;
}

TEST(TextureLookup, ClosestReadsTheTexelContainingThePoint) {
    const Image im = Grey2x2();
    const auto closest = TextureInterpolation::kClosest;
    EXPECT_EQ(Grey(im, 0.1f, 0.1f, closest, TextureExtension::kRepeat), 0.0f);
    EXPECT_EQ(Grey(im, 0.9f, 0.1f, closest, TextureExtension::kRepeat), 0.25f);
    EXPECT_EQ(Grey(im, 0.1f, 0.9f, closest, TextureExtension::kRepeat), 0.5f);
    EXPECT_EQ(Grey(im, 0.6f, 0.6f, closest, TextureExtension::kRepeat), 1.0f);
    // Repeat wraps negative coordinates (period 1), extend clamps, clip is black outside [0, 1]^2.
    EXPECT_EQ(Grey(im, -0.4f, 0.1f, closest, TextureExtension::kRepeat), 0.25f);
    EXPECT_EQ(Grey(im, -0.4f, 0.1f, closest, TextureExtension::kExtend), 0.0f);
    EXPECT_EQ(Grey(im, 3.0f, 7.0f, closest, TextureExtension::kExtend), 1.0f);
    EXPECT_EQ(Grey(im, 1.2f, 0.5f, closest, TextureExtension::kClip), 0.0f);
    EXPECT_EQ(LookupImage(im, 1.2f, 0.5f, closest, TextureExtension::kClip).a, 0.0f);
    EXPECT_EQ(Grey(im, 0.9f, 0.9f, closest, TextureExtension::kClip), 1.0f);
}

TEST(TextureLookup, LinearIsBilinearBetweenTexelCentres) {
    const Image im = Grey2x2();
    const auto linear = TextureInterpolation::kLinear;
    // At texel centres the texel itself; midway the mean of the four.
    EXPECT_FLOAT_EQ(Grey(im, 0.25f, 0.25f, linear, TextureExtension::kExtend), 0.0f);
    EXPECT_FLOAT_EQ(Grey(im, 0.75f, 0.75f, linear, TextureExtension::kExtend), 1.0f);
    EXPECT_FLOAT_EQ(Grey(im, 0.5f, 0.5f, linear, TextureExtension::kExtend), (0 + 0.25f + 0.5f + 1) / 4);
    EXPECT_FLOAT_EQ(Grey(im, 0.5f, 0.25f, linear, TextureExtension::kExtend), 0.125f);
    // Past the last centre: extend holds the edge, repeat blends with the opposite edge, clip with black.
    EXPECT_FLOAT_EQ(Grey(im, 1.0f, 0.25f, linear, TextureExtension::kExtend), 0.25f);
    EXPECT_FLOAT_EQ(Grey(im, 1.0f, 0.25f, linear, TextureExtension::kRepeat), 0.125f);
    EXPECT_FLOAT_EQ(Grey(im, 1.0f, 0.25f, linear, TextureExtension::kClip), 0.125f);
}

TEST(TextureLookup, NonFiniteAndHugeCoordinatesStayDefined) {
    const Image im = Grey2x2();
    for (float u : {NAN, INFINITY, -INFINITY, 3e30f, -3e30f}) {
        for (auto i : {TextureInterpolation::kLinear, TextureInterpolation::kClosest})
            for (auto e : {TextureExtension::kRepeat, TextureExtension::kExtend, TextureExtension::kClip}) {
                const Rgba c = LookupImage(im, u, 0.3f, i, e);
                EXPECT_TRUE(std::isfinite(c.r) && c.r >= 0 && c.r <= 1) << u;
            }
    }
}

TEST(TextureLookup, SrgbBytesDecodeAfterFiltering) {
    const uint8_t texels[] = {0, 0, 0, 255, 255, 255};
    const Image im = MakeImage("black, white", 2, 1, 3, texels, nullptr, true);
    // Halfway between black and white: the stored values are averaged (0.5), then decoded, as Cycles does.
    const Rgba c = LookupImage(im, 0.5f, 0.5f, TextureInterpolation::kLinear, TextureExtension::kExtend);
    EXPECT_NEAR(c.g, std::pow((0.5 + 0.055) / 1.055, 2.4), 1e-6);
    EXPECT_EQ(c.a, 1.0f);
    EXPECT_NEAR(SrgbToLinear(0.02f), 0.02f / 12.92f, 1e-9);
}

TEST(TextureLookup, ChannelsExpandAsBlenderShowsThem) {
    const float texel[] = {0.3f, 0.6f};
    const Image grey_alpha = MakeImage("grey, alpha", 1, 1, 2, nullptr, texel, false);
    const Rgba c = grey_alpha.Texel(0, 0);
    EXPECT_EQ(c.r, 0.3f);
    EXPECT_EQ(c.b, 0.3f);
    EXPECT_EQ(c.a, 0.6f);
    TextureLookup alpha;
    alpha.image = 0;
    alpha.alpha_output = true;
    EXPECT_EQ(EvalTextureLookup({grey_alpha}, alpha, {}).g, 0.6f);
}

TEST(TextureLookup, TransformMapsTheCoordinates) {
    const Image im = Grey2x2();
    TextureLookup t;
    t.image = 0;
    t.interpolation = TextureInterpolation::kClosest;
    // (u, v) -> (v, u): the texel (1, 0) is read at (0.1, 0.9).
    const float swap[3][4] = {{0, 1, 0, 0}, {1, 0, 0, 0}, {0, 0, 1, 0}};
    std::copy(&swap[0][0], &swap[0][0] + 12, &t.transform[0][0]);
    EXPECT_EQ(EvalTextureLookup({im}, t, {0.1f, 0.9f, 0}).r, 0.25f);
}

Image Constant(float r, float g, float b) {
    const float texel[] = {r, g, b};
    return MakeImage("constant", 1, 1, 3, nullptr, texel, false);
}

void ExpectSameMaterial(const Bsdf& a, const Bsdf& b) {
    // What EvalPrincipled reads: compare by evaluating both at a few direction pairs.
    const Vec3f wo = Normalize(Vec3f(0.3f, -0.2f, 0.9f));
    for (const Vec3f& wi : {Vec3f(0, 0, 1), Normalize(Vec3f(-0.5f, 0.4f, 0.6f)), Normalize(Vec3f(0.7f, 0.1f, 0.2f))}) {
        const Spectrum fa = EvalBsdf<true>(a, wo, wi), fb = EvalBsdf<true>(b, wo, wi);
        EXPECT_NEAR(fa.x, fb.x, 1e-6f * (1 + fb.x));
        EXPECT_NEAR(fa.y, fb.y, 1e-6f * (1 + fb.y));
        EXPECT_NEAR(fa.z, fb.z, 1e-6f * (1 + fb.z));
        EXPECT_NEAR(BsdfPDF<true>(a, wo, wi), BsdfPDF<true>(b, wo, wi), 1e-5f);
    }
}

TEST(TexturedMaterial, PrincipledInputsFromImagesEqualTheConstants) {
    const std::vector<Image> images = {Constant(0.2f, 0.5f, 0.7f), Constant(0.4f, 0.4f, 0.4f)};
    Material r;
    r.kind = MaterialKind::kPrincipled;
    r.inputs.clearcoat = 0.3f;
    r.textures[int(TexturedInput::kBaseColor)].image = 0;
    r.textures[int(TexturedInput::kRoughness)].image = 1;
    r.textures[int(TexturedInput::kMetallic)].image = 1;
    PrincipledInputs in = r.inputs;
    in.base_color = {0.2f, 0.5f, 0.7f};
    in.roughness = in.metallic = 0.4f;
    ExpectSameMaterial(EvaluateTexturedBsdf(r, images, {}), MakePrincipledBsdf(in));
}

TEST(TexturedMaterial, MixFactorsWeightTheLayers) {
    const std::vector<Image> images = {Constant(0.3f, 0.3f, 0.3f)};
    Material diffuse, glossy, mix;
    diffuse.inputs.base_color = {0.8f, 0.2f, 0.1f};
    glossy.kind = MaterialKind::kGlossyBsdf;
    glossy.inputs.base_color = {0.9f, 0.9f, 0.9f};
    glossy.inputs.roughness = 0.3f;
    mix.kind = MaterialKind::kMix;
    MixFactorLookup fac;
    fac.lookup.image = 0;
    fac.complement = true;
    mix.layers.push_back({1.0f, {fac}, diffuse});
    fac.complement = false;
    mix.layers.push_back({1.0f, {fac}, glossy});
    Bsdf expected = MakeDiffuseBsdf({});
    MixIntoBsdf(expected, MakeDiffuseBsdf(diffuse.inputs.base_color), 0.7f);
    MixIntoBsdf(expected, MakeGlossyBsdf(glossy.inputs.base_color, 0.3f), 0.3f);
    ExpectSameMaterial(EvaluateTexturedBsdf(mix, images, {}), expected);
}

TEST(TexturedMaterial, LenientMixNeverThrows) {
    // Two Principled BSDFs: the scene's construction refuses them, a hit keeps the first.
    Bsdf mix = MakeDiffuseBsdf({});
    PrincipledInputs in;
    MixIntoBsdf(mix, MakePrincipledBsdf(in), 0.5f);
    EXPECT_THROW(MixIntoBsdf(mix, MakePrincipledBsdf(in), 0.5f), std::invalid_argument);
    Bsdf kept = mix;
    MixIntoBsdf<MixOverflow::kLenient>(kept, MakePrincipledBsdf(in), 0.5f);
    EXPECT_EQ(kept.diffuse.x, mix.diffuse.x);
    // Microfacet lobes beyond the limit add to the last one.
    Bsdf lobes = MakeDiffuseBsdf({});
    for (int i = 0; i < kMaxMicrofacetLobes; ++i) MixIntoBsdf(lobes, MakeGlossyBsdf({1, 1, 1}, 0.2f + 0.1f * i), 0.1f);
    EXPECT_THROW(MixIntoBsdf(lobes, MakeGlossyBsdf({1, 1, 1}, 0.9f), 0.1f), std::invalid_argument);
    MixIntoBsdf<MixOverflow::kLenient>(lobes, MakeGlossyBsdf({1, 1, 1}, 0.9f), 0.1f);
    EXPECT_EQ(lobes.num_lobes, kMaxMicrofacetLobes);
    EXPECT_FLOAT_EQ(lobes.lobes[kMaxMicrofacetLobes - 1].color.x, 0.2f);
}

}  // namespace
}  // namespace sphrect::render
