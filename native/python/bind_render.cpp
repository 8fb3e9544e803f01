// Bindings of the renderer: `_native._Scene` (built by python/sphrect/render.py from a
// sphrect.Scene) and `_native._Renderer`.  The Python-facing API is sphrect.Renderer.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "name_tuple.h"
#include "numpy_arrays.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/svm/standard_attributes.h"

namespace py = pybind11;

namespace sphrect::python {

// bind_material.cpp: a sphrect.Material (its dataclasses.asdict fields) as the renderer takes it.
render::Material MaterialFromFields(const py::handle& fields);
// bind_material.cpp: a sphrect.TextureLookup (its dataclasses.asdict fields); `what` names it in errors.
render::TextureLookup LookupFromFields(const py::handle& fields, const std::string& what);
render::svm::NodeProgram ProgramFromFields(const py::handle& fields, const std::string& what);

namespace {

using render::Renderer;
using render::RenderScene;
using render::Spectrum;
using V3 = std::array<float, 3>;

Vec3f ToVec(const V3& a) { return {a[0], a[1], a[2]}; }

// [n, columns] float32 per-vertex attribute of a mesh (one row per vertex), or an empty array for None.
CArray<float> VertexAttribute(const py::object& obj, py::ssize_t columns, py::ssize_t vertices,
                              const std::string& what) {
    if (obj.is_none()) return {};
    CArray<float> a = CArray<float>::ensure(obj);
    if (!a || a.ndim() != 2 || a.shape(1) != columns || a.shape(0) != vertices)
        throw py::value_error(what + " must have shape [V, " + std::to_string(columns) + "] for the V vertices");
    return a;
}

// The ray kinds not named in `hidden` (render::kRayKindNames): a mesh's or light's visibility bits.
uint8_t VisibleTo(const std::vector<std::string>& hidden) {
    uint8_t bits = render::kRayAll;
    for (const std::string& name : hidden)
        bits &= uint8_t(~(1u << ParseNameOrThrow<int>("ray kind", "ray kinds", name, render::kRayKindNames)));
    return bits;
}

// The Light Path node's context (render/svm/program.h) named `name`: 'camera', 'light_sample', 'shadow', or a BSDF or
// phase ray's kinds (render::kRayKindNames) joined by '+'; after `transparent` transparent surfaces.
render::svm::RayContext RayContextNamed(const std::string& name, int transparent) {
    if (transparent < 0 || transparent > render::kMaxTransparentHits)
        throw py::value_error("transparent_depth must be in [0, " + std::to_string(render::kMaxTransparentHits) + "]");
    if (name == "camera") return render::svm::CameraRayContext(transparent);
    if (name == "light_sample") return render::svm::LightSampleContext(transparent);
    if (name == "shadow") return render::svm::ShadowRayContext(transparent);
    uint8_t kinds = 0;
    for (size_t start = 0; start <= name.size();) {
        const size_t end = std::min(name.find('+', start), name.size());
        kinds |= uint8_t(1u << ParseNameOrThrow<int>("ray kind", "ray kinds", name.substr(start, end - start),
                                                     render::kRayKindNames));
        start = end + 1;
    }
    if (kinds & (render::kRayCamera | render::kRayShadow))
        throw py::value_error("ray '" + name + "': 'camera' and 'shadow' are rays of their own");
    return render::svm::ScatteredRayContext(render::ScatteredRayFlags(kinds), transparent);
}

// A light's visibility (render/ray_visibility.h): `invisible_to` names the ray kinds it does not light (camera: not
// seen, as visible = false); shadow is no light's (Cycles' lights cast no shadow of their own: cast_shadow is theirs).
render::LightVisibility LightVisibilityOf(const std::vector<std::string>& invisible_to, bool cast_shadow,
                                          bool use_mis) {
    const uint8_t rays = VisibleTo(invisible_to);
    if (!(rays & render::kRayShadow))
        throw py::value_error("a light's invisible_to cannot name 'shadow' (its own shadows are cast_shadow)");
    return {rays, cast_shadow, use_mis};
}

void AddMesh(RenderScene& s, const std::string& name, const py::object& vertices, const py::object& triangles,
             const py::object& normals, const py::object& material_ids, const py::object& uvs,
             const py::object& generated, const std::vector<std::string>& invisible_to) {
    const uint8_t visibility = VisibleTo(invisible_to);
    const auto v = RowsOf<float>(vertices, 3, "vertices");
    const auto t = RowsOf<int32_t>(triangles, 3, "triangles");
    CArray<float> n;
    CArray<int32_t> m;
    if (!normals.is_none()) {
        n = RowsOf<float>(normals, 3, "normals");
        if (n.shape(0) != v.shape(0)) throw py::value_error("mesh '" + name + "': normals must match the vertices");
    }
    if (!material_ids.is_none()) {
        m = CArray<int32_t>::ensure(material_ids);
        if (!m || m.ndim() != 1 || m.shape(0) != t.shape(0))
            throw py::value_error("mesh '" + name + "': material_ids must have one entry per triangle");
    }
    const CArray<float> uv = VertexAttribute(uvs, 2, v.shape(0), "mesh '" + name + "': uvs");
    const CArray<float> gen = VertexAttribute(generated, 3, v.shape(0), "mesh '" + name + "': generated");
    py::gil_scoped_release release;  // validation and the copies into Embree's buffers
    s.AddMesh(name, v.data(), size_t(v.shape(0)), t.data(), size_t(t.shape(0)), normals.is_none() ? nullptr : n.data(),
              material_ids.is_none() ? nullptr : m.data(), uvs.is_none() ? nullptr : uv.data(),
              generated.is_none() ? nullptr : gen.data(), visibility);
}

void AddVolume(RenderScene& s, const std::string& name, const py::object& vertices, const py::object& triangles,
               V3 sigma_s, V3 sigma_a, float g) {
    const auto v = RowsOf<float>(vertices, 3, "vertices");
    const auto t = RowsOf<int32_t>(triangles, 3, "triangles");
    py::gil_scoped_release release;
    s.AddVolume(name, v.data(), size_t(v.shape(0)), t.data(), size_t(t.shape(0)), ToVec(sigma_s), ToVec(sigma_a), g);
}

// An image from a [H, W, C] uint8 or float32 array (C in 1..4, rows bottom to top).
// Keeps a numpy array alive for the Image that reads its values; released with the GIL wherever the last scene
// holding it goes.
std::shared_ptr<const void> ArrayKeeper(const py::array& a) {
    return std::shared_ptr<const void>(new py::object(a), [](const void* p) {
        py::gil_scoped_acquire gil;
        delete static_cast<const py::object*>(p);
    });
}

// An Image of a numpy array's values, [H, W, 1..4] uint8 or floats.  It reads the array in place where nobody can
// change the values under it -- a converted copy made here, a read-only array (the add-on's textures, which its
// compare mode hands to up to 20 renderers), or for the call's own duration (`transient`) -- and copies it otherwise.
render::Image ImageOfArray(const std::string& name, const py::array& pixels, bool srgb, bool transient = false) {
    if (pixels.ndim() != 3 || pixels.shape(2) < 1 || pixels.shape(2) > 4 || pixels.shape(0) < 1 || pixels.shape(1) < 1)
        throw py::value_error("image '" + name + "': pixels must have shape [H, W, 1..4]");
    if (pixels.shape(0) > render::kMaxImageSide || pixels.shape(1) > render::kMaxImageSide)
        throw py::value_error("image '" + name + "': at most " + std::to_string(render::kMaxImageSide) +
                              " pixels a side");
    const int h = int(pixels.shape(0)), w = int(pixels.shape(1)), c = int(pixels.shape(2));
    const size_t values = size_t(w) * size_t(h) * size_t(c);
    if (py::isinstance<py::array_t<uint8_t>>(pixels)) {
        const auto a = CArray<uint8_t>::ensure(pixels);
        if (transient || !a.is(pixels) || !pixels.writeable())
            return render::ShareImage(name, w, h, c, a.data(), nullptr, ArrayKeeper(a), srgb);
        return render::MakeImage(name, w, h, c, a.data(), nullptr, srgb);
    }
    auto a = CArray<float>::ensure(pixels);
    if (!a) throw py::value_error("image '" + name + "': pixels must be numbers");
    if (!a.is(pixels)) {  // a copy of our own: made finite in place
        render::ZeroNonFinite(a.mutable_data(), values);
        return render::ShareImage(name, w, h, c, nullptr, a.data(), ArrayKeeper(a), srgb);
    }
    const bool finite = std::all_of(a.data(), a.data() + values, [](float v) { return std::isfinite(v); });
    if (finite && (transient || !pixels.writeable()))
        return render::ShareImage(name, w, h, c, nullptr, a.data(), ArrayKeeper(a), srgb);
    return render::MakeImage(name, w, h, c, nullptr, a.data(), srgb);
}

int AddImage(RenderScene& s, const std::string& name, const py::array& pixels, bool srgb) {
    if (pixels.ndim() == 3)  // before any copy is made
        s.CheckImageMemory(
            "image '" + name + "'",
            uint64_t(pixels.size()) * (py::isinstance<py::array_t<uint8_t>>(pixels) ? 1 : sizeof(float)));
    return s.AddImage(ImageOfArray(name, pixels, srgb));
}

// A 3x3 rotation (row-major) from Python, or ValueError naming `what`.
void RotationOf(const py::object& obj, const std::string& what, float out[3][3]) {
    const auto a = ArrayOf<double>(obj, what);
    if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3)
        throw py::value_error(what + " must be a 3x3 matrix, got shape " + ShapeString(a));
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) out[r][c] = float(a.at(r, c));
}

render::TextureInterpolation InterpolationOf(const std::string& name) {
    return ParseNameOrThrow<render::TextureInterpolation>("world environment interpolation", "interpolations", name,
                                                          render::kTextureInterpolationNames);
}

// The binding of a RenderScene setter of an image world (SetEnvironment, SetCameraEnvironment): `what` names it in
// errors.
template <class Setter>
auto EnvironmentSetter(Setter set, const std::string& what) {
    return [set, what](RenderScene& s, int texture, V3 strength, const py::object& to_world,
                       const std::string& interpolation) {
        float m[3][3];
        RotationOf(to_world, what + " to_world", m);
        (s.*set)(texture, ToVec(strength), m, InterpolationOf(interpolation));
    };
}

// The image world on its own, for tests of its sampling (environment_light.h): its image given as pixels.
struct EnvironmentSampler {
    render::Image image;
    render::EnvironmentLight light;
};

EnvironmentSampler MakeEnvironmentSampler(const py::array& pixels, const py::object& to_world, V3 strength,
                                          const std::string& interpolation) {
    EnvironmentSampler s;
    s.image = ImageOfArray("environment", pixels, false);
    if (!to_world.is_none()) RotationOf(to_world, "to_world", s.light.to_world);
    s.light.strength = ToVec(strength);
    s.light.interpolation = InterpolationOf(interpolation);
    s.light.image = 0;
    render::BuildEnvironmentDistribution(s.light, s.image);
    return s;
}

// f(row i of the (N, 3) directions) for each row, as an (N, width) float64 array.
template <class F>
py::array_t<double> PerDirection(const py::object& dirs, int width, F&& f) {
    const auto d = RowsOf<float>(dirs, 3, "directions");
    py::array_t<double> out({d.shape(0), py::ssize_t(width)});
    auto o = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < d.shape(0); ++i) f(Vec3f{d.at(i, 0), d.at(i, 1), d.at(i, 2)}, &o(i, 0));
    return out;
}

render::CameraModel MakeCameraModel(int width, int height, const py::object& to_world, bool orthographic,
                                    float half_width, float half_height, float offset_x, float offset_y,
                                    float aperture_radius, float focus_distance, float clip_start, float clip_end,
                                    const std::string& pixel_filter, float filter_width) {
    const auto mat = CArray<double>::ensure(to_world);
    if (!mat || mat.ndim() != 2 || mat.shape(0) != 4 || mat.shape(1) != 4)
        throw py::value_error("camera to_world must be a 4x4 matrix");
    render::CameraModel c;
    c.width = width;
    c.height = height;
    c.orthographic = orthographic;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) c.to_world[i][j] = float(mat.at(i, j));
    c.half_width = half_width;
    c.half_height = half_height;
    c.offset_x = offset_x;
    c.offset_y = offset_y;
    c.aperture_radius = aperture_radius;
    c.focus_distance = focus_distance;
    c.clip_start = clip_start;
    c.clip_end = clip_end;
    if (!(filter_width >= render::kMinPixelFilterWidth && filter_width <= render::kMaxPixelFilterWidth))
        throw py::value_error(py::str("camera filter_width must be in [{:g}, {:g}] pixels, got {:g}")
                                  .format(render::kMinPixelFilterWidth, render::kMaxPixelFilterWidth, filter_width)
                                  .cast<std::string>());
    c.filter =
        render::MakePixelFilter(ParseNameOrThrow<render::PixelFilterType>("camera pixel_filter", "pixel filters",
                                                                          pixel_filter, render::kPixelFilterNames),
                                filter_width);
    return c;
}

// set_camera of the scene and of the renderer: the same arguments (sphrect/render.py _set_camera).
template <class Target>
void SetCamera(Target& target, int width, int height, const py::object& to_world, bool orthographic, float half_width,
               float half_height, float offset_x, float offset_y, float aperture_radius, float focus_distance,
               float clip_start, float clip_end, const std::string& pixel_filter, float filter_width) {
    const render::CameraModel c =
        MakeCameraModel(width, height, to_world, orthographic, half_width, half_height, offset_x, offset_y,
                        aperture_radius, focus_distance, clip_start, clip_end, pixel_filter, filter_width);
    py::gil_scoped_release release;  // the renderer's screen lights of many lights take a while
    target.SetCamera(c);
}

std::unique_ptr<Renderer> MakeRenderer(std::shared_ptr<RenderScene> scene, const std::vector<std::string>& techniques,
                                       int light_samples, const std::string& pattern, const std::string& mis,
                                       const std::string& medium_sampling, const std::string& light_selection,
                                       const std::string& ellipse_technique, uint64_t seed, int threads, int tile_size,
                                       bool analytic_light_coverage, bool bsdf_samples_on_diffuse,
                                       uint64_t memory_limit, bool emission_blocks, double added_shading_cost,
                                       double added_ray_cost, int ris_candidates) {
    if (!scene->committed()) throw py::value_error("the scene must be committed before rendering");
    render::RenderOptions o;
    o.techniques.clear();
    for (const auto& name : techniques) {
        Technique t;
        ParseEnumNameOrThrow("technique", "techniques", name, kAllTechniques, TechniqueName, &t);
        o.techniques.push_back(t);  // (the Renderer refuses one listed twice)
    }
    ParseEnumNameOrThrow("pattern", "patterns", pattern, kAllPatterns, PatternName, &o.pattern);
    ParseEnumNameOrThrow("mis", "mis modes", mis, render::kAllMisModes, render::MisModeName, &o.mis);
    ParseEnumNameOrThrow("medium_sampling", "medium_sampling values", medium_sampling, render::kAllMediumSamplings,
                         render::MediumSamplingName, &o.medium_sampling);
    ParseEnumNameOrThrow("light_selection", "light_selection values", light_selection, render::kAllLightSelections,
                         render::LightSelectionName, &o.light_selection);
    ParseEnumNameOrThrow("ellipse_technique", "ellipse techniques", ellipse_technique, kAllEllipseTechniques,
                         EllipseTechniqueName, &o.ellipse_technique);
    o.light_samples = light_samples;
    o.seed = seed;
    o.threads = threads;
    o.tile_size = tile_size;
    o.analytic_light_coverage = analytic_light_coverage;
    o.bsdf_samples_on_diffuse = bsdf_samples_on_diffuse;
    o.memory_limit = memory_limit;
    o.emission_blocks = emission_blocks;
    o.added_shading_cost = added_shading_cost;
    o.added_ray_cost = added_ray_cost;
    o.ris_candidates = ris_candidates;
    return std::make_unique<Renderer>(std::move(scene), std::move(o));
}

bool Render(Renderer& r, int samples, double time_budget, const py::object& progress) {
    // Called on this (the calling) thread after every tile, with the GIL re-acquired: runs the
    // user's callback and lets Ctrl-C (KeyboardInterrupt) stop the render.
    std::function<void(int, int)> callback = [&progress](int done, int total) {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        if (!progress.is_none()) progress(done, total);
    };
    py::gil_scoped_release release;
    return r.Render(samples, time_budget, callback);
}

py::array_t<float> Image(const Renderer& r, int k) {
    const auto lock = r.ReadLock();  // set_camera on another thread waits: the resolution and image stay one
    py::array_t<float> a({r.height(), r.width(), 4});
    r.Image(k, a.mutable_data());
    return a;
}

// A copy of an accumulation buffer as an array of `shape`.
template <typename T>
py::array_t<T> BufferArray(const std::vector<T>& buffer, std::vector<py::ssize_t> shape) {
    py::array_t<T> a(shape);
    std::copy(buffer.begin(), buffer.end(), a.mutable_data());
    return a;
}

py::array_t<float> ResolveImageArray(const py::array_t<double, py::array::c_style | py::array::forcecast>& sums,
                                     const py::array_t<uint32_t, py::array::c_style | py::array::forcecast>& counts,
                                     const py::array_t<double, py::array::c_style | py::array::forcecast>& alpha_sums,
                                     bool film_alpha) {
    if (counts.ndim() != 2 || sums.ndim() != 3 || sums.shape(2) != 3 || alpha_sums.ndim() != 2 ||
        sums.shape(0) != counts.shape(0) || sums.shape(1) != counts.shape(1) ||
        alpha_sums.shape(0) != counts.shape(0) || alpha_sums.shape(1) != counts.shape(1))
        throw py::value_error("resolve_image needs sums [H, W, 3], counts [H, W] and alpha_sums [H, W]");
    py::array_t<float> out({counts.shape(0), counts.shape(1), py::ssize_t(4)});
    render::ResolveImage(sums.data(), counts.data(), alpha_sums.data(), film_alpha, size_t(counts.size()),
                         out.mutable_data());
    return out;
}

py::dict Stats(const Renderer& r, int k) {
    const render::TechniqueStats s = r.Stats(k);
    py::dict d;
    d["samples"] = s.samples;
    d["wall_time"] = s.wall_time;
    d["light_time"] = s.light_time;
    d["shading_time"] = s.shading_time;
    d["camera_time"] = s.camera_time;
    d["tile_time"] = s.tile_time;
    d["trace_time"] = s.trace_time;
    d["camera_trace_time"] = s.camera_trace_time;
    d["rays"] = s.rays;
    d["camera_rays"] = s.camera_rays;
    d["surface_hits"] = s.surface_hits;
    d["dropped_samples"] = s.dropped_samples;
    return d;
}

}  // namespace

// The camera's keyword arguments, the same for the scene's and the renderer's set_camera.
#define CAMERA_ARGS                                                                                             \
    py::arg("width"), py::arg("height"), py::arg("to_world"), py::arg("orthographic"), py::arg("half_width"),   \
        py::arg("half_height"), py::arg("offset_x"), py::arg("offset_y"), py::arg("aperture_radius"),           \
        py::arg("focus_distance"), py::arg("clip_start"), py::arg("clip_end"), py::arg("pixel_filter") = "box", \
                                                                               py::arg("filter_width") = 1.0f

// RenderOptions' defaults by the names sphrect.Renderer's keywords have (memory_limit 0: None, the machine's).
py::dict RenderDefaults() {
    const render::RenderOptions o;
    py::list techniques;
    for (Technique t : o.techniques) techniques.append(TechniqueName(t));
    py::dict d;
    d["techniques"] = py::tuple(techniques);
    d["light_samples"] = o.light_samples;
    d["pattern"] = PatternName(o.pattern);
    d["mis"] = render::MisModeName(o.mis);
    d["seed"] = o.seed;
    d["threads"] = o.threads;
    d["medium_sampling"] = render::MediumSamplingName(o.medium_sampling);
    d["tile_size"] = o.tile_size;
    d["light_selection"] = render::LightSelectionName(o.light_selection);
    d["ris_candidates"] = o.ris_candidates;
    d["ellipse_technique"] = EllipseTechniqueName(o.ellipse_technique);
    d["analytic_light_coverage"] = o.analytic_light_coverage;
    d["bsdf_samples_on_diffuse"] = o.bsdf_samples_on_diffuse;
    d["emission_blocks"] = o.emission_blocks;
    d["added_shading_cost"] = o.added_shading_cost;
    d["added_ray_cost"] = o.added_ray_cost;
    d["memory_limit"] = o.memory_limit ? py::object(py::int_(o.memory_limit)) : py::object(py::none());
    return d;
}

void BindRender(py::module_& m) {
    auto names = [](const auto& list) {
        py::tuple t(std::size(list));
        for (size_t i = 0; i < std::size(list); ++i) t[i] = list[i];
        return t;
    };
    m.def(
        "texture_scalar_mean",
        [](const py::array& pixels, bool srgb, bool alpha_output) {
            return render::ImageScalarMean(ImageOfArray("pixels", pixels, srgb, true), alpha_output);
        },
        py::arg("pixels"), py::arg("srgb"), py::arg("alpha_output"),
        "Mean over an image's texels ([H, W, C] uint8 or float32) of the scalar a material input reads there (the "
        "decoded colour's Rec.709 luminance, or the alpha), each clamped to [0, 1] as a Mix factor is.");
    m.def(
        "texture_color_mean",
        [](const py::array& pixels, bool srgb) {
            const Spectrum c = render::ImageColorMean(ImageOfArray("pixels", pixels, srgb, true));
            return py::make_tuple(c.x, c.y, c.z);
        },
        py::arg("pixels"), py::arg("srgb"),
        "Mean over an image's texels ([H, W, C] uint8 or float32) of the decoded colour (r, g, b), as a material's "
        "Color input reads it.");
    m.def(
        "_eval_node_program",
        [](const py::handle& program, const V3& p, const V3& uv, const V3& generated, const std::optional<V3>& object,
           const std::vector<std::pair<py::array, bool>>& textures, float ray_length, float dP,
           const std::optional<std::vector<std::array<V3, 4>>>& shifts, const std::string& ray, int transparent_depth,
           const std::vector<std::pair<py::array, bool>>& attributes, const std::array<uint32_t, 3>& vertices,
           const std::array<float, 3>& barycentrics, const std::optional<std::array<float, 9>>& object_info,
           const V3& normal, bool corners_reversed) {
            const render::svm::NodeProgram prog = ProgramFromFields(program, "program");
            std::vector<render::Image> images;
            for (const auto& [pixels, srgb] : textures) images.push_back(ImageOfArray("texture", pixels, srgb, true));
            render::svm::CheckNodeProgram(prog, images.size());
            render::svm::ShaderGlobals sg;
            sg.p = sg.object = {p[0], p[1], p[2]};
            if (object) sg.object = {(*object)[0], (*object)[1], (*object)[2]};
            sg.uv = {uv[0], uv[1], uv[2]};
            sg.generated = {generated[0], generated[1], generated[2]};
            sg.incoming = sg.object_normal = {0, 0, 1};
            sg.n = sg.ng = {normal[0], normal[1], normal[2]};
            sg.ray_length = ray_length;
            sg.dP = dP;
            if (shifts) {  // (p, uv, generated, object) at P + dx and P + dy
                if (shifts->size() != 2) throw py::value_error("shifts: two (p, uv, generated, object) expected");
                auto v3 = [](const V3& v) { return Vec3f(v[0], v[1], v[2]); };
                for (size_t k = 0; k < 2; ++k) {
                    const auto& s = (*shifts)[k];
                    sg.shift[k] = {v3(s[0]), v3(s[1]), v3(s[2]), v3(s[3])};
                }
                sg.shifted = true;
            }
            std::vector<render::svm::MeshAttribute> attrs;
            for (const auto& [values, fac_is_x] : attributes) {
                const auto a = CArray<float>::ensure(values);
                if (!a || a.ndim() != 2 || a.shape(1) != 4) throw py::value_error("attributes must be [V, 4] arrays");
                for (uint32_t v : vertices)  // an empty array: the mesh lacks it
                    if (a.shape(0) > 0 && v >= a.shape(0))
                        throw py::value_error("a vertex index is out of an attribute's range");
                attrs.push_back({std::vector<float>(a.data(), a.data() + a.size()), fac_is_x});
            }
            sg.attributes = &attrs;
            for (int k = 0; k < 3; ++k) sg.v[k] = vertices[k], sg.b[k] = barycentrics[k];
            render::svm::ObjectInfo info;
            if (object_info) {
                const auto& o = *object_info;
                info.location = {o[0], o[1], o[2]};
                info.color = {o[3], o[4], o[5]};
                info.alpha = o[6], info.index = o[7], info.random = o[8];
            }
            info.reversed = corners_reversed;
            if (object_info || corners_reversed) sg.object_info = &info;
            sg.ray = RayContextNamed(ray, transparent_depth);
            const Spectrum v = render::svm::EvalNodeProgram(prog, images, sg);
            return V3{v.x, v.y, v.z};
        },
        py::arg("program"), py::arg("p"), py::arg("uv"), py::arg("generated"), py::arg("object") = py::none(),
        py::arg("textures") = std::vector<std::pair<py::array, bool>>{}, py::arg("ray_length") = 0.0f,
        py::arg("dP") = 0.0f, py::arg("shifts") = py::none(), py::arg("ray") = "camera",
        py::arg("transparent_depth") = 0, py::arg("attributes") = std::vector<std::pair<py::array, bool>>{},
        py::arg("vertices") = std::array<uint32_t, 3>{0, 0, 0}, py::arg("barycentrics") = std::array<float, 3>{1, 0, 0},
        py::arg("object_info") = py::none(), py::arg("normal") = V3{0, 0, 1}, py::arg("corners_reversed") = false,
        "A node program at point p of a plane facing +z seen from +z (object coordinates: p unless given; textures: "
        "(pixels, srgb) of the scene's, as Texture holds them; the ray's length; a Bump's ray differential dP and "
        "shifted inputs (p, uv, generated, object) at P + dx and P + dy; the Light Path node's ray: 'camera', "
        "'light_sample', 'shadow', or a BSDF / phase ray's kinds joined by '+', e.g. 'diffuse+transmission', after "
        "transparent_depth transparent surfaces; mesh attributes ([V, 4] values, "
        "[0, 4]: missing, fac_is_x) by slot at `barycentrics` of triangle `vertices`; object_info: location, colour, "
        "alpha, index, random; the shading normal; whether the mesh's corners are reversed): for tests "
        "and the exporter's constants");
    // Cycles' sync-time mesh attributes and object random numbers (render/svm/standard_attributes.h), for the exporter.
    m.def(
        "_pointiness",
        [](const py::object& positions, const py::object& normals, const py::object& edges) {
            const auto p = RowsOf<float>(positions, 3, "positions");
            const auto n = RowsOf<float>(normals, 3, "normals");
            const auto e = RowsOf<int32_t>(edges, 2, "edges");
            if (n.shape(0) != p.shape(0)) throw py::value_error("normals must match the positions");
            std::vector<Vec3f> pv(size_t(p.shape(0))), nv(pv.size());
            for (size_t i = 0; i < pv.size(); ++i) {
                pv[i] = {p.at(i, 0), p.at(i, 1), p.at(i, 2)};
                nv[i] = {n.at(i, 0), n.at(i, 1), n.at(i, 2)};
            }
            std::vector<uint32_t> ev(size_t(e.size()));
            for (size_t i = 0; i < ev.size(); ++i) {
                if (e.data()[i] < 0 || size_t(e.data()[i]) >= pv.size()) throw py::value_error("edge out of range");
                ev[i] = uint32_t(e.data()[i]);
            }
            return render::svm::Pointiness(pv, nv, ev);
        },
        py::arg("positions"), py::arg("normals"), py::arg("edges"),
        "Cycles' Pointiness per vertex of a mesh (positions, vertex normals, edges as vertex pairs).");
    m.def(
        "_random_per_island",
        [](size_t num_vertices, const py::object& edges) {
            const auto e = RowsOf<int32_t>(edges, 2, "edges");
            std::vector<uint32_t> ev(size_t(e.size()));
            for (size_t i = 0; i < ev.size(); ++i) {
                if (e.data()[i] < 0 || size_t(e.data()[i]) >= num_vertices) throw py::value_error("edge out of range");
                ev[i] = uint32_t(e.data()[i]);
            }
            return render::svm::RandomPerIsland(num_vertices, ev);
        },
        py::arg("num_vertices"), py::arg("edges"), "Cycles' Random Per Island per vertex of a mesh.");
    m.def(
        "_object_random",
        [](const std::string& name, std::optional<int64_t> random_id) {
            return random_id ? render::svm::ObjectIdRandom(uint32_t(uint64_t(*random_id) & 0xFFFFFFFFu))
                             : render::svm::ObjectNameRandom(name);
        },
        py::arg("name"), py::arg("random_id") = py::none(),
        "Object Info > Random as Cycles gives it: from an instance's random_id, else hashed from the object's name.");
    m.attr("textured_inputs") = names(render::kTexturedInputNames);
    m.attr("texture_interpolations") = names(render::kTextureInterpolationNames);
    m.attr("texture_extensions") = names(render::kTextureExtensionNames);
    m.attr("pixel_filters") = names(render::kPixelFilterNames);
    m.attr("MIN_PIXEL_FILTER_WIDTH") = render::kMinPixelFilterWidth;
    m.attr("MAX_PIXEL_FILTER_WIDTH") = render::kMaxPixelFilterWidth;
    m.attr("MIN_AREA_SPREAD") = render::kMinAreaSpread;
    m.def(
        "area_spread_factors",
        [](float spread) {
            render::AreaLight l;
            render::SetAreaSpread(l, spread);
            return py::make_tuple(l.spread_cot, l.spread_normalization);
        },
        py::arg("spread"),
        "(spread_cot, normalization) of an area light's spread as Cycles 3.4 sets them up (render/area_light.h)");
    py::class_<RenderScene, std::shared_ptr<RenderScene>>(
        m, "_Scene", "Native scene; built by sphrect.Renderer from a sphrect.Scene")
        .def(py::init<>())
        .def("set_camera", &SetCamera<RenderScene>, CAMERA_ARGS)
        .def("set_background", [](RenderScene& s, V3 c) { s.SetBackground(ToVec(c)); })
        .def(
            "set_world_visibility",
            [](RenderScene& s, const std::vector<std::string>& invisible_to) {
                s.SetWorldVisibility(LightVisibilityOf(invisible_to, true, true));
            },
            py::arg("invisible_to"))
        .def("set_medium", [](RenderScene& s, V3 ss, V3 sa, float g) { s.SetMedium(ToVec(ss), ToVec(sa), g); })
        .def(
            "add_material",
            [](RenderScene& s, const py::handle& fields) { return s.AddMaterial(MaterialFromFields(fields)); },
            py::arg("fields"), "Adds a sphrect.Material given as dataclasses.asdict(material); returns its index")
        .def("set_film_transparent", &RenderScene::SetFilmTransparent, py::arg("transparent"))
        .def("set_environment", EnvironmentSetter(&RenderScene::SetEnvironment, "world environment"),
             py::arg("texture"), py::arg("strength"), py::arg("to_world"), py::arg("interpolation"),
             "The image world (sphrect.Environment): an image added before, which replaces the background")
        .def("set_camera_environment",
             EnvironmentSetter(&RenderScene::SetCameraEnvironment, "world camera environment"), py::arg("texture"),
             py::arg("strength"), py::arg("to_world"), py::arg("interpolation"),
             "What escaping camera rays see instead (World.camera_environment): an image added before")
        .def("add_image", &AddImage, py::arg("name"), py::arg("pixels"), py::arg("srgb"))
        .def("load_image", &RenderScene::LoadImage, py::arg("name"), py::arg("path"), py::arg("srgb"),
             py::call_guard<py::gil_scoped_release>())
        .def("set_image_memory_limit", &RenderScene::SetImageMemoryLimit, py::arg("bytes"))
        .def_property_readonly("image_memory_bytes", &RenderScene::ImageMemoryBytes)
        .def(
            "set_last_light_texture",
            [](RenderScene& s, const py::handle& fields) {
                s.SetLastLightTexture(LookupFromFields(fields, "a light's texture"));
            },
            py::arg("lookup"))
        .def(
            "set_last_mesh_attribute",
            [](RenderScene& s, size_t slot, const py::object& values, bool fac_is_x) {
                const auto a = CArray<float>::ensure(values);
                if (!a || a.ndim() != 2 || a.shape(1) != 4)
                    throw py::value_error("a mesh attribute must be a [V, 4] float array");
                s.SetLastMeshAttribute(slot, std::vector<float>(a.data(), a.data() + a.size()), fac_is_x);
            },
            py::arg("slot"), py::arg("values"), py::arg("fac_is_x") = false)
        .def(
            "set_last_mesh_object_info",
            [](RenderScene& s, const V3& color, float alpha, float index, float random, bool reversed) {
                s.SetLastMeshObjectInfo(Spectrum(color[0], color[1], color[2]), alpha, index, random, reversed);
            },
            py::arg("color"), py::arg("alpha"), py::arg("index"), py::arg("random"), py::arg("reversed") = false)
        .def("set_last_mesh_shadow_terminator_offset", &RenderScene::SetLastMeshShadowTerminatorOffset,
             py::arg("offset"))
        .def(
            "set_last_mesh_object_linear",
            [](RenderScene& s, const py::object& linear, const py::object& inverse,
               const std::array<double, 3>& translation) {
                float l[3][3], li[3][3];
                for (auto [obj, out] : {std::pair{&linear, &l}, std::pair{&inverse, &li}}) {
                    const auto a = CArray<double>::ensure(*obj);
                    if (!a || a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3)
                        throw py::value_error("object_linear must be a 3x3 matrix");
                    for (int r = 0; r < 3; ++r)
                        for (int c = 0; c < 3; ++c) (*out)[r][c] = float(a.at(r, c));
                }
                s.SetLastMeshObjectLinear(
                    l, li, Spectrum(float(translation[0]), float(translation[1]), float(translation[2])));
            },
            py::arg("linear"), py::arg("inverse"), py::arg("translation") = std::array<double, 3>{0, 0, 0})

        .def("add_volume", &AddVolume, py::arg("name"), py::arg("vertices"), py::arg("triangles"), py::arg("sigma_s"),
             py::arg("sigma_a"), py::arg("g"),
             "A homogeneous medium bounded by the closed mesh (sphrect.Volume): vertices [N, 3], triangles [M, 3] "
             "counter-clockwise seen from outside")
        .def("add_mesh", &AddMesh, py::arg("name"), py::arg("vertices"), py::arg("triangles"),
             py::arg("normals") = py::none(), py::arg("material_ids") = py::none(), py::arg("uvs") = py::none(),
             py::arg("generated") = py::none(), py::arg("invisible_to") = std::vector<std::string>{})
        // Every light: invisible_to, cast_shadow, use_mis (LightVisibilityOf).
        .def(
            "add_rect_light",
            [](RenderScene& s, V3 corner, V3 ex, V3 ey, V3 radiance, bool two_sided, bool visible, float spread,
               const std::vector<std::string>& invisible_to, bool cast_shadow, bool use_mis) {
                const auto vis = LightVisibilityOf(invisible_to, cast_shadow, use_mis);
                return s.AddRectLight(ToVec(corner), ToVec(ex), ToVec(ey), ToVec(radiance), two_sided,
                                      visible && (vis.rays() & render::kRayCamera), spread, vis);
            },
            py::arg("corner"), py::arg("edge_x"), py::arg("edge_y"), py::arg("radiance"), py::arg("two_sided"),
            py::arg("visible"), py::arg("spread"), py::arg("invisible_to") = std::vector<std::string>{},
            py::arg("cast_shadow") = true, py::arg("use_mis") = true)
        .def(
            "add_ellipse_light",
            [](RenderScene& s, V3 center, V3 ax, V3 ay, V3 radiance, bool two_sided, bool visible, float spread,
               const std::vector<std::string>& invisible_to, bool cast_shadow, bool use_mis) {
                const auto vis = LightVisibilityOf(invisible_to, cast_shadow, use_mis);
                return s.AddEllipseLight(ToVec(center), ToVec(ax), ToVec(ay), ToVec(radiance), two_sided,
                                         visible && (vis.rays() & render::kRayCamera), spread, vis);
            },
            py::arg("center"), py::arg("axis_x"), py::arg("axis_y"), py::arg("radiance"), py::arg("two_sided"),
            py::arg("visible"), py::arg("spread"), py::arg("invisible_to") = std::vector<std::string>{},
            py::arg("cast_shadow") = true, py::arg("use_mis") = true)
        .def(
            "add_point_light",
            [](RenderScene& s, V3 p, V3 i, float radius, bool visible, const std::vector<std::string>& invisible_to,
               bool cast_shadow, bool use_mis) {
                const auto vis = LightVisibilityOf(invisible_to, cast_shadow, use_mis);
                s.AddPointLight(ToVec(p), ToVec(i), radius, visible && (vis.rays() & render::kRayCamera), vis);
            },
            py::arg("position"), py::arg("intensity"), py::arg("radius") = 0.0f, py::arg("visible") = true,
            py::arg("invisible_to") = std::vector<std::string>{}, py::arg("cast_shadow") = true,
            py::arg("use_mis") = true)
        .def(
            "add_spot_light",
            [](RenderScene& s, V3 p, V3 d, V3 i, float size, float blend, float radius, bool visible,
               const std::vector<std::string>& invisible_to, bool cast_shadow, bool use_mis) {
                const auto vis = LightVisibilityOf(invisible_to, cast_shadow, use_mis);
                s.AddSpotLight(ToVec(p), ToVec(d), ToVec(i), size, blend, radius,
                               visible && (vis.rays() & render::kRayCamera), vis);
            },
            py::arg("position"), py::arg("direction"), py::arg("intensity"), py::arg("spot_size"),
            py::arg("spot_blend"), py::arg("radius") = 0.0f, py::arg("visible") = true,
            py::arg("invisible_to") = std::vector<std::string>{}, py::arg("cast_shadow") = true,
            py::arg("use_mis") = true)
        .def(
            "add_sun_light",
            [](RenderScene& s, V3 d, V3 e, float angle, bool visible, const std::vector<std::string>& invisible_to,
               bool cast_shadow, bool use_mis) {
                const auto vis = LightVisibilityOf(invisible_to, cast_shadow, use_mis);
                s.AddSunLight(ToVec(d), ToVec(e), angle, visible && (vis.rays() & render::kRayCamera), vis);
            },
            py::arg("direction"), py::arg("irradiance"), py::arg("angle") = 0.0f, py::arg("visible") = true,
            py::arg("invisible_to") = std::vector<std::string>{}, py::arg("cast_shadow") = true,
            py::arg("use_mis") = true)
        .def("commit", &RenderScene::Commit, py::call_guard<py::gil_scoped_release>())
        .def_property_readonly("features", [](const RenderScene& s) { return s.features().Names(); })
        .def_property_readonly("warnings", [](const RenderScene& s) { return s.warnings; })
        .def_property_readonly("num_area_lights", [](const RenderScene& s) { return s.area_lights.size(); })
        .def_property_readonly(
            "area_light_radiance",
            [](const RenderScene& s) {
                std::vector<V3> out;
                for (const auto& l : s.area_lights) out.push_back({l.radiance.x, l.radiance.y, l.radiance.z});
                return out;
            },
            "The radiance light selection weighs each area light by (a textured emitter's mean over its points and, "
            "for a node program's, the directions it is seen from)")
        .def_property_readonly("num_triangles", &RenderScene::NumTriangles);

    py::class_<EnvironmentSampler>(m, "EnvironmentSampler",
                                   "An image world's radiance and importance sampling (render/environment_light.h), "
                                   "for tests: pixels [H, W, C] floats, rows bottom to top")
        .def(py::init(&MakeEnvironmentSampler), py::arg("pixels"), py::arg("to_world") = py::none(),
             py::arg("strength") = V3{1, 1, 1}, py::arg("interpolation") = "linear")
        .def(
            "sample",
            [](const EnvironmentSampler& s, const py::object& u) {
                const auto a = RowsOf<float>(u, 2, "u");
                py::array_t<double> dirs({a.shape(0), py::ssize_t(3)}), pdf(a.shape(0));
                auto d = dirs.mutable_unchecked<2>();
                auto p = pdf.mutable_unchecked<1>();
                for (py::ssize_t i = 0; i < a.shape(0); ++i) {
                    const render::EnvironmentSample e = render::SampleEnvironment(s.light, {a.at(i, 0), a.at(i, 1)});
                    d(i, 0) = e.wi.x, d(i, 1) = e.wi.y, d(i, 2) = e.wi.z, p(i) = e.pdf;
                }
                return py::make_tuple(dirs, pdf);
            },
            py::arg("u"), "(directions [N, 3], solid-angle pdfs [N]) of SampleEnvironment at the points u [N, 2]")
        .def(
            "pdf",
            [](const EnvironmentSampler& s, const py::object& dirs) {
                return PerDirection(dirs, 1, [&](Vec3f w, double* o) { o[0] = render::EnvironmentPDF(s.light, w); });
            },
            py::arg("directions"), "EnvironmentPDF (per steradian) of unit directions [N, 3], as [N, 1]")
        .def(
            "invert",
            [](const EnvironmentSampler& s, const py::object& dirs) {
                return PerDirection(dirs, 2, [&](Vec3f w, double* o) {
                    const Point2<float> u = render::InvertEnvironmentSample(s.light, w);
                    o[0] = u.u, o[1] = u.v;
                });
            },
            py::arg("directions"), "InvertEnvironmentSample of unit directions [N, 3]: the points u [N, 2]")
        .def(
            "radiance",
            [](const EnvironmentSampler& s, const py::object& dirs) {
                return PerDirection(dirs, 3, [&](Vec3f w, double* o) {
                    const Spectrum c = render::EnvironmentRadiance(s.light, s.image, w);
                    o[0] = c.x, o[1] = c.y, o[2] = c.z;
                });
            },
            py::arg("directions"), "EnvironmentRadiance of unit directions [N, 3], as [N, 3] RGB");

    py::class_<Renderer>(m, "_Renderer", "Native renderer; use sphrect.Renderer")
        .def(py::init(&MakeRenderer), py::arg("scene"), py::arg("techniques"), py::arg("light_samples"),
             py::arg("pattern"), py::arg("mis"), py::arg("medium_sampling"), py::arg("light_selection"),
             py::arg("ellipse_technique"), py::arg("seed"), py::arg("threads"), py::arg("tile_size"),
             py::arg("analytic_light_coverage"), py::arg("bsdf_samples_on_diffuse"), py::arg("memory_limit"),
             py::arg("emission_blocks") = render::RenderOptions{}.emission_blocks, py::arg("added_shading_cost") = 0.0,
             py::arg("added_ray_cost") = 0.0, py::arg("ris_candidates") = render::RenderOptions{}.ris_candidates)
        .def("render", &Render, py::arg("samples"), py::arg("time_budget"), py::arg("progress"))
        .def("cancel", &Renderer::Cancel)
        .def("set_camera", &SetCamera<Renderer>, CAMERA_ARGS)
        .def("image", &Image)
        .def("stats", &Stats)
        .def("start_at", &Renderer::StartAt, py::arg("first_sample"), py::arg("pass_index"))
        .def("sums",
             [](const Renderer& r, int k) {
                 const auto lock = r.ReadLock();
                 return BufferArray(r.Sums(k), {r.height(), r.width(), 3});
             })
        .def("counts",
             [](const Renderer& r) {
                 const auto lock = r.ReadLock();
                 return BufferArray(r.Counts(), {r.height(), r.width()});
             })
        .def("alpha_sums",
             [](const Renderer& r) {
                 const auto lock = r.ReadLock();
                 return BufferArray(r.AlphaSums(), {r.height(), r.width()});
             })
        .def_property_readonly("film_alpha", &Renderer::FilmAlpha)
        .def_property_readonly("features", &Renderer::Features)
        .def_property_readonly("width", &Renderer::width)
        .def_property_readonly("height", &Renderer::height);
    m.def("resolve_image", &ResolveImageArray, py::arg("sums"), py::arg("counts"), py::arg("alpha_sums"),
          py::arg("film_alpha"), "RGBA float32 [H, W, 4] from accumulation buffers, exactly as a Renderer's image()");
    m.attr("SAMPLE_INDEX_LIMIT") = render::kSampleIndexLimit;
    m.attr("MAX_LIGHT_SAMPLES") = render::kMaxLightSamples;
    m.attr("MAX_RIS_CANDIDATES") = render::kMaxRisCandidates;
    m.def("_render_defaults", &RenderDefaults, "sphrect.RENDER_DEFAULTS: render/options.h RenderOptions' defaults");
    m.attr("MAX_THREADS") = render::kMaxThreads;
    m.def("default_memory_limit", &render::DefaultMemoryLimit,
          "Bytes a Renderer's images may take by default: half the physical memory");
    m.def(
        "render_memory_bytes",
        [](int techniques, int width, int height) {
            render::RenderOptions o;
            o.techniques.assign(size_t(std::max(techniques, 0)), Technique::Rectangle);
            return render::RenderMemoryBytes(o, width, height);
        },
        py::arg("techniques"), py::arg("width"), py::arg("height"),
        "Bytes the images of a Renderer with `techniques` techniques at width x height take");
    m.def(
        "check_render_memory",
        [](int techniques, int width, int height, uint64_t memory_limit) {
            render::RenderOptions o;
            o.techniques.assign(size_t(std::max(techniques, 0)), Technique::Rectangle);
            o.memory_limit = memory_limit;
            render::CheckRenderMemory(o, width, height);
        },
        py::arg("techniques"), py::arg("width"), py::arg("height"), py::arg("memory_limit"),
        "ValueError if those images would take more than memory_limit bytes (0: default_memory_limit())");
    m.attr("MAX_SAMPLES_PER_CALL") = render::kMaxSamplesPerCall;
    m.attr("MAX_IMAGE_SIDE") = render::kMaxImageSide;
    m.attr("MAX_LIGHT_TREE_EMITTERS") = render::kMaxLightTreeEmitters;
    m.attr("MAX_DELTA_LIGHTS_BESIDE_TREE") = render::kMaxDeltaLightsBesideTree;
    m.attr("TREE_FLUX_SHARE") = render::kTreeFluxShare;
    m.attr("MAX_MIX_GLOSSY_LOBES") = render::kMaxMicrofacetLobes;
    m.attr("MAX_TRANSPARENT_HITS") = render::kMaxTransparentHits;
    m.attr("mis_modes") = NameTuple(render::kAllMisModes, render::MisModeName);
    m.attr("medium_samplings") = NameTuple(render::kAllMediumSamplings, render::MediumSamplingName);
    m.attr("light_selections") = NameTuple(render::kAllLightSelections, render::LightSelectionName);
    m.attr("ray_kinds") = NameTuple(render::kRayKindNames, [](const char* n) { return n; });
}

#undef CAMERA_ARGS

}  // namespace sphrect::python
