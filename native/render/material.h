// A Material is what a surface is made of: its kind, its inputs, the image lookups bound to them, a mix's layers.
// The scene turns each into a Bsdf (bsdf.h: the lobes it evaluates) once; a hit on a textured one rebuilds its
// Bsdf from the Material with the looked-up values (EvaluateTexturedBsdf).  Untextured materials never come
// here: the integrator reads RenderScene::bsdfs, and a scene without textures pays one flag test
// per hit (BM_DiffuseKernel vs BM_TexturedKernel).
#pragma once

#include <string>
#include <vector>

#include "bsdf.h"
#include "svm/evaluate.h"
#include "texture.h"

namespace sphrect::render {

enum class MaterialKind {
    kDiffuse,
    kGlossy,
    kPrincipled,
    kGlass,
    kGlossyBsdf,
    kTranslucent,
    kHoldout,
    kTransparent,
    kMix
};
// The scene format's names of the kinds (MATERIAL_KINDS, in MaterialKind's order; bindings export them), and of the
// microfacet distributions the kinds that have one take.
constexpr const char* kMaterialKindNames[] = {"diffuse",     "glossy",  "principled",  "glass", "glossy_bsdf",
                                              "translucent", "holdout", "transparent", "mix"};
constexpr const char* kGlassDistributionNames[] = {"ggx", "beckmann"};
constexpr const char* kPrincipledDistributionNames[] = {"ggx", "multiscatter_ggx"};
constexpr const char* kGlossyDistributionNames[] = {"ggx", "beckmann", "multiscatter_ggx"};

// The inputs a lookup can drive (the scene format's TEXTURED_INPUTS, in order; bindings export the names).  The
// emission's lookup multiplies Material::emission (Cycles' colour x strength, the colour an image's) at each point
// of the emitter (textured_emission.h); the others replace their input.
enum class TexturedInput { kBaseColor, kRoughness, kMetallic, kSpecular, kEmission, kCount };
constexpr int kNumTexturedInputs = int(TexturedInput::kCount);
constexpr const char* kTexturedInputNames[kNumTexturedInputs] = {"base_color", "roughness", "metallic", "specular",
                                                                 "emission"};
constexpr const char* kTextureInterpolationNames[] = {"linear", "closest"};     // TextureInterpolation's order
constexpr const char* kTextureExtensionNames[] = {"repeat", "extend", "clip"};  // TextureExtension's order
constexpr const char* kTextureOutputNames[] = {"color", "alpha"};               // TextureLookup::alpha_output
constexpr const char* kTextureCoordinateNames[] = {"uv", "generated"};          // TextureLookup::generated

// A Mix Shader factor from a texture or a node program (when `program` is not empty): the layer's weight times fac,
// or 1 - fac (the node's first shader).
struct MixFactorLookup {
    TextureLookup lookup;
    bool complement = false;
    svm::NodeProgram program;
};

// What replaces a material's shading normal: a Normal Map node (tangent space): its image lookup, strength, read in
// the frame of the mesh's UV tangent, bitangent and shading normal (ApplyNormalMap); or a node program (a Bump
// node's graph: its result, a world-space normal, replaces it; BumpedShadingNormal).  `differentials`: some program
// of the material bumps, so its hits carry their ray differential (RenderScene::AddMaterial sets it).
struct NormalMap {
    TextureLookup lookup;
    float strength = 1;
    svm::NodeProgram program;
    bool differentials = false;
    bool replaces_normal() const { return lookup.bound() || !program.empty(); }
};

struct MaterialLayer;

// sphrect.Material's fields (python/sphrect/scene.py documents them), as RenderScene::AddMaterial takes them.
struct Material {
    std::string name = "default";
    MaterialKind kind = MaterialKind::kDiffuse;
    PrincipledInputs inputs;  // base_color, roughness, metallic, specular used by every kind that has them
    float ior = 1.45f;        // glass
    bool beckmann = false;    // glass, glossy BSDF
    Spectrum emission;        // radiance from both sides (times its lookup's colour when textured); a mix adds its
                              // layers' (each times its weight)
    TextureLookup textures[kNumTexturedInputs];
    // Node programs driving inputs (svm/program.h; empty: none), as textures do: a program's result replaces its input
    // (a colour, or a float in x), but for the emission's, which multiplies Material::emission as its lookup would.
    svm::NodeProgram programs[kNumTexturedInputs];
    NormalMap normal_map;               // lookup unbound: none
    bool programmed = false;            // HasPrograms(), set by RenderScene::AddMaterial
    std::vector<MaterialLayer> layers;  // kMix

    bool ReadsCoordinates(bool generated) const;  // some lookup reads 'generated' (true) or 'uv' (false)
    bool HasPrograms() const;                     // some input or mix factor (of any layer) is a node program
    bool Bumps() const;                           // some program (the normal's too) has a Bump node
    // Whether pred holds for some program: an input's, a layer's mix factor's (any layer, recursively) and, with
    // `with_normal`, the normal's.
    template <class Pred>
    bool AnyProgram(const Pred& pred, bool with_normal = false) const;
    bool ReadsRayContext() const;  // some program reads the Light Path node's ray kinds or depths
    // The emission varies over the surface: an image or a program drives it (a textured emitter).
    bool EmissionVaries() const {
        return textures[int(TexturedInput::kEmission)].bound() || !programs[int(TexturedInput::kEmission)].empty();
    }
};

struct MaterialLayer {
    float weight = 1;
    std::vector<MixFactorLookup> factors;
    Material material;
};

// A Diffuse BSDF (kind 'diffuse') of this colour and emission.
inline Material DiffuseMaterial(const Spectrum& color, const Spectrum& emission = {}) {
    Material m;
    m.inputs.base_color = color;
    m.emission = emission;
    return m;
}

inline bool Material::ReadsCoordinates(bool generated) const {
    for (const TextureLookup& t : textures)
        if (t.bound() && t.generated == generated) return true;
    for (const MaterialLayer& l : layers) {
        for (const MixFactorLookup& f : l.factors)
            if (f.program.empty() && f.lookup.generated == generated) return true;
        if (l.material.ReadsCoordinates(generated)) return true;
    }
    return false;
}

template <class Pred>
bool Material::AnyProgram(const Pred& pred, bool with_normal) const {
    if (with_normal && pred(normal_map.program)) return true;
    for (const svm::NodeProgram& p : programs)
        if (pred(p)) return true;
    for (const MaterialLayer& l : layers) {
        for (const MixFactorLookup& f : l.factors)
            if (pred(f.program)) return true;
        if (l.material.AnyProgram(pred, with_normal)) return true;
    }
    return false;
}

inline bool Material::ReadsRayContext() const {
    return AnyProgram([](const svm::NodeProgram& p) { return p.ReadsRayContext(); });
}

inline bool Material::HasPrograms() const {
    return AnyProgram([](const svm::NodeProgram& p) { return !p.empty(); });
}

inline bool Material::Bumps() const {
    return AnyProgram([](const svm::NodeProgram& p) { return p.Bumps(); }, true);
}

// Texture coordinates at a hit: the mesh's UVs as (u, v, 0) and its Generated coordinates (zero where the
// mesh has none: Cycles reads zeros for a missing attribute too).
struct TextureCoordinates {
    Vec3f uv, generated;
};

inline Rgba EvalTextureAt(const std::vector<Image>& images, const TextureLookup& t, const TextureCoordinates& tc) {
    return EvalTextureLookup(images, t, t.generated ? tc.generated : tc.uv);
}

// The Bsdf of a Material that is not a mix, with these inputs.
inline Bsdf MakeBsdfFromInputs(const Material& r, const PrincipledInputs& in) {
    switch (r.kind) {
        case MaterialKind::kDiffuse: return MakeDiffuseBsdf(in.base_color, in.diffuse_roughness);
        case MaterialKind::kGlossy: return MakeLambertGgxBsdf(in.base_color, in.roughness, in.metallic, in.specular);
        case MaterialKind::kPrincipled: return MakePrincipledBsdf(in);
        case MaterialKind::kGlass: return MakeGlassBsdf(in.base_color, in.roughness, r.ior, r.beckmann);
        case MaterialKind::kGlossyBsdf:
            return MakeGlossyBsdf(in.base_color, in.roughness, r.beckmann, in.anisotropic, in.anisotropic_rotation,
                                  in.multiscatter);
        case MaterialKind::kTranslucent: return MakeTranslucentBsdf(in.base_color);
        case MaterialKind::kHoldout: return MakeHoldoutBsdf();
        case MaterialKind::kTransparent: return MakeTransparentBsdf(in.base_color);
        case MaterialKind::kMix: break;
    }
    return MakeDiffuseBsdf({});  // a mix's layers are the caller's
}

// For materials mixed together: the index of the distinct microfacet lobe each one's (first) lobe takes in the
// mix, equal ones sharing one as MixIntoBsdf merges them; -1 for one without (the Blender exporter asks, to keep the
// heaviest kMaxMicrofacetLobes).
inline std::vector<int> MixLobeSlots(const std::vector<Material>& parts) {
    std::vector<MicrofacetLobe> distinct;
    std::vector<int> slots;
    for (const Material& m : parts) {
        int slot = -1;
        const Bsdf bsdf = m.kind == MaterialKind::kMix ? MakeEmptyMixBsdf() : MakeBsdfFromInputs(m, m.inputs);
        if (bsdf.num_lobes > 0) {
            slot = 0;
            while (slot < int(distinct.size()) && !SameMicrofacetLobe(distinct[size_t(slot)], bsdf.lobes[0])) ++slot;
            if (slot == int(distinct.size())) distinct.push_back(bsdf.lobes[0]);
        }
        slots.push_back(slot);
    }
    return slots;
}

namespace material_detail {

// The Material's Bsdf at texture coordinates tc (and, kPrograms, hit sg for its node programs): each bound input
// replaced by its lookup or its program's result (colours as RGB, scalars as luminance; Cycles' closure setup clamps
// them as the Make*Bsdf functions do), a mix rebuilt from its layers with the factors' weights (clamped to [0, 1], as
// svm_node_mix_closure does).  Without kPrograms, the code of a textured material without programs: no test of them.
template <bool kPrograms>
Bsdf EvaluateAt(const Material& r, const std::vector<Image>& images, const TextureCoordinates& tc,
                const svm::ShaderGlobals* sg) {
    if (r.kind == MaterialKind::kMix) {
        Bsdf mix = MakeEmptyMixBsdf();
        for (const MaterialLayer& l : r.layers) {
            float w = l.weight;
            for (const MixFactorLookup& f : l.factors) {
                float v;
                if constexpr (kPrograms) {
                    v = f.program.empty() ? TextureScalar(EvalTextureAt(images, f.lookup, tc))
                                          : svm::EvalNodeProgram(f.program, images, *sg).x;
                } else {
                    v = TextureScalar(EvalTextureAt(images, f.lookup, tc));
                }
                const float fac = std::clamp(v, 0.0f, 1.0f);
                w *= f.complement ? 1 - fac : fac;
            }
            MixIntoBsdf<MixOverflow::kLenient>(mix, EvaluateAt<kPrograms>(l.material, images, tc, sg), w);
        }
        return mix;
    }
    PrincipledInputs in = r.inputs;
    auto scalar = [&](TexturedInput i, float& value) {
        const TextureLookup& t = r.textures[int(i)];
        if (t.bound()) value = TextureScalar(EvalTextureAt(images, t, tc));
        if constexpr (kPrograms) {
            if (const svm::NodeProgram& p = r.programs[int(i)]; !p.empty())
                value = svm::EvalNodeProgram(p, images, *sg).x;
        }
    };
    auto color = [&](const Spectrum& c) {
        in.base_color = {std::max(c.x, 0.0f), std::max(c.y, 0.0f), std::max(c.z, 0.0f)};
    };
    if (const TextureLookup& t = r.textures[int(TexturedInput::kBaseColor)]; t.bound())
        color(TextureColor(EvalTextureAt(images, t, tc)));
    if constexpr (kPrograms) {
        if (const svm::NodeProgram& p = r.programs[int(TexturedInput::kBaseColor)]; !p.empty())
            color(svm::EvalNodeProgram(p, images, *sg));
    }
    scalar(TexturedInput::kRoughness, in.roughness);
    scalar(TexturedInput::kMetallic, in.metallic);
    scalar(TexturedInput::kSpecular, in.specular);
    return MakeBsdfFromInputs(r, in);
}

}  // namespace material_detail

// A Material's Bsdf at hit sg (its programs read it; its lookups its coordinates).  Emission is not part of a Bsdf:
// the caller keeps the material's own (a textured one is textured_emission.h's).
inline Bsdf EvaluateBsdfAtHit(const Material& r, const std::vector<Image>& images, const svm::ShaderGlobals& sg) {
    return material_detail::EvaluateAt<true>(r, images, TextureCoordinates{sg.uv, sg.generated}, &sg);
}

// A textured Material's Bsdf where only texture coordinates are known: a programmed one's programs (Material::
// programmed, set by RenderScene::AddMaterial) read zero for the other inputs of the hit.
inline Bsdf EvaluateTexturedBsdf(const Material& r, const std::vector<Image>& images, const TextureCoordinates& tc) {
    if (!r.programmed) return material_detail::EvaluateAt<false>(r, images, tc, nullptr);
    svm::ShaderGlobals sg;
    sg.uv = tc.uv;
    sg.generated = tc.generated;
    return EvaluateBsdfAtHit(r, images, sg);
}

}  // namespace sphrect::render
