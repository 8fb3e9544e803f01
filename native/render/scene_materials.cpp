// Materials into the scene (Cycles: scene/shader.cpp): a Material is checked once, here, and turned into the Bsdf
// the integrator evaluates; a mix is made from its layers' Bsdfs by MixIntoBsdf, which says what a mix can hold.
#include <cmath>
#include <string>

#include "scene.h"
#include "scene_checks.h"

namespace sphrect::render {

namespace {

// Blender's IOR inputs stop at 1000; far beyond (2e19) the Fresnel terms overflow float and every sample is dropped.
constexpr float kMaxIor = 1000;

std::string KindName(MaterialKind kind) { return kMaterialKindNames[int(kind)]; }

// The inputs each kind reads must be finite (the Make*Bsdf functions clamp their ranges, as Cycles does).
void CheckInputsFinite(const Material& m) {
    const PrincipledInputs& in = m.inputs;
    switch (m.kind) {
        case MaterialKind::kDiffuse:
            if (!std::isfinite(in.diffuse_roughness)) Fail("diffuse_roughness must be finite");
            break;
        case MaterialKind::kGlossy:
            if (!std::isfinite(in.roughness) || !std::isfinite(in.metallic) || !std::isfinite(in.specular))
                Fail("roughness, metallic and specular must be finite");
            break;
        case MaterialKind::kPrincipled:
            for (float v :
                 {in.metallic, in.specular, in.specular_tint, in.roughness, in.sheen, in.sheen_tint, in.clearcoat,
                  in.clearcoat_roughness, in.anisotropic, in.anisotropic_rotation, in.transmission, in.ior})
                if (!std::isfinite(v)) Fail("Principled inputs must be finite");
            if (in.ior > kMaxIor) Fail("ior must be at most " + std::to_string(int(kMaxIor)) + ", as in Blender");
            break;
        case MaterialKind::kGlass:
            if (!std::isfinite(in.roughness) || !std::isfinite(m.ior)) Fail("roughness and ior must be finite");
            if (m.ior > kMaxIor) Fail("ior must be at most " + std::to_string(int(kMaxIor)) + ", as in Blender");
            break;
        case MaterialKind::kGlossyBsdf:
            if (!std::isfinite(in.roughness) || !std::isfinite(in.anisotropic) ||
                !std::isfinite(in.anisotropic_rotation))
                Fail("roughness, anisotropy and rotation must be finite");
            break;
        default: break;
    }
}

}  // namespace

void RenderScene::CheckLookup(const TextureLookup& lookup) const {
    if (lookup.image < 0 || size_t(lookup.image) >= images.size())
        Fail("texture " + std::to_string(lookup.image) + " is not an index into the scene's " +
             std::to_string(images.size()) + " textures");
    for (const auto& row : lookup.transform)
        for (float v : row)
            if (!std::isfinite(v)) Fail("transform must be a finite 3x4 matrix");
}

Bsdf RenderScene::MakeMaterialBsdf(const Material& m) const {
    if (m.kind != MaterialKind::kMix && !m.layers.empty())
        Fail("only kind 'mix' has layers (kind '" + KindName(m.kind) + "')");
    if (m.kind == MaterialKind::kTransparent && !IsBlack(m.emission))
        Fail("a 'transparent' material has no emission (mix in one instead)");
    if (m.kind != MaterialKind::kHoldout) {
        CheckColor("base_color", m.inputs.base_color);
        CheckColor("emission", m.emission);
        CheckInputsFinite(m);
    }
    Bsdf bsdf;
    if (m.kind == MaterialKind::kHoldout) {
        bsdf = MakeHoldoutBsdf();  // black: its colour and emission are not drawn
    } else if (m.kind == MaterialKind::kMix) {
        bsdf = MakeEmptyMixBsdf();
        bsdf.emission = m.emission;
        for (size_t i = 0; i < m.layers.size(); ++i) {
            const MaterialLayer& layer = m.layers[i];
            try {
                if (!(layer.weight >= 0) || !std::isfinite(layer.weight)) Fail("mix weight must be finite and >= 0");
                for (const MixFactorLookup& f : layer.factors) {
                    if (f.program.empty())
                        CheckLookup(f.lookup);
                    else
                        svm::CheckNodeProgram(f.program, images.size());
                }
                if (layer.material.normal_map.replaces_normal())
                    Fail("a mix layer cannot have a normal map of its own (the mix's has)");
                if (layer.material.EmissionVaries())
                    Fail("a mix layer cannot have an emission texture of its own (the mix's has)");
                const Bsdf part = MakeMaterialBsdf(layer.material);
                if (!layer.factors.empty() && !IsBlack(part.emission))
                    Fail(
                        "an emitting mix layer cannot have texture-driven factors (mesh lights need a constant "
                        "emission)");
                // The untextured values stand for the textured ones (a factor as 1/2): the structure a hit rebuilds.
                MixIntoBsdf(bsdf, part, layer.factors.empty() ? layer.weight : layer.weight * 0.5f);
                bsdf.emission += part.emission * layer.weight;
                bsdf.textured = bsdf.textured || part.textured || !layer.factors.empty();
                bsdf.may_be_translucent = bsdf.may_be_translucent || part.may_be_translucent;
            } catch (const std::invalid_argument& e) {
                Fail("layer " + std::to_string(i) + " ('" + layer.material.name + "'): " + e.what());
            }
        }
        if (m.EmissionVaries() && !IsBlack(bsdf.emission - m.emission))
            Fail(
                "a mix with an emission texture cannot have emitting layers (the texture multiplies its own emission)");
    } else {
        bsdf = MakeBsdfFromInputs(m, m.inputs);
        bsdf.emission = m.emission;
        bsdf.may_be_translucent = m.kind == MaterialKind::kTranslucent;
    }
    for (int i = 0; i < kNumTexturedInputs; ++i) {
        const TextureLookup& lookup = m.textures[i];
        const svm::NodeProgram& program = m.programs[i];
        if (!lookup.bound() && program.empty()) continue;
        if (lookup.bound() && !program.empty())
            Fail("input '" + std::string(kTexturedInputNames[i]) + "' has both a texture and a node program");
        try {
            if (lookup.bound())
                CheckLookup(lookup);
            else
                svm::CheckNodeProgram(program, images.size());
        } catch (const std::invalid_argument& e) {
            Fail((lookup.bound() ? "texture '" : "program '") + std::string(kTexturedInputNames[i]) + "': " + e.what());
        }
        bsdf.textured = true;                                        // the hit's texture coordinates are needed
        if (TexturedInput(i) == TexturedInput::kEmission) continue;  // any kind that emits (textured_emission.h)
        if (m.kind == MaterialKind::kMix) Fail("a mix's textures are its layers' (but for its emission)");
        if (m.kind == MaterialKind::kGlossy) Fail("the 'glossy' model takes no textures (use 'principled')");
        if (m.kind == MaterialKind::kTransparent && TexturedInput(i) == TexturedInput::kBaseColor) {
            // May let rays through wherever its image is not black: the hit evaluates it (integrator/transparency.h).
            bsdf.transparency = {1, 1, 1};
            bsdf.has_transparency = true;
        }
    }
    if (m.normal_map.lookup.bound()) {
        try {
            CheckLookup(m.normal_map.lookup);
        } catch (const std::invalid_argument& e) {
            Fail(std::string("normal_map: ") + e.what());
        }
        if (!std::isfinite(m.normal_map.strength)) Fail("normal map strength must be finite");
        if (m.kind == MaterialKind::kGlossy) Fail("the 'glossy' model takes no normal map (use 'principled')");
        bsdf.normal_mapped = true;
    }
    if (!m.normal_map.program.empty()) {
        if (m.normal_map.lookup.bound()) Fail("a material has a normal map or a normal program, not both");
        try {
            svm::CheckNodeProgram(m.normal_map.program, images.size());
        } catch (const std::invalid_argument& e) {
            Fail(std::string("normal program: ") + e.what());
        }
        if (m.kind == MaterialKind::kGlossy) Fail("the 'glossy' model takes no normal program (use 'principled')");
        bsdf.normal_mapped = true;
    }
    return bsdf;
}

int RenderScene::AddMaterial(const Material& material) {
    RequireNotCommitted();
    try {
        bsdfs.push_back(MakeMaterialBsdf(material));
    } catch (const std::invalid_argument& e) {
        Fail("material '" + material.name + "': " + e.what());
    }
    materials.push_back(material);
    materials.back().programmed = material.HasPrograms();
    if (materials.back().programmed) light_path_programs |= material.ReadsRayContext();
    NormalMap normal_map = material.normal_map;
    normal_map.strength = std::max(normal_map.strength, 0.0f);  // Cycles: max(strength, 0)
    normal_map.differentials = material.Bumps();
    materials.back().normal_map.differentials = normal_map.differentials;
    normal_maps.push_back(normal_map);
    return int(bsdfs.size()) - 1;
}

}  // namespace sphrect::render
