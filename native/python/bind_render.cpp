// Bindings of the renderer: `_native._Scene` (built by python/sphrect/render.py from a
// sphrect.Scene) and `_native._Renderer`.  The Python-facing API is sphrect.Renderer.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "name_tuple.h"
#include "numpy_arrays.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace py = pybind11;

namespace sphrect::python {

// bind_material.cpp: a sphrect.Material (its dataclasses.asdict fields) as the renderer takes it.
render::Material MaterialFromFields(const py::handle& fields);

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

void AddMesh(RenderScene& s, const std::string& name, const py::object& vertices, const py::object& triangles,
             const py::object& normals, const py::object& material_ids, const py::object& uvs,
             const py::object& generated) {
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
              generated.is_none() ? nullptr : gen.data());
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
                                       uint64_t memory_limit, bool emission_blocks) {
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
    d["rays"] = s.rays;
    d["camera_rays"] = s.camera_rays;
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
    d["ellipse_technique"] = EllipseTechniqueName(o.ellipse_technique);
    d["analytic_light_coverage"] = o.analytic_light_coverage;
    d["bsdf_samples_on_diffuse"] = o.bsdf_samples_on_diffuse;
    d["emission_blocks"] = o.emission_blocks;
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
        .def("set_medium", [](RenderScene& s, V3 ss, V3 sa, float g) { s.SetMedium(ToVec(ss), ToVec(sa), g); })
        .def(
            "add_material",
            [](RenderScene& s, const py::handle& fields) { return s.AddMaterial(MaterialFromFields(fields)); },
            py::arg("fields"), "Adds a sphrect.Material given as dataclasses.asdict(material); returns its index")
        .def("set_film_transparent", &RenderScene::SetFilmTransparent, py::arg("transparent"))
        .def("add_image", &AddImage, py::arg("name"), py::arg("pixels"), py::arg("srgb"))
        .def("load_image", &RenderScene::LoadImage, py::arg("name"), py::arg("path"), py::arg("srgb"),
             py::call_guard<py::gil_scoped_release>())
        .def("set_image_memory_limit", &RenderScene::SetImageMemoryLimit, py::arg("bytes"))
        .def_property_readonly("image_memory_bytes", &RenderScene::ImageMemoryBytes)
        .def(
            "set_last_mesh_object_linear",
            [](RenderScene& s, const py::object& linear, const py::object& inverse) {
                float l[3][3], li[3][3];
                for (auto [obj, out] : {std::pair{&linear, &l}, std::pair{&inverse, &li}}) {
                    const auto a = CArray<double>::ensure(*obj);
                    if (!a || a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3)
                        throw py::value_error("object_linear must be a 3x3 matrix");
                    for (int r = 0; r < 3; ++r)
                        for (int c = 0; c < 3; ++c) (*out)[r][c] = float(a.at(r, c));
                }
                s.SetLastMeshObjectLinear(l, li);
            },
            py::arg("linear"), py::arg("inverse"))

        .def("add_mesh", &AddMesh, py::arg("name"), py::arg("vertices"), py::arg("triangles"),
             py::arg("normals") = py::none(), py::arg("material_ids") = py::none(), py::arg("uvs") = py::none(),
             py::arg("generated") = py::none())
        .def("add_rect_light",
             [](RenderScene& s, V3 corner, V3 ex, V3 ey, V3 radiance, bool two_sided, bool visible, float spread) {
                 return s.AddRectLight(ToVec(corner), ToVec(ex), ToVec(ey), ToVec(radiance), two_sided, visible,
                                       spread);
             })
        .def("add_ellipse_light",
             [](RenderScene& s, V3 center, V3 ax, V3 ay, V3 radiance, bool two_sided, bool visible, float spread) {
                 return s.AddEllipseLight(ToVec(center), ToVec(ax), ToVec(ay), ToVec(radiance), two_sided, visible,
                                          spread);
             })
        .def(
            "add_point_light",
            [](RenderScene& s, V3 p, V3 i, float radius, bool visible) {
                s.AddPointLight(ToVec(p), ToVec(i), radius, visible);
            },
            py::arg("position"), py::arg("intensity"), py::arg("radius") = 0.0f, py::arg("visible") = true)
        .def(
            "add_spot_light",
            [](RenderScene& s, V3 p, V3 d, V3 i, float size, float blend, float radius, bool visible) {
                s.AddSpotLight(ToVec(p), ToVec(d), ToVec(i), size, blend, radius, visible);
            },
            py::arg("position"), py::arg("direction"), py::arg("intensity"), py::arg("spot_size"),
            py::arg("spot_blend"), py::arg("radius") = 0.0f, py::arg("visible") = true)
        .def(
            "add_sun_light",
            [](RenderScene& s, V3 d, V3 e, float angle, bool visible) {
                s.AddSunLight(ToVec(d), ToVec(e), angle, visible);
            },
            py::arg("direction"), py::arg("irradiance"), py::arg("angle") = 0.0f, py::arg("visible") = true)
        .def("commit", &RenderScene::Commit, py::call_guard<py::gil_scoped_release>())
        .def_property_readonly("features", [](const RenderScene& s) { return s.features().Names(); })
        .def_property_readonly("warnings", [](const RenderScene& s) { return s.warnings; })
        .def_property_readonly("num_area_lights", [](const RenderScene& s) { return s.area_lights.size(); })
        .def_property_readonly("num_triangles", &RenderScene::NumTriangles);

    py::class_<Renderer>(m, "_Renderer", "Native renderer; use sphrect.Renderer")
        .def(py::init(&MakeRenderer), py::arg("scene"), py::arg("techniques"), py::arg("light_samples"),
             py::arg("pattern"), py::arg("mis"), py::arg("medium_sampling"), py::arg("light_selection"),
             py::arg("ellipse_technique"), py::arg("seed"), py::arg("threads"), py::arg("tile_size"),
             py::arg("analytic_light_coverage"), py::arg("bsdf_samples_on_diffuse"), py::arg("memory_limit"),
             py::arg("emission_blocks") = render::RenderOptions{}.emission_blocks)
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
    m.attr("MAX_MIX_GLOSSY_LOBES") = render::kMaxMicrofacetLobes;
    m.attr("MAX_TRANSPARENT_HITS") = render::kMaxTransparentHits;
    m.attr("mis_modes") = NameTuple(render::kAllMisModes, render::MisModeName);
    m.attr("medium_samplings") = NameTuple(render::kAllMediumSamplings, render::MediumSamplingName);
    m.attr("light_selections") = NameTuple(render::kAllLightSelections, render::LightSelectionName);
}

#undef CAMERA_ARGS

}  // namespace sphrect::python
