// sphrect.Material into the renderer: the dataclass as dataclasses.asdict gives it (python/sphrect/render.py),
// read here once into a render::Material, whose values RenderScene::AddMaterial checks; and the mix's lobe slots
// the Blender exporter asks for instead of keeping its own copy of MixIntoBsdf's rule.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "numpy_arrays.h"
#include "render/material.h"
#include "render/svm/color_nodes.h"
#include "render/svm/image_projection.h"
#include "render/svm/math_nodes.h"
#include "render/svm/mix_nodes.h"
#include "render/svm/procedural_textures.h"
#include "render/svm/vector_nodes.h"

namespace py = pybind11;

namespace sphrect::python {

namespace {

using render::Material;
using render::MaterialKind;
using render::Spectrum;

// 'a', 'b' or 'c': the allowed values, for messages (as sphrect.arguments.one_of).
template <size_t N>
std::string OneOf(const char* const (&names)[N]) {
    std::string s;
    for (size_t i = 0; i < N; ++i) s += (i ? (i + 1 == N ? " or '" : ", '") : "'") + std::string(names[i]) + "'";
    return s;
}

std::string Repr(const py::handle& h) { return py::repr(h).cast<std::string>(); }

// The index of a name field's value in `names` (ParseNameOrThrow's message), or ValueError naming `what`.
template <size_t N>
int IndexOf(const py::handle& value, const char* const (&names)[N], const std::string& what,
            const std::string& plural) {
    if (!py::isinstance<py::str>(value)) throw py::value_error(what + " must be a name, got " + Repr(value));
    return ParseNameOrThrow<int>(what, plural, value.cast<std::string>(), names);
}

float Number(const py::dict& d, const char* field) {
    const py::handle v = d[field];
    if (py::isinstance<py::bool_>(v) ||
        !(py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v) || py::hasattr(v, "__float__")))
        throw py::value_error(std::string(field) + " must be a number, got " + Repr(v));
    return float(v.cast<double>());
}

Spectrum Rgb(const py::handle& v, const std::string& what) {
    try {
        const auto c = v.cast<std::vector<double>>();
        if (c.size() == 3) return {float(c[0]), float(c[1]), float(c[2])};
    } catch (const py::cast_error&) {
    }
    throw py::value_error(what + " must be three numbers, got " + Repr(v));
}

py::dict Fields(const py::handle& v, const std::string& what) {
    if (!py::isinstance<py::dict>(v)) throw py::value_error(what);
    return py::reinterpret_borrow<py::dict>(v);
}

// The microfacet distribution of a kind that has one (its names: `names`).
template <size_t N>
std::string Distribution(const py::dict& d, const char* const (&names)[N], const std::string& kind) {
    const py::handle v = d["distribution"];
    if (py::isinstance<py::str>(v))
        for (const char* name : names)
            if (v.cast<std::string>() == name) return name;
    throw py::value_error("unknown distribution " + Repr(v) + " for kind '" + kind + "' (expected " + OneOf(names) +
                          ")");
}

render::TextureLookup Lookup(const py::handle& value, const std::string& what) {
    const py::dict d = Fields(value, what + " must be a sphrect.TextureLookup, got " +
                                         std::string(py::str(value.get_type().attr("__name__"))));
    render::TextureLookup t;
    const py::handle index = d["texture"];
    if (py::isinstance<py::bool_>(index) || !py::isinstance<py::int_>(index) || index.cast<long long>() < 0 ||
        index.cast<long long>() > (1LL << 31) - 1)
        throw py::value_error(what + ": texture " + Repr(index) + " is not an index into the scene's textures");
    t.image = index.cast<int>();
    t.alpha_output = IndexOf(d["output"], render::kTextureOutputNames, what + " output", "outputs") == 1;
    t.generated = IndexOf(d["coordinates"], render::kTextureCoordinateNames, what + " coordinates", "coordinates") == 1;
    t.interpolation = render::TextureInterpolation(
        IndexOf(d["interpolation"], render::kTextureInterpolationNames, what + " interpolation", "interpolations"));
    t.extension = render::TextureExtension(
        IndexOf(d["extension"], render::kTextureExtensionNames, what + " extension", "extensions"));
    const std::string bad_transform = what + ": transform must be a finite 3x4 matrix";
    const CArray<double> m = ArrayOf<double>(d["transform"], what + ": transform");
    if (m.ndim() != 2 || m.shape(0) != 3 || m.shape(1) != 4) throw py::value_error(bad_transform);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            if (!std::isfinite(m.at(r, c))) throw py::value_error(bad_transform);
            t.transform[r][c] = float(m.at(r, c));
        }
    return t;
}

// A sphrect.NodeProgram (its instructions' op names kNodeOpNames'; registers -1: an output nobody reads).  The
// scene checks the rest (svm::CheckNodeProgram).
render::svm::NodeProgram Program(const py::handle& value, const std::string& what) {
    namespace svm = render::svm;
    const py::dict d = Fields(
        value, what + " must be a sphrect.NodeProgram, got " + std::string(py::str(value.get_type().attr("__name__"))));
    auto integer = [&](const py::handle& v, const std::string& field, long long lo, long long hi) {
        if (py::isinstance<py::bool_>(v) || !py::isinstance<py::int_>(v) || v.cast<long long>() < lo ||
            v.cast<long long>() > hi)
            throw py::value_error(what + ": " + field + " must be an integer in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "], got " + Repr(v));
        return v.cast<long long>();
    };
    svm::NodeProgram p;
    p.output = int(integer(d["output"], "output", 0, svm::kMaxNodeRegisters - 1));
    p.num_registers = int(integer(d["num_registers"], "num_registers", 1, svm::kMaxNodeRegisters));
    p.data = d["data"].cast<std::vector<float>>();
    size_t i = 0;
    for (const py::handle h : d["instructions"]) {
        const std::string iwhat = what + " instruction " + std::to_string(i++);
        const py::dict f = Fields(h, iwhat + " is not a sphrect.NodeInstruction");
        svm::NodeInstruction in;
        in.op = svm::NodeOp(IndexOf(f["op"], svm::kNodeOpNames, iwhat + " op", "ops"));
        in.mode = uint8_t(integer(f["mode"], "mode", 0, 255));
        in.flags = uint8_t(integer(f["flags"], "flags", 0, 255));
        in.data = int32_t(integer(f["data"], "data", 0, (1LL << 31) - 1));
        in.size = int32_t(integer(f["size"], "size", 0, (1LL << 31) - 1));
        in.value = Rgb(f["value"], iwhat + " value");
        size_t k = 0;
        for (const py::handle r : f["regs"]) {
            if (k == size_t(svm::kMaxNodeOperands)) throw py::value_error(iwhat + ": too many registers");
            const long long reg = integer(r, "regs", -1, svm::kMaxNodeRegisters - 1);
            in.reg[k++] = reg < 0 ? svm::kNoRegister : uint16_t(reg);
        }
        p.code.push_back(in);
    }
    if (p.code.empty()) throw py::value_error(what + ": a program needs instructions");
    return p;
}

// Which input a key of Material.textures or Material.programs names.
int TexturedInputOf(const py::handle& key, const char* what) {
    for (int i = 0; i < render::kNumTexturedInputs; ++i)
        if (py::isinstance<py::str>(key) && key.cast<std::string>() == render::kTexturedInputNames[i]) return i;
    throw py::value_error("no input " + Repr(key) + " takes " + what + " (expected " +
                          OneOf(render::kTexturedInputNames) + ")");
}

Material ReadMaterial(const py::dict& d);

Material ReadMaterialNamed(const py::dict& d) {
    const std::string name = py::str(d["name"]);
    try {
        Material m = ReadMaterial(d);
        m.name = name;
        return m;
    } catch (const py::error_already_set&) {
        throw;
    } catch (const std::exception& e) {
        throw py::value_error("material '" + name + "': " + e.what());
    }
}

Material ReadMaterial(const py::dict& d) {
    Material m;
    m.kind = MaterialKind(IndexOf(d["kind"], render::kMaterialKindNames, "kind", "kinds"));
    m.emission = Rgb(d["emission"], "emission");
    render::PrincipledInputs& in = m.inputs;
    in.base_color = Rgb(d["base_color"], "base_color");
    in.roughness = Number(d, "roughness");
    in.diffuse_roughness = Number(d, "diffuse_roughness");
    in.metallic = Number(d, "metallic");
    in.specular = Number(d, "specular");
    in.specular_tint = Number(d, "specular_tint");
    in.sheen = Number(d, "sheen");
    in.sheen_tint = Number(d, "sheen_tint");
    in.clearcoat = Number(d, "clearcoat");
    in.clearcoat_roughness = Number(d, "clearcoat_roughness");
    in.anisotropic = Number(d, "anisotropic");
    in.anisotropic_rotation = Number(d, "anisotropic_rotation");
    in.transmission = Number(d, "transmission");
    in.ior = m.ior = Number(d, "ior");
    const std::string kind = render::kMaterialKindNames[int(m.kind)];
    std::string distribution;
    if (m.kind == MaterialKind::kGlass) distribution = Distribution(d, render::kGlassDistributionNames, kind);
    if (m.kind == MaterialKind::kGlossyBsdf) distribution = Distribution(d, render::kGlossyDistributionNames, kind);
    if (m.kind == MaterialKind::kPrincipled) distribution = Distribution(d, render::kPrincipledDistributionNames, kind);
    m.beckmann = distribution == "beckmann";
    in.multiscatter = distribution == "multiscatter_ggx";
    const py::handle textures = d["textures"];
    const py::dict texture_fields =
        Fields(textures, "textures must be a dict of input name -> sphrect.TextureLookup, got " +
                             std::string(py::str(textures.get_type().attr("__name__"))));
    for (const auto& [key, lookup] : texture_fields) {
        const int input = TexturedInputOf(key, "a texture");
        m.textures[input] = Lookup(lookup, "texture '" + std::string(render::kTexturedInputNames[input]) + "'");
    }
    if (d.contains("programs")) {  // sphrect.Material.programs (scene format 18)
        const py::handle programs = d["programs"];
        const py::dict program_fields =
            Fields(programs, "programs must be a dict of input name -> sphrect.NodeProgram, got " +
                                 std::string(py::str(programs.get_type().attr("__name__"))));
        for (const auto& [key, program] : program_fields) {
            const int input = TexturedInputOf(key, "a node program");
            m.programs[input] = Program(program, "program '" + std::string(render::kTexturedInputNames[input]) + "'");
        }
    }
    if (d.contains("normal_program") && !d["normal_program"].is_none())  // scene format 19: a Bump node's graph
        m.normal_map.program = Program(d["normal_program"], "normal_program");
    if (!d["normal_map"].is_none()) {
        m.normal_map.lookup = Lookup(d["normal_map"], "normal_map");
        m.normal_map.strength = Number(d, "normal_map_strength");
    }
    const py::handle layers = d["layers"];
    if (!py::isinstance<py::list>(layers) && !py::isinstance<py::tuple>(layers))
        throw py::value_error("layers must be a list of sphrect.MaterialLayer, got " + Repr(layers));
    size_t i = 0;
    for (const py::handle layer : layers) {
        const std::string what = "layer " + std::to_string(i);
        const py::dict l = Fields(layer, what + " is not a sphrect.MaterialLayer");
        render::MaterialLayer out;
        out.weight = Number(l, "weight");
        out.material = ReadMaterialNamed(Fields(l["material"], what + ": material is not a sphrect.Material"));
        size_t j = 0;
        for (const py::handle factor : l["factors"]) {
            const std::string fwhat = what + " factor " + std::to_string(j++);
            const py::dict f = Fields(factor, fwhat + " is not a sphrect.MixFactor");
            render::MixFactorLookup factor_out;
            factor_out.complement = py::bool_(f["complement"]).cast<bool>();
            if (f.contains("program") && !f["program"].is_none())
                factor_out.program = Program(f["program"], fwhat);
            else
                factor_out.lookup = Lookup(f["lookup"], fwhat);
            out.factors.push_back(std::move(factor_out));
        }
        m.layers.push_back(std::move(out));
        ++i;
    }
    return m;
}

}  // namespace

render::svm::NodeProgram ProgramFromFields(const py::handle& fields, const std::string& what) {
    return Program(fields, what);
}

render::TextureLookup LookupFromFields(const py::handle& fields, const std::string& what) {
    return Lookup(fields, what);
}

Material MaterialFromFields(const py::handle& fields) {
    return ReadMaterialNamed(Fields(fields, "a material must be a sphrect.Material"));
}

void BindMaterial(py::module_& m) {
    auto names = [](const auto& list) {
        py::tuple t(std::size(list));
        for (size_t i = 0; i < std::size(list); ++i) t[i] = list[i];
        return t;
    };
    m.attr("material_kinds") = names(render::kMaterialKindNames);
    m.attr("glass_distributions") = names(render::kGlassDistributionNames);
    m.attr("principled_distributions") = names(render::kPrincipledDistributionNames);
    m.attr("glossy_distributions") = names(render::kGlossyDistributionNames);
    // Whether a roughness makes a microfacet closure singular (a sharp mirror or glass: bsdf/singular.h).
    m.def("is_singular_roughness", &render::IsSingularRoughness, py::arg("roughness"));
    m.attr("texture_outputs") = names(render::kTextureOutputNames);
    m.attr("texture_coordinates") = names(render::kTextureCoordinateNames);
    // Node programs (render/svm): the ops, and the names of each op's modes the exporter compiles to.
    m.attr("node_ops") = names(render::svm::kNodeOpNames);
    m.attr("node_globals") = names(render::svm::kShaderGlobalNames);
    {
        py::list shifted;  // the globals a Bump's Height copies read at P + dx / P + dy (kGlobal's flags)
        for (int g = 0; g < int(render::svm::ShaderGlobal::kCount); ++g)
            if (render::svm::IsShiftedGlobal(render::svm::ShaderGlobal(g)))
                shifted.append(render::svm::kShaderGlobalNames[g]);
        m.attr("node_shifted_globals") = shifted;
    }
    m.attr("node_conversions") = names(render::svm::kNodeConversionNames);
    m.attr("node_math_ops") = names(render::svm::kMathOpNames);
    m.attr("node_mix_blends") = names(render::svm::kMixBlendNames);
    m.attr("node_clamp_types") = names(render::svm::kClampTypeNames);
    m.attr("node_map_range_types") = names(render::svm::kMapRangeNames);
    m.attr("node_image_projections") = names(render::svm::kImageProjectionNames);
    m.attr("node_color_models") = names(render::svm::kColorModelNames);
    m.attr("node_mapping_types") = names(render::svm::kMappingTypeNames);
    m.attr("node_musgrave_types") = names(render::svm::kMusgraveTypeNames);
    m.attr("node_voronoi_features") = names(render::svm::kVoronoiFeatureNames);
    m.attr("node_voronoi_metrics") = names(render::svm::kVoronoiMetricNames);
    m.attr("node_gradient_types") = names(render::svm::kGradientTypeNames);
    m.attr("node_wave_types") = names(render::svm::kWaveTypeNames);
    m.attr("node_wave_bands_directions") = names(render::svm::kWaveBandsDirectionNames);
    m.attr("node_wave_rings_directions") = names(render::svm::kWaveRingsDirectionNames);
    m.attr("node_wave_profiles") = names(render::svm::kWaveProfileNames);
    m.attr("node_vector_math_ops") = names(render::svm::kVectorMathOpNames);
    m.attr("node_vector_rotate_types") = names(render::svm::kVectorRotateTypeNames);
    m.attr("node_attribute_nodes") = names(render::svm::kAttributeNodeNames);
    m.attr("MAX_NODE_REGISTERS") = render::svm::kMaxNodeRegisters;

    m.def(
        "_mix_lobe_slots",
        [](const py::list& materials) {
            std::vector<Material> parts;
            for (const py::handle h : materials) parts.push_back(MaterialFromFields(h));
            return render::MixLobeSlots(parts);
        },
        py::arg("materials"), "sphrect.mix_lobe_slots of the materials' dataclasses.asdict fields");
}

}  // namespace sphrect::python
