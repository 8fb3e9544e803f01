// sphrect._native.svm_color: the colour and shading-input node functions (render/svm/color_nodes.h,
// shading_nodes.h) on numpy arrays, for the tests that hold them against Cycles.  Every per-point input is a number
// or an array of N numbers (a vector: 3 numbers or an (N, 3) array); the outputs have N rows.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "core/enum_names.h"
#include "name_tuple.h"
#include "numpy_arrays.h"
#include "render/svm/color_nodes.h"
#include "render/svm/shading_nodes.h"

namespace py = pybind11;

namespace sphrect::python {

namespace {

using namespace render::svm;

// The per-point inputs of one call, read and checked against each other's length.
class Batch {
  public:
    // A scalar input: a number or an array of shape (N,).
    int Scalar(const py::handle& obj, const std::string& name) { return Add(obj, name, 1); }
    // A vector input: 3 numbers or an array of shape (N, 3).
    int Vector(const py::handle& obj, const std::string& name) { return Add(obj, name, 3); }

    py::ssize_t size() const { return n_; }
    float F(int column, py::ssize_t i) const { return Row(column, i)[0]; }
    Vec3f V(int column, py::ssize_t i) const {
        const float* r = Row(column, i);
        return {r[0], r[1], r[2]};
    }

  private:
    struct Column {
        CArray<float> a;
        bool per_point;
        int width;
    };

    int Add(const py::handle& obj, const std::string& name, int width) {
        CArray<float> a = ArrayOf<float>(obj, name);
        const bool single = width == 1 ? a.ndim() == 0 : (a.ndim() == 1 && a.shape(0) == 3);
        const bool rows = width == 1 ? a.ndim() == 1 : (a.ndim() == 2 && a.shape(1) == 3);
        if (!single && !rows)
            throw py::value_error(name +
                                  (width == 1 ? " must be a number or an array of shape (N,)"
                                              : " must be 3 numbers or an array of shape (N, 3)") +
                                  ", got shape " + ShapeString(a));
        if (rows) {
            if (n_set_ && a.shape(0) != n_)
                throw py::value_error(name + " has " + std::to_string(a.shape(0)) + " rows, the inputs before it " +
                                      std::to_string(n_));
            n_ = a.shape(0);
            n_set_ = true;
        }
        columns_.push_back({a, rows, width});
        return int(columns_.size()) - 1;
    }
    const float* Row(int column, py::ssize_t i) const {
        const Column& c = columns_[size_t(column)];
        return c.a.data() + (c.per_point ? i * c.width : 0);
    }

    std::vector<Column> columns_;
    py::ssize_t n_ = 1;
    bool n_set_ = false;
};

py::array_t<float> Floats(py::ssize_t n) { return py::array_t<float>(n); }
py::array_t<float> Vectors(py::ssize_t n) { return py::array_t<float>({n, py::ssize_t(3)}); }
void Put(py::array_t<float>& out, py::ssize_t i, const Vec3f& v) {
    float* p = out.mutable_data() + 3 * i;
    p[0] = v.x;
    p[1] = v.y;
    p[2] = v.z;
}

template <class Fn>
py::array_t<float> MapColor(Batch& b, Fn fn) {
    py::array_t<float> out = Vectors(b.size());
    for (py::ssize_t i = 0; i < b.size(); ++i) Put(out, i, fn(i));
    return out;
}
template <class Fn>
py::array_t<float> MapFloat(Batch& b, Fn fn) {
    py::array_t<float> out = Floats(b.size());
    for (py::ssize_t i = 0; i < b.size(); ++i) out.mutable_data()[i] = fn(i);
    return out;
}

// A sampled curve table of `channels` columns, (size, channels) or (size,) for one channel.
CurveTable Table(const CArray<float>& values, int channels, float min_x, float max_x, bool extrapolate) {
    const bool ok = channels == 1 ? values.ndim() == 1 : (values.ndim() == 2 && values.shape(1) == channels);
    if (!ok || values.shape(0) < 2)
        throw py::value_error("table must have shape " +
                              std::string(channels == 1 ? "(size,)" : "(size, " + std::to_string(channels) + ")") +
                              " with size >= 2, got " + ShapeString(values));
    if (!(max_x > min_x))
        throw py::value_error("max_x must be greater than min_x, got " + std::to_string(min_x) + ", " +
                              std::to_string(max_x));
    CurveTable t;
    t.values = values.data();
    t.size = int(values.shape(0));
    t.stride = channels;
    t.min_x = min_x;
    t.max_x = max_x;
    t.extrapolate = extrapolate;
    return t;
}

template <class Enum, size_t N>
Enum Named(const std::string& what, const std::string& plural, const std::string& name, const char* const (&names)[N]) {
    return ParseNameOrThrow<Enum>(what, plural, name, names);
}

}  // namespace

void BindSvmColor(py::module_& parent) {
    py::module_ m = parent.def_submodule(
        "svm_color", "Cycles 3.4's colour and shading-input nodes as pure functions, on arrays (for tests)");
    m.attr("VECTOR_MATH_OPERATIONS") = NameTuple(kVectorMathOpNames, [](const char* s) { return s; });
    m.attr("VECTOR_ROTATE_TYPES") = NameTuple(kVectorRotateTypeNames, [](const char* s) { return s; });
    m.attr("LIGHT_FALLOFF_KINDS") = NameTuple(kLightFalloffKindNames, [](const char* s) { return s; });
    m.attr("CURVE_TABLE_SIZE") = kCurveTableSize;
    m.attr("XYZ_TO_RGB") = py::make_tuple(py::make_tuple(kXyzToRgb[0].x, kXyzToRgb[0].y, kXyzToRgb[0].z),
                                          py::make_tuple(kXyzToRgb[1].x, kXyzToRgb[1].y, kXyzToRgb[1].z),
                                          py::make_tuple(kXyzToRgb[2].x, kXyzToRgb[2].y, kXyzToRgb[2].z));
    m.attr("RGB_TO_Y") = py::make_tuple(kRgbToY.x, kRgbToY.y, kRgbToY.z);

    m.def(
        "layer_weight",
        [](py::object blend, py::object incoming, py::object normal, py::object backfacing) {
            Batch b;
            const int bl = b.Scalar(blend, "blend"), in = b.Vector(incoming, "incoming"),
                      n = b.Vector(normal, "normal");
            const int bf = b.Scalar(backfacing, "backfacing");
            py::array_t<float> fresnel = Floats(b.size()), facing = Floats(b.size());
            for (py::ssize_t i = 0; i < b.size(); ++i) {
                fresnel.mutable_data()[i] = LayerWeightFresnel(b.F(bl, i), b.V(in, i), b.V(n, i), b.F(bf, i) != 0);
                facing.mutable_data()[i] = LayerWeightFacing(b.F(bl, i), b.V(in, i), b.V(n, i));
            }
            return py::make_tuple(fresnel, facing);
        },
        py::arg("blend"), py::arg("incoming"), py::arg("normal"), py::arg("backfacing") = 0,
        "Layer Weight's (Fresnel, Facing): incoming = -ray direction, normal = the shading normal or the Normal "
        "input, backfacing = 1 on a back face.");
    m.def(
        "fresnel",
        [](py::object ior, py::object incoming, py::object normal, py::object backfacing) {
            Batch b;
            const int e = b.Scalar(ior, "ior"), in = b.Vector(incoming, "incoming"), n = b.Vector(normal, "normal");
            const int bf = b.Scalar(backfacing, "backfacing");
            return MapFloat(
                b, [&](py::ssize_t i) { return FresnelNode(b.F(e, i), b.V(in, i), b.V(n, i), b.F(bf, i) != 0); });
        },
        py::arg("ior"), py::arg("incoming"), py::arg("normal"), py::arg("backfacing") = 0);
    m.def(
        "light_falloff",
        [](const std::string& kind, py::object strength, py::object smooth, py::object ray_length) {
            const auto k = Named<LightFalloffKind>("light falloff output", "outputs", kind, kLightFalloffKindNames);
            Batch b;
            const int s = b.Scalar(strength, "strength"), sm = b.Scalar(smooth, "smooth");
            const int r = b.Scalar(ray_length, "ray_length");
            return MapFloat(b, [&](py::ssize_t i) { return LightFalloff(k, b.F(s, i), b.F(sm, i), b.F(r, i)); });
        },
        py::arg("kind"), py::arg("strength"), py::arg("smooth"), py::arg("ray_length"));
    m.def(
        "bump_differentials",
        [](py::object ng, py::object dp) {
            Batch b;
            const int g = b.Vector(ng, "ng"), d = b.Scalar(dp, "dp");
            py::array_t<float> dx = Vectors(b.size()), dy = Vectors(b.size());
            for (py::ssize_t i = 0; i < b.size(); ++i) {
                const BumpOffsets o = BumpDifferentials(b.V(g, i), b.F(d, i));
                Put(dx, i, o.dx);
                Put(dy, i, o.dy);
            }
            return py::make_tuple(dx, dy);
        },
        py::arg("ng"), py::arg("dp"), "The two offsets (dx, dy) at which Cycles samples a bumped height.");
    m.def(
        "bump",
        [](py::object normal, py::object ng, py::object incoming, py::object dx, py::object dy, py::object h_c,
           py::object h_x, py::object h_y, py::object strength, py::object distance, bool invert) {
            Batch b;
            const int n = b.Vector(normal, "normal"), g = b.Vector(ng, "ng"), in = b.Vector(incoming, "incoming");
            const int x = b.Vector(dx, "dx"), y = b.Vector(dy, "dy");
            const int hc = b.Scalar(h_c, "h_c"), hx = b.Scalar(h_x, "h_x"), hy = b.Scalar(h_y, "h_y");
            const int s = b.Scalar(strength, "strength"), d = b.Scalar(distance, "distance");
            return MapColor(b, [&](py::ssize_t i) {
                return BumpNormal(b.V(n, i), b.V(g, i), b.V(in, i), {b.V(x, i), b.V(y, i)}, b.F(hc, i), b.F(hx, i),
                                  b.F(hy, i), b.F(s, i), b.F(d, i), invert);
            });
        },
        py::arg("normal"), py::arg("ng"), py::arg("incoming"), py::arg("dx"), py::arg("dy"), py::arg("h_c"),
        py::arg("h_x"), py::arg("h_y"), py::arg("strength") = 1.0f, py::arg("distance") = 1.0f,
        py::arg("invert") = false);
    m.def(
        "ensure_valid_reflection",
        [](py::object ng, py::object incoming, py::object normal) {
            Batch b;
            const int g = b.Vector(ng, "ng"), in = b.Vector(incoming, "incoming"), n = b.Vector(normal, "normal");
            return MapColor(b, [&](py::ssize_t i) { return EnsureValidReflection(b.V(g, i), b.V(in, i), b.V(n, i)); });
        },
        py::arg("ng"), py::arg("incoming"), py::arg("normal"));

    m.def(
        "blackbody",
        [](py::object temperature) {
            Batch b;
            const int t = b.Scalar(temperature, "temperature");
            return MapColor(b, [&](py::ssize_t i) { return Blackbody(b.F(t, i)); });
        },
        py::arg("temperature"));
    m.def(
        "wavelength",
        [](py::object nm) {
            Batch b;
            const int w = b.Scalar(nm, "wavelength");
            return MapColor(b, [&](py::ssize_t i) { return Wavelength(b.F(w, i)); });
        },
        py::arg("wavelength"));
    m.def(
        "hue_saturation_value",
        [](py::object color, py::object hue, py::object saturation, py::object value, py::object fac) {
            Batch b;
            const int c = b.Vector(color, "color"), h = b.Scalar(hue, "hue"), s = b.Scalar(saturation, "saturation");
            const int v = b.Scalar(value, "value"), f = b.Scalar(fac, "fac");
            return MapColor(b, [&](py::ssize_t i) {
                return HueSaturationValue(b.V(c, i), b.F(h, i), b.F(s, i), b.F(v, i), b.F(f, i));
            });
        },
        py::arg("color"), py::arg("hue") = 0.5f, py::arg("saturation") = 1.0f, py::arg("value") = 1.0f,
        py::arg("fac") = 1.0f);
    m.def(
        "bright_contrast",
        [](py::object color, py::object bright, py::object contrast) {
            Batch b;
            const int c = b.Vector(color, "color"), br = b.Scalar(bright, "bright"),
                      co = b.Scalar(contrast, "contrast");
            return MapColor(b, [&](py::ssize_t i) { return BrightContrast(b.V(c, i), b.F(br, i), b.F(co, i)); });
        },
        py::arg("color"), py::arg("bright") = 0.0f, py::arg("contrast") = 0.0f);
    m.def(
        "gamma",
        [](py::object color, py::object gamma) {
            Batch b;
            const int c = b.Vector(color, "color"), g = b.Scalar(gamma, "gamma");
            return MapColor(b, [&](py::ssize_t i) { return GammaColor(b.V(c, i), b.F(g, i)); });
        },
        py::arg("color"), py::arg("gamma") = 1.0f);
    m.def(
        "invert",
        [](py::object color, py::object fac) {
            Batch b;
            const int c = b.Vector(color, "color"), f = b.Scalar(fac, "fac");
            return MapColor(b, [&](py::ssize_t i) { return InvertColor(b.V(c, i), b.F(f, i)); });
        },
        py::arg("color"), py::arg("fac") = 1.0f);
    m.def(
        "rgb_to_bw",
        [](py::object color) {
            Batch b;
            const int c = b.Vector(color, "color");
            return MapFloat(b, [&](py::ssize_t i) { return RgbToBw(b.V(c, i)); });
        },
        py::arg("color"));
    m.def(
        "curves_rgb",
        [](py::object table, float min_x, float max_x, bool extrapolate, py::object fac, py::object color) {
            const CArray<float> values = ArrayOf<float>(table, "table");
            const CurveTable t = Table(values, 3, min_x, max_x, extrapolate);
            Batch b;
            const int f = b.Scalar(fac, "fac"), c = b.Vector(color, "color");
            return MapColor(b, [&](py::ssize_t i) { return CurvesRgb(t, b.F(f, i), b.V(c, i)); });
        },
        py::arg("table"), py::arg("min_x"), py::arg("max_x"), py::arg("extrapolate"), py::arg("fac"), py::arg("color"),
        "RGB Curves / Vector Curves through a sampled (size, 3) table.");
    m.def(
        "curve_float",
        [](py::object table, float min_x, float max_x, bool extrapolate, py::object fac, py::object value) {
            const CArray<float> values = ArrayOf<float>(table, "table");
            const CurveTable t = Table(values, 1, min_x, max_x, extrapolate);
            Batch b;
            const int f = b.Scalar(fac, "fac"), v = b.Scalar(value, "value");
            return MapFloat(b, [&](py::ssize_t i) { return CurveFloat(t, b.F(f, i), b.F(v, i)); });
        },
        py::arg("table"), py::arg("min_x"), py::arg("max_x"), py::arg("extrapolate"), py::arg("fac"), py::arg("value"),
        "Float Curve through a sampled (size,) table.");
    m.def(
        "vector_math",
        [](const std::string& operation, py::object a, py::object b_, py::object c, py::object scale) {
            const auto op = Named<VectorMathOp>("vector math operation", "operations", operation, kVectorMathOpNames);
            Batch b;
            const int ia = b.Vector(a, "a"), ib = b.Vector(b_, "b"), ic = b.Vector(c, "c"),
                      s = b.Scalar(scale, "scale");
            py::array_t<float> value = Floats(b.size()), vector = Vectors(b.size());
            for (py::ssize_t i = 0; i < b.size(); ++i) {
                const VectorMathResult r = VectorMath(op, b.V(ia, i), b.V(ib, i), b.V(ic, i), b.F(s, i));
                value.mutable_data()[i] = r.value;
                Put(vector, i, r.vector);
            }
            return py::make_tuple(value, vector);
        },
        py::arg("operation"), py::arg("a"), py::arg("b") = py::make_tuple(0, 0, 0),
        py::arg("c") = py::make_tuple(0, 0, 0), py::arg("scale") = 1.0f, "(Value, Vector) of Vector Math.");
    m.def(
        "vector_rotate",
        [](const std::string& type, bool invert, py::object vector, py::object center, py::object axis,
           py::object angle, py::object rotation) {
            const auto t = Named<VectorRotateType>("vector rotate type", "types", type, kVectorRotateTypeNames);
            Batch b;
            const int v = b.Vector(vector, "vector"), c = b.Vector(center, "center"), ax = b.Vector(axis, "axis");
            const int an = b.Scalar(angle, "angle"), r = b.Vector(rotation, "rotation");
            return MapColor(b, [&](py::ssize_t i) {
                return VectorRotate(t, invert, b.V(v, i), b.V(c, i), b.V(ax, i), b.F(an, i), b.V(r, i));
            });
        },
        py::arg("type"), py::arg("invert"), py::arg("vector"), py::arg("center") = py::make_tuple(0, 0, 0),
        py::arg("axis") = py::make_tuple(0, 0, 1), py::arg("angle") = 0.0f,
        py::arg("rotation") = py::make_tuple(0, 0, 0));
    m.def(
        "normal_dot",
        [](py::object direction, py::object normal) {
            Batch b;
            const int d = b.Vector(direction, "direction"), n = b.Vector(normal, "normal");
            return MapFloat(b, [&](py::ssize_t i) { return NormalNodeDot(b.V(d, i), b.V(n, i)); });
        },
        py::arg("direction"), py::arg("normal"), "The Normal node's Dot output.");
}

}  // namespace sphrect::python
