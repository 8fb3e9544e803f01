// sphrect._native.procedural_texture: Cycles' procedural texture nodes (render/svm/procedural_textures.h)
// evaluated at an array of texture-space points, for tests and the exporter's checks against Cycles.
//   procedural_texture("voronoi", points, w=None, dimensions=3, feature="f2", scale=4.0) -> {"distance": ..., ...}
// Settings are keyword arguments named as the params structs' fields; enums by name (Blender's identifiers in
// lower case); unknown or ill-typed settings raise ValueError naming the valid ones.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <set>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "numpy_arrays.h"
#include "render/svm/procedural_textures.h"

namespace py = pybind11;

namespace sphrect::python {

namespace {

namespace svm = render::svm;

std::string Repr(const py::handle& h) { return py::repr(h).cast<std::string>(); }

// Reads a node's settings from the keyword arguments, remembering which it knows so that Finish can reject the rest.
class SettingsReader {
  public:
    SettingsReader(std::string node, const py::kwargs& kwargs) : node_(std::move(node)), kwargs_(kwargs) {}

    void Float(const char* name, float* out) {
        known_.push_back(name);
        if (!kwargs_.contains(name)) return;
        const py::handle v = kwargs_[name];
        if (py::isinstance<py::bool_>(v) ||
            !(py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v) || py::hasattr(v, "__float__")))
            throw py::value_error(Where(name) + " must be a number, got " + Repr(v));
        *out = float(v.cast<double>());
    }
    void Int(const char* name, int* out, int lo, int hi) {
        known_.push_back(name);
        if (!kwargs_.contains(name)) return;
        const py::handle v = kwargs_[name];
        if (py::isinstance<py::bool_>(v) || !py::isinstance<py::int_>(v))
            throw py::value_error(Where(name) + " must be an integer, got " + Repr(v));
        const long long i = v.cast<long long>();
        if (i < lo || i > hi)
            throw py::value_error(Where(name) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                  "], got " + std::to_string(i));
        *out = int(i);
    }
    void Color(const char* name, Vec3f* out) {
        known_.push_back(name);
        if (!kwargs_.contains(name)) return;
        const py::handle v = kwargs_[name];
        try {
            const auto c = v.cast<std::vector<double>>();
            if (c.size() == 3) {
                *out = {float(c[0]), float(c[1]), float(c[2])};
                return;
            }
        } catch (const py::cast_error&) {
        }
        throw py::value_error(Where(name) + " must be three numbers, got " + Repr(v));
    }
    template <class E, size_t N>
    void Enum(const char* name, E* out, const char* const (&names)[N]) {
        known_.push_back(name);
        if (!kwargs_.contains(name)) return;
        const py::handle v = kwargs_[name];
        if (!py::isinstance<py::str>(v)) throw py::value_error(Where(name) + " must be a name, got " + Repr(v));
        *out = ParseNameOrThrow<E>(Where(name), std::string(name) + "s", v.cast<std::string>(), names);
    }
    void Dimensions(int* out) { Int("dimensions", out, 1, 4); }

    // ValueError for a setting this node does not have.
    void Finish() const {
        const std::set<std::string> known(known_.begin(), known_.end());
        for (const auto& item : kwargs_) {
            const std::string key = item.first.cast<std::string>();
            if (!known.count(key)) {
                std::string valid;
                for (const auto& k : known_) valid += (valid.empty() ? "'" : ", '") + k + "'";
                throw py::value_error("unknown " + node_ + " setting '" + key + "'; valid settings: " + valid);
            }
        }
    }

  private:
    std::string Where(const char* name) const { return node_ + " " + name; }
    std::string node_;
    const py::kwargs& kwargs_;
    std::vector<std::string> known_;
};

// The outputs being filled: float32 arrays of N values or N x 3 colours, by output name.
class Outputs {
  public:
    explicit Outputs(py::ssize_t n) : n_(n) {}
    float* Scalar(const char* name) {
        py::array_t<float> a(n_);
        dict_[name] = a;
        return a.mutable_data();
    }
    Vec3f* Vector(const char* name) {
        py::array_t<float> a({n_, py::ssize_t(3)});
        dict_[name] = a;
        return reinterpret_cast<Vec3f*>(a.mutable_data());  // Vec3f is three packed floats
    }
    py::dict dict() const { return dict_; }

  private:
    py::ssize_t n_;
    py::dict dict_;
};
static_assert(sizeof(Vec3f) == 3 * sizeof(float));

py::dict ProceduralTexture(const std::string& node_name, const py::handle& points_in, const py::handle& w_in,
                           const py::kwargs& kwargs) {
    const auto node = ParseNameOrThrow<svm::ProceduralTexture>("procedural texture", "procedural textures", node_name,
                                                               svm::kProceduralTextureNames);
    const CArray<float> points = RowsOf<float>(points_in, 3, "points");
    const py::ssize_t n = points.shape(0);
    CArray<float> w_array;
    if (!w_in.is_none()) {
        w_array = ArrayOf<float>(w_in, "w");
        if (w_array.ndim() != 1 || w_array.shape(0) != n)
            throw py::value_error("w must have shape (" + std::to_string(n) + ",) like points' rows, got " +
                                  ShapeString(w_array));
    }
    const float* pts = points.data();
    const float* ws = w_in.is_none() ? nullptr : w_array.data();
    const auto P = [&](py::ssize_t i) { return Vec3f(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]); };
    const auto W = [&](py::ssize_t i) { return ws ? ws[i] : 0.0f; };

    SettingsReader r(node_name, kwargs);
    Outputs out(n);
    switch (node) {
        case svm::ProceduralTexture::kNoise: {
            svm::NoiseTextureParams p;
            r.Dimensions(&p.dimensions);
            r.Float("scale", &p.scale), r.Float("detail", &p.detail), r.Float("roughness", &p.roughness);
            r.Float("distortion", &p.distortion);
            r.Finish();
            float* fac = out.Scalar("fac");
            Vec3f* color = out.Vector("color");
            for (py::ssize_t i = 0; i < n; ++i) {
                const auto o = svm::NoiseTexture(p, P(i), W(i));
                fac[i] = o.fac, color[i] = o.color;
            }
            break;
        }
        case svm::ProceduralTexture::kMusgrave: {
            svm::MusgraveTextureParams p;
            r.Dimensions(&p.dimensions);
            r.Enum("type", &p.type, svm::kMusgraveTypeNames);
            r.Float("scale", &p.scale), r.Float("detail", &p.detail), r.Float("dimension", &p.dimension);
            r.Float("lacunarity", &p.lacunarity), r.Float("offset", &p.offset), r.Float("gain", &p.gain);
            r.Finish();
            float* fac = out.Scalar("fac");
            for (py::ssize_t i = 0; i < n; ++i) fac[i] = svm::MusgraveTexture(p, P(i), W(i));
            break;
        }
        case svm::ProceduralTexture::kVoronoi: {
            svm::VoronoiTextureParams p;
            r.Dimensions(&p.dimensions);
            r.Enum("feature", &p.feature, svm::kVoronoiFeatureNames);
            r.Enum("metric", &p.metric, svm::kVoronoiMetricNames);
            r.Float("scale", &p.scale), r.Float("smoothness", &p.smoothness), r.Float("exponent", &p.exponent);
            r.Float("randomness", &p.randomness);
            r.Finish();
            float* distance = out.Scalar("distance");
            Vec3f* color = out.Vector("color");
            Vec3f* position = out.Vector("position");
            float* w = out.Scalar("w");
            float* radius = out.Scalar("radius");
            for (py::ssize_t i = 0; i < n; ++i) {
                const auto o = svm::VoronoiTexture(p, P(i), W(i));
                distance[i] = o.distance, color[i] = o.color, position[i] = o.position, w[i] = o.w;
                radius[i] = o.radius;
            }
            break;
        }
        case svm::ProceduralTexture::kWhiteNoise: {
            svm::WhiteNoiseTextureParams p;
            r.Dimensions(&p.dimensions);
            r.Finish();
            float* value = out.Scalar("value");
            Vec3f* color = out.Vector("color");
            for (py::ssize_t i = 0; i < n; ++i) {
                const auto o = svm::WhiteNoiseTexture(p, P(i), W(i));
                value[i] = o.value, color[i] = o.color;
            }
            break;
        }
        case svm::ProceduralTexture::kGradient: {
            svm::GradientTextureParams p;
            r.Enum("type", &p.type, svm::kGradientTypeNames);
            r.Finish();
            float* fac = out.Scalar("fac");
            Vec3f* color = out.Vector("color");
            for (py::ssize_t i = 0; i < n; ++i) {
                fac[i] = svm::GradientTexture(p, P(i));
                color[i] = {fac[i], fac[i], fac[i]};
            }
            break;
        }
        case svm::ProceduralTexture::kChecker: {
            svm::CheckerTextureParams p;
            r.Color("color1", &p.color1), r.Color("color2", &p.color2), r.Float("scale", &p.scale);
            r.Finish();
            float* fac = out.Scalar("fac");
            Vec3f* color = out.Vector("color");
            for (py::ssize_t i = 0; i < n; ++i) {
                const auto o = svm::CheckerTexture(p, P(i));
                fac[i] = o.fac, color[i] = o.color;
            }
            break;
        }
        case svm::ProceduralTexture::kWave: {
            svm::WaveTextureParams p;
            r.Enum("type", &p.type, svm::kWaveTypeNames);
            r.Enum("bands_direction", &p.bands_direction, svm::kWaveBandsDirectionNames);
            r.Enum("rings_direction", &p.rings_direction, svm::kWaveRingsDirectionNames);
            r.Enum("profile", &p.profile, svm::kWaveProfileNames);
            r.Float("scale", &p.scale), r.Float("distortion", &p.distortion), r.Float("detail", &p.detail);
            r.Float("detail_scale", &p.detail_scale), r.Float("detail_roughness", &p.detail_roughness);
            r.Float("phase_offset", &p.phase_offset);
            r.Finish();
            float* fac = out.Scalar("fac");
            Vec3f* color = out.Vector("color");
            for (py::ssize_t i = 0; i < n; ++i) {
                fac[i] = svm::WaveTexture(p, P(i));
                color[i] = {fac[i], fac[i], fac[i]};
            }
            break;
        }
        case svm::ProceduralTexture::kMagic: {
            svm::MagicTextureParams p;
            r.Int("depth", &p.depth, 0, svm::kMaxMagicDepth);
            r.Float("scale", &p.scale), r.Float("distortion", &p.distortion);
            r.Finish();
            float* fac = out.Scalar("fac");
            Vec3f* color = out.Vector("color");
            for (py::ssize_t i = 0; i < n; ++i) {
                const auto o = svm::MagicTexture(p, P(i));
                fac[i] = o.fac, color[i] = o.color;
            }
            break;
        }
        case svm::ProceduralTexture::kBrick: {
            svm::BrickTextureParams p;
            r.Float("offset", &p.offset), r.Int("offset_frequency", &p.offset_frequency, 1, 99);
            r.Float("squash", &p.squash), r.Int("squash_frequency", &p.squash_frequency, 1, 99);
            r.Color("color1", &p.color1), r.Color("color2", &p.color2), r.Color("mortar", &p.mortar);
            r.Float("scale", &p.scale), r.Float("mortar_size", &p.mortar_size);
            r.Float("mortar_smooth", &p.mortar_smooth), r.Float("bias", &p.bias);
            r.Float("brick_width", &p.brick_width), r.Float("row_height", &p.row_height);
            r.Finish();
            float* fac = out.Scalar("fac");
            Vec3f* color = out.Vector("color");
            for (py::ssize_t i = 0; i < n; ++i) {
                const auto o = svm::BrickTexture(p, P(i));
                fac[i] = o.fac, color[i] = o.color;
            }
            break;
        }
    }
    return out.dict();
}

}  // namespace

void BindSvmTextures(py::module_& m) {
    m.def("procedural_texture", &ProceduralTexture, py::arg("node"), py::arg("points"), py::arg("w") = py::none(),
          "Cycles 3.4's procedural texture `node` at texture-space `points` (N x 3; W per point for 1D/4D), "
          "settings as keyword arguments: a dict of output arrays (float32).");
    m.attr("procedural_textures") = py::tuple(py::cast(
        std::vector<std::string>(std::begin(svm::kProceduralTextureNames), std::end(svm::kProceduralTextureNames))));
}

}  // namespace sphrect::python
