// Python bindings of the sampling core: techniques (through technique.h's LightSampler, the
// code the renderer runs) and sample patterns.  numpy in, numpy out; bad input -> ValueError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/ellipse_technique.h"
#include "core/patterns.h"
#include "name_tuple.h"
#include "numpy_arrays.h"
#include "core/rect_light.h"
#include "core/rectangle.h"
#include "core/cone.h"
#include "core/rectangle_blocks.h"
#include "core/rectangle_ltc.h"
#include "core/technique.h"

namespace py = pybind11;

namespace sphrect::python {
namespace {

// ---------------------------------------------------------------------------------------------
// Names

Technique ToTechnique(const std::string& name) {
    Technique t;
    ParseEnumNameOrThrow("technique", "techniques", name, kAllTechniques, TechniqueName, &t);
    return t;
}

enum class Precision { Float32, Float64 };

// dtype= accepts "float32"/"float64" or anything numpy.dtype() accepts (np.float32, "f8", ...).
Precision ToPrecision(const py::object& dtype) {
    py::dtype dt;
    if (dtype.is_none())  // numpy would read None as float64; the default here is float32
        throw py::value_error("dtype must be 'float32' or 'float64', got None");
    try {
        dt = py::dtype::from_args(dtype);
    } catch (py::error_already_set&) {
        throw py::value_error("dtype must be 'float32' or 'float64', got " + std::string(py::repr(dtype)));
    }
    if (dt.kind() == 'f' && dt.itemsize() == 4) return Precision::Float32;
    if (dt.kind() == 'f' && dt.itemsize() == 8) return Precision::Float64;
    throw py::value_error("dtype must be 'float32' or 'float64', got " + std::string(py::repr(dtype)));
}

// A Python integer (or anything with __index__, e.g. numpy integers) in [0, hi].
uint64_t ToInteger(const py::object& obj, const char* name, uint64_t hi) {
    if (py::isinstance<py::bool_>(obj) || !PyIndex_Check(obj.ptr()))
        throw py::value_error(std::string(name) + " must be an integer, got " + std::string(py::repr(obj)));
    py::int_ value = py::reinterpret_steal<py::int_>(PyNumber_Index(obj.ptr()));
    if (!value) throw py::error_already_set();
    if (value < py::int_(0) || value > py::int_(hi))
        throw py::value_error(std::string(name) + " must be in [0, " + std::to_string(hi) + "], got " +
                              std::string(py::str(value)));
    return value.cast<uint64_t>();
}

// ---------------------------------------------------------------------------------------------
// Array inputs.  Everything is read as float64 (any numeric array-like), checked for shape and
// finiteness, then converted to the working precision T (checked again: 1e300 is not a float).

using ArrayD = CArray<double>;

std::string Num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

template <class T>
T CheckedValue(double x, const char* name) {
    if (!std::isfinite(x)) throw py::value_error(std::string(name) + " contains NaN or Inf");
    const T t = T(x);
    if (!std::isfinite(t))
        throw py::value_error(std::string(name) + " contains a value (" + Num(x) +
                              ") that overflows the requested dtype");
    return t;
}

// Rows of width `width` from an array of shape [width] (one row, when allow_single) or [N, width].
template <class T, int width>
std::vector<std::array<T, width>> ReadRows(const py::handle& obj, const char* name, bool allow_single) {
    const ArrayD a = RowsOf<double>(obj, width, name, allow_single);
    const size_t rows = a.ndim() == 1 ? 1 : size_t(a.shape(0));
    std::vector<std::array<T, width>> out(rows);
    const double* p = a.data();
    for (size_t i = 0; i < rows; ++i)
        for (int k = 0; k < width; ++k) out[i][k] = CheckedValue<T>(p[i * width + k], name);
    return out;
}

// float32's range for what the core squares (lengths, dot products): coordinates and edge lengths
// beyond sqrt(FLT_MAX) ~ 1.8e19 overflow, non-zero edges below sqrt(FLT_MIN) ~ 1.1e-19 underflow,
// and the float32 code would answer 0 where the solid angle is 2 pi or finite.
constexpr double kFloat32Largest = 1.8e19, kFloat32SmallestEdge = 1.1e-19;

double LargestCoordinate(const Vec3d& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

template <class T>
void CheckFloat32Range(const Vec3<T>& v, const char* name, bool is_edge) {
    if constexpr (std::is_same_v<T, float>) {
        const double largest = LargestCoordinate(Vec3d(v)), length = Length(Vec3d(v));
        if (largest > kFloat32Largest || (is_edge && length > 0 && length < kFloat32SmallestEdge))
            throw py::value_error(std::string(name) +
                                  " is beyond what float32 computes (coordinates up to 1.8e19, "
                                  "edges from 1.1e-19): use dtype='float64', or rescale the scene");
    }
}

template <class T>
std::vector<Vec3<T>> ReadVec3s(const py::handle& obj, const char* name, bool allow_batch) {
    std::vector<Vec3<T>> v;
    if (!allow_batch) {
        const ArrayD a = ArrayOf<double>(obj, name);
        if (!(a.ndim() == 1 && a.shape(0) == 3))
            throw py::value_error(std::string(name) + " must have shape (3,), got " + ShapeString(a));
    }
    for (const auto& r : ReadRows<T, 3>(obj, name, true)) {
        v.push_back({r[0], r[1], r[2]});
        CheckFloat32Range(v.back(), name, false);
    }
    return v;
}

template <class T>
RectLight<T> ReadLight(const py::handle& corner, const py::handle& ex, const py::handle& ey, bool two_sided) {
    RectLight<T> light{ReadVec3s<T>(corner, "corner", false)[0], ReadVec3s<T>(ex, "edge_x", false)[0],
                       ReadVec3s<T>(ey, "edge_y", false)[0], two_sided};
    const std::string problem = ValidateRectLight(light);
    if (!problem.empty()) throw py::value_error(problem);
    CheckFloat32Range(light.ex, "edge_x", true);
    CheckFloat32Range(light.ey, "edge_y", true);
    return light;
}

// Whether p lies on the light, within kOffLightTolerance of its longest edge (semi-axis) plus
// kCoordinateTolerance of p's largest coordinate (float32's own rounding of far points), both off its
// plane and beyond its edges.  pdf() gives 0 and invert() NaN for points off the light.
constexpr double kOffLightTolerance = 1e-3, kCoordinateTolerance = 1e-5;

// Point p in the frame of a planar light at `origin` with axes a, b: its distance h off the plane
// and its coordinates along the axes (length units), and the tolerance for p.
struct LightPlanePoint {
    double h, x, y, len_a, len_b, tol;
};

inline LightPlanePoint ToLightPlane(const Vec3d& p, const Vec3d& origin, const Vec3d& a, const Vec3d& b) {
    const double len_a = Length(a), len_b = Length(b);
    const Vec3d d = p - origin;
    return {Dot(d, Normalize(Cross(a, b))),
            Dot(d, a) / len_a,
            Dot(d, b) / len_b,
            len_a,
            len_b,
            kOffLightTolerance * std::max(len_a, len_b) + kCoordinateTolerance * LargestCoordinate(p)};
}

template <class T>
bool OnLight(const RectLight<T>& l, const Vec3<T>& point) {
    const LightPlanePoint q = ToLightPlane(Vec3d(point), Vec3d(l.corner), Vec3d(l.ex), Vec3d(l.ey));
    return std::abs(q.h) <= q.tol && q.x >= -q.tol && q.x <= q.len_a + q.tol && q.y >= -q.tol && q.y <= q.len_b + q.tol;
}

template <class T>
bool OnLight(const EllipseLight<T>& l, const Vec3<T>& point) {
    const LightPlanePoint q = ToLightPlane(Vec3d(point), Vec3d(l.center), Vec3d(l.axis_u), Vec3d(l.axis_v));
    const double ra = q.x / (q.len_a + q.tol), rb = q.y / (q.len_b + q.tol);
    return std::abs(q.h) <= q.tol && ra * ra + rb * rb <= 1;
}

// A per-row input (origin, normal) must have one row (shared) or as many rows as the batch.
void CheckRows(size_t batch, const char* batch_name, size_t rows, const char* name) {
    if (rows == 1 || rows == batch) return;
    throw py::value_error(std::string(batch_name) + " has " + std::to_string(batch) + " rows but " + name + " has " +
                          std::to_string(rows) + "; they must match (or " + name + " be a single (3,) vector)");
}

template <class T>
py::array_t<T> NewArray(size_t n, size_t width) {
    if (width == 0) return py::array_t<T>(std::vector<py::ssize_t>{py::ssize_t(n)});
    return py::array_t<T>(std::vector<py::ssize_t>{py::ssize_t(n), py::ssize_t(width)});
}

// Shading normals: required by rectangle_cosine, rectangle_projected and rectangle_ltc; unit length is enforced here
// (the renderer passes unit normals, so the core may assume them).
template <class T>
std::vector<Vec3<T>> ReadNormals(Technique technique, const py::object& normal) {
    if (normal.is_none()) {
        if (NeedsShadingNormal(technique))
            throw py::value_error("technique '" + std::string(TechniqueName(technique)) +
                                  "' needs normal= (the shading normal, shape (3,) or (N, 3))");
        return {Vec3<T>(0, 0, 0)};
    }
    std::vector<Vec3<T>> n = ReadVec3s<T>(normal, "normal", true);
    for (auto& v : n) {
        const T len = Length(v);
        if (!(len > 0)) throw py::value_error("normal must be a non-zero vector");
        v = v / len;
    }
    return n;
}

// Everything a per-row technique call needs, read and validated with the GIL held: the light
// (RectLight<T> or EllipseLight<T>) and the origins and normals, one (shared) or one per row.
template <class T, class Light>
struct Call {
    Light light;
    std::vector<Vec3<T>> origins, normals;
    GlossyLobe<T> lobe;  // rectangle_ltc's (wo= and alpha=); none by default
    const Vec3<T>& Origin(size_t i) const { return origins[origins.size() == 1 ? 0 : i]; }
    const Vec3<T>& Normal(size_t i) const { return normals[normals.size() == 1 ? 0 : i]; }
    bool PerRow() const { return origins.size() > 1 || normals.size() > 1; }
};

template <class T>
using Setup = Call<T, RectLight<T>>;

// rectangle_ltc's glossy lobe from the keyword arguments: wo (towards the viewer) and the GGX alpha together, the
// lobe's and the rest's weights; none when wo is None.
struct LobeArguments {
    py::object wo = py::none(), alpha = py::none();
    double weight = 1, rest_weight = 0;
};

template <class T>
GlossyLobe<T> ReadLobe(Technique technique, const LobeArguments& a) {
    if (a.wo.is_none() && a.alpha.is_none()) return {};
    if (technique != Technique::RectangleLtc)
        throw py::value_error("wo= and alpha= are for technique 'rectangle_ltc', not '" +
                              std::string(TechniqueName(technique)) + "'");
    if (a.wo.is_none() || a.alpha.is_none()) throw py::value_error("rectangle_ltc's lobe needs both wo= and alpha=");
    const std::vector<Vec3<T>> wo = ReadVec3s<T>(a.wo, "wo", false);
    const double alpha = a.alpha.cast<double>();
    if (!(Length(wo[0]) > 0)) throw py::value_error("wo must be a non-zero vector");
    if (!(alpha > 0) || !std::isfinite(alpha)) throw py::value_error("alpha must be positive and finite");
    if (!(a.weight >= 0) || !(a.rest_weight >= 0) || !(a.weight + a.rest_weight > 0) || !std::isfinite(a.weight) ||
        !std::isfinite(a.rest_weight))
        throw py::value_error("glossy_weight and rest_weight must be finite, >= 0 and not both 0");
    return {wo[0], T(alpha), T(a.weight), T(a.rest_weight)};
}

template <class T>
Setup<T> ReadSetup(Technique technique, const py::object& origin, const py::object& corner, const py::object& ex,
                   const py::object& ey, const py::object& normal, bool two_sided, const LobeArguments& lobe = {}) {
    Setup<T> s{ReadLight<T>(corner, ex, ey, two_sided), ReadVec3s<T>(origin, "origin", true),
               ReadNormals<T>(technique, normal), ReadLobe<T>(technique, lobe)};
    return s;
}

// Runs per(i, sampler) for i in [0, n) with a Sampler(origin, normal, light_or_frame), set up
// once when the origin and normal are shared, per row otherwise.  GIL released.
template <class Sampler, class C, class LightOrFrame, class F>
void RunRows(const C& s, const LightOrFrame& light, size_t n, F&& per) {
    py::gil_scoped_release release;
    auto make = [&](size_t i) {  // (rectangle_ltc's with the call's lobe)
        if constexpr (std::is_constructible_v<Sampler, decltype(s.Origin(i)), decltype(s.Normal(i)), LightOrFrame,
                                              decltype(s.lobe)>)
            return Sampler(s.Origin(i), s.Normal(i), light, s.lobe);
        else
            return Sampler(s.Origin(i), s.Normal(i), light);
    };
    if (!s.PerRow()) {
        const Sampler sampler = make(0);
        for (size_t i = 0; i < n; ++i) per(i, sampler);
    } else {
        for (size_t i = 0; i < n; ++i) per(i, make(i));
    }
}

// The rectangle techniques: the right LightSampler.
template <class T, class F>
void ForEachRow(Technique technique, const Setup<T>& s, size_t n, F&& per) {
    DispatchTechnique(technique, [&](auto tag) { RunRows<LightSampler<decltype(tag)::value, T>>(s, s.light, n, per); });
}

// ---------------------------------------------------------------------------------------------
// The bound functions, templated on the precision; each takes the call `s` and how to run a
// sampler over its rows, for_each(n, per), so rectangles and ellipses share them.

template <class T>
std::vector<std::array<T, 2>> ReadUV(const py::object& uv_obj) {
    const auto uv = ReadRows<T, 2>(uv_obj, "uv", false);
    for (const auto& q : uv)
        if (!(q[0] >= 0 && q[0] <= 1 && q[1] >= 0 && q[1] <= 1))
            throw py::value_error("uv must lie in [0, 1]^2, got (" + Num(q[0]) + ", " + Num(q[1]) + ")");
    return uv;
}

template <class T, class C, class ForEach>
py::tuple SampleRows(const C& s, const py::object& uv_obj, bool with_directions, ForEach&& for_each) {
    const auto uv = ReadUV<T>(uv_obj);
    const size_t n = uv.size();
    CheckRows(n, "uv", s.origins.size(), "origin");
    CheckRows(n, "uv", s.normals.size(), "normal");

    py::array_t<T> points = NewArray<T>(n, 3), dirs = NewArray<T>(n, 3), dist = NewArray<T>(n, 0),
                   pdf = NewArray<T>(n, 0);
    T* P = points.mutable_data();
    T* D = dirs.mutable_data();
    T* L = dist.mutable_data();
    T* Q = pdf.mutable_data();
    for_each(n, [&](size_t i, const auto& sampler) {
        const LightSample<T> ls = sampler.Sample(Point2<T>{uv[i][0], uv[i][1]});
        P[3 * i] = ls.point.x, P[3 * i + 1] = ls.point.y, P[3 * i + 2] = ls.point.z;
        D[3 * i] = ls.dir.x, D[3 * i + 1] = ls.dir.y, D[3 * i + 2] = ls.dir.z;
        L[i] = ls.dist;
        Q[i] = ls.pdf;
    });
    if (with_directions) return py::make_tuple(points, dirs, dist, pdf);
    return py::make_tuple(points, pdf);
}

template <class T, class C, class ForEach>
py::array PDFRows(const C& s, const py::object& points_obj, ForEach&& for_each) {
    const auto pts = ReadRows<T, 3>(points_obj, "points", false);
    const size_t n = pts.size();
    CheckRows(n, "points", s.origins.size(), "origin");
    CheckRows(n, "points", s.normals.size(), "normal");
    py::array_t<T> pdf = NewArray<T>(n, 0);
    T* Q = pdf.mutable_data();
    for_each(n, [&](size_t i, const auto& sampler) {
        const Vec3<T> p(pts[i][0], pts[i][1], pts[i][2]);
        Q[i] = OnLight(s.light, p) ? sampler.PDF(p) : T(0);
    });
    return pdf;
}

// uv [N, 2] of the points of `light` through a map's inverse: make_setup(origin) -> setup with
// .valid, invert(setup, point) -> Point2<double>.
template <class T, class Light, class MakeSetup, class Invert>
py::array InvertRows(const Light& light, const py::object& origin, const py::object& points_obj, MakeSetup&& make_setup,
                     Invert&& invert_point) {
    const std::vector<Vec3<T>> origins = ReadVec3s<T>(origin, "origin", true);
    const auto pts = ReadRows<T, 3>(points_obj, "points", false);
    const size_t n = pts.size();
    CheckRows(n, "points", origins.size(), "origin");
    py::array_t<T> uv = NewArray<T>(n, 2);
    T* U = uv.mutable_data();
    {
        py::gil_scoped_release release;
        auto invert = [&](size_t i, const auto& r) {
            // A configuration the map does not cover (degenerate light, origin in the light's
            // plane or behind a one-sided light), or a point off the light, has no (u, v): NaN.
            Point2<double> q{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
            const Vec3<T> p(pts[i][0], pts[i][1], pts[i][2]);
            if (r.valid && OnLight(light, p)) q = invert_point(r, p);
            U[2 * i] = T(q.u);
            U[2 * i + 1] = T(q.v);
        };
        if (origins.size() == 1) {
            const auto r = make_setup(origins[0]);
            for (size_t i = 0; i < n; ++i) invert(i, r);
        } else {
            for (size_t i = 0; i < n; ++i) invert(i, make_setup(origins[i]));
        }
    }
    return uv;
}

// solid_angle(origin) (double) for origin (3,) -> float, or (N, 3) -> array [N] of T.
template <class T, class SolidAngle>
py::object SolidAngleRows(const py::object& origin, SolidAngle&& solid_angle) {
    const ArrayD o = ArrayOf<double>(origin, "origin");
    const std::vector<Vec3<T>> origins = ReadVec3s<T>(origin, "origin", true);
    if (o.ndim() == 1) return py::float_(solid_angle(origins[0]));
    py::array_t<T> out = NewArray<T>(origins.size(), 0);
    T* W = out.mutable_data();
    {
        py::gil_scoped_release release;
        for (size_t i = 0; i < origins.size(); ++i) W[i] = T(solid_angle(origins[i]));
    }
    return std::move(out);
}

// Rectangles.

template <class T>
py::tuple SampleImpl(Technique technique, const py::object& origin, const py::object& corner, const py::object& ex,
                     const py::object& ey, const py::object& uv_obj, const py::object& normal, bool two_sided,
                     bool with_directions, const LobeArguments& lobe) {
    const Setup<T> s = ReadSetup<T>(technique, origin, corner, ex, ey, normal, two_sided, lobe);
    return SampleRows<T>(s, uv_obj, with_directions, [&](size_t n, auto&& per) { ForEachRow(technique, s, n, per); });
}

template <class T>
py::array PDFImpl(Technique technique, const py::object& origin, const py::object& corner, const py::object& ex,
                  const py::object& ey, const py::object& points_obj, const py::object& normal, bool two_sided,
                  const LobeArguments& lobe) {
    const Setup<T> s = ReadSetup<T>(technique, origin, corner, ex, ey, normal, two_sided, lobe);
    return PDFRows<T>(s, points_obj, [&](size_t n, auto&& per) { ForEachRow(technique, s, n, per); });
}

template <class T>
py::array InvertImpl(const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
                     const py::object& points_obj, bool two_sided) {
    const RectLight<T> light = ReadLight<T>(corner, ex, ey, two_sided);
    return InvertRows<T>(
        light, origin, points_obj, [&](const Vec3<T>& o) { return MakeRectangleSetup(o, light); },
        [](const RectangleSetup<T>& r, const Vec3<T>& p) { return InvertRectangle(r, p); });
}

// The inverse of rectangle_projected: like InvertRows, with the normals (one or one per row).
template <class T>
py::array InvertProjectedImpl(const py::object& origin, const py::object& corner, const py::object& ex,
                              const py::object& ey, const py::object& points_obj, const py::object& normal,
                              bool two_sided) {
    const Setup<T> s = ReadSetup<T>(Technique::RectangleProjected, origin, corner, ex, ey, normal, two_sided);
    const auto pts = ReadRows<T, 3>(points_obj, "points", false);
    const size_t n = pts.size();
    CheckRows(n, "points", s.origins.size(), "origin");
    CheckRows(n, "points", s.normals.size(), "normal");
    py::array_t<T> uv = NewArray<T>(n, 2);
    T* U = uv.mutable_data();
    {
        py::gil_scoped_release release;
        const RectLightFrame<T> frame = MakeRectLightFrame(s.light);
        for (size_t i = 0; i < n; ++i) {
            const RectangleProjectedSetup<T> r = MakeRectangleProjectedSetup(s.Origin(i), s.Normal(i), frame);
            Point2<double> q{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
            const Vec3<T> p(pts[i][0], pts[i][1], pts[i][2]);
            if (r.valid && OnLight(s.light, p)) q = InvertRectangleProjected(r, p);
            U[2 * i] = T(q.u);
            U[2 * i + 1] = T(q.v);
        }
    }
    return uv;
}

template <class T>
py::object ProjectedSolidAngleImpl(const py::object& origin, const py::object& corner, const py::object& ex,
                                   const py::object& ey, const py::object& normal, bool two_sided) {
    const Setup<T> s = ReadSetup<T>(Technique::RectangleProjected, origin, corner, ex, ey, normal, two_sided);
    if (s.normals.size() != 1) throw py::value_error("projected_solid_angle takes one normal, shape (3,)");
    return SolidAngleRows<T>(origin,
                             [&](const Vec3<T>& o) { return RectangleProjectedSolidAngle(o, s.normals[0], s.light); });
}

template <class T>
py::object SolidAngleImpl(const py::object& origin, const py::object& corner, const py::object& ex,
                          const py::object& ey, bool two_sided) {
    const RectLight<T> light = ReadLight<T>(corner, ex, ey, two_sided);
    return SolidAngleRows<T>(origin, [&](const Vec3<T>& o) { return RectangleSolidAngle(o, light); });
}

// ---------------------------------------------------------------------------------------------
// Ellipse (disk) lights: the same conventions, through ellipse_technique.h's EllipseSampler.

EllipseTechnique ToEllipseTechnique(const std::string& name) {
    EllipseTechnique t;
    ParseEnumNameOrThrow("ellipse technique", "ellipse techniques", name, kAllEllipseTechniques, EllipseTechniqueName,
                         &t);
    return t;
}

template <class T>
EllipseLight<T> ReadEllipse(const py::handle& center, const py::handle& au, const py::handle& av, bool two_sided) {
    EllipseLight<T> light{ReadVec3s<T>(center, "center", false)[0], ReadVec3s<T>(au, "axis_u", false)[0],
                          ReadVec3s<T>(av, "axis_v", false)[0], two_sided};
    const std::string problem = ValidateEllipseLight(light);
    if (!problem.empty()) throw py::value_error(problem);
    CheckFloat32Range(light.axis_u, "axis_u", true);
    CheckFloat32Range(light.axis_v, "axis_v", true);
    return light;
}

template <class T>
using EllipseCall = Call<T, EllipseLight<T>>;

// Neither ellipse technique uses the shading normal; it is accepted (and checked) for symmetry
// with sample() and the renderer's sampler interface.
template <class T>
EllipseCall<T> ReadEllipseCall(const py::object& origin, const py::object& center, const py::object& au,
                               const py::object& av, const py::object& normal, bool two_sided) {
    return {ReadEllipse<T>(center, au, av, two_sided), ReadVec3s<T>(origin, "origin", true),
            ReadNormals<T>(Technique::Area, normal)};
}

template <class T, class F>
void ForEachEllipseRow(EllipseTechnique technique, const EllipseCall<T>& s, size_t n, F&& per) {
    const EllipseLightFrame<T> frame = MakeEllipseLightFrame(s.light);
    DispatchEllipseTechnique(technique,
                             [&](auto tag) { RunRows<EllipseSampler<decltype(tag)::value, T>>(s, frame, n, per); });
}

template <class T>
py::tuple SampleEllipseImpl(EllipseTechnique technique, const py::object& origin, const py::object& center,
                            const py::object& au, const py::object& av, const py::object& uv_obj,
                            const py::object& normal, bool two_sided) {
    const EllipseCall<T> s = ReadEllipseCall<T>(origin, center, au, av, normal, two_sided);
    return SampleRows<T>(s, uv_obj, false, [&](size_t n, auto&& per) { ForEachEllipseRow(technique, s, n, per); });
}

template <class T>
py::array EllipsePDFImpl(EllipseTechnique technique, const py::object& origin, const py::object& center,
                         const py::object& au, const py::object& av, const py::object& points_obj,
                         const py::object& normal, bool two_sided) {
    const EllipseCall<T> s = ReadEllipseCall<T>(origin, center, au, av, normal, two_sided);
    return PDFRows<T>(s, points_obj, [&](size_t n, auto&& per) { ForEachEllipseRow(technique, s, n, per); });
}

template <class T>
py::array InvertEllipseImpl(const py::object& origin, const py::object& center, const py::object& au,
                            const py::object& av, const py::object& points_obj, bool two_sided) {
    const EllipseLight<T> light = ReadEllipse<T>(center, au, av, two_sided);
    const EllipseLightFrame<T> frame = MakeEllipseLightFrame(light);
    return InvertRows<T>(
        light, origin, points_obj, [&](const Vec3<T>& o) { return MakeSphericalEllipseSetup(o, frame); },
        [](const SphericalEllipseSetup<T>& r, const Vec3<T>& p) { return InvertSphericalEllipse(r, p); });
}

template <class T>
py::object EllipseSolidAngleImpl(const py::object& origin, const py::object& center, const py::object& au,
                                 const py::object& av, bool two_sided) {
    const EllipseLight<T> light = ReadEllipse<T>(center, au, av, two_sided);
    return SolidAngleRows<T>(origin, [&](const Vec3<T>& o) { return EllipseSolidAngle(o, light); });
}

py::array PatternImpl(const std::string& name, const py::object& n_obj, const py::object& seed_obj) {
    Pattern p;
    ParseEnumNameOrThrow("pattern", "patterns", name, kAllPatterns, PatternName, &p);
    // n must fit the core's uint32 index; a cap well below that keeps a typo from exhausting memory.
    const uint32_t n = uint32_t(ToInteger(n_obj, "n", 1u << 28));
    const uint64_t seed = ToInteger(seed_obj, "seed", std::numeric_limits<uint64_t>::max());
    py::array_t<float> out = NewArray<float>(n, 2);
    static_assert(sizeof(Point2<float>) == 2 * sizeof(float), "Point2<float> must be two packed floats");
    auto* pts = reinterpret_cast<Point2<float>*>(out.mutable_data());
    {
        py::gil_scoped_release release;
        GeneratePattern(p, n, seed, pts);
    }
    return std::move(out);
}

}  // namespace

// rectangle_ltc's glossy part alone -- its LTC map without the mixture with rectangle_projected (technique.h) -- as a
// sampler RunRows runs with the call's lobe: what the tests' chi-square of that map takes (_rectangle_ltc_sample/_pdf).
template <class T>
struct LtcGlossyPart {
    RectangleLtcSetup<T> setup;
    LtcGlossyPart(const Vec3<T>& origin, const Vec3<T>& normal, const RectLight<T>& light, const GlossyLobe<T>& lobe)
        : setup(MakeRectangleLtcSetup(origin, normal, lobe.wo, lobe.alpha, light)) {}
    LightSample<T> Sample(Point2<T> uv) const { return SampleRectangleLtc(setup, uv); }
    T PDF(const Vec3<T>& p) const { return RectangleLtcPDF(setup, p); }
};

template <class T>
Setup<T> ReadLtcGlossyPartSetup(const py::object& origin, const py::object& corner, const py::object& ex,
                                const py::object& ey, const py::object& normal, const py::object& wo, double alpha,
                                bool two_sided) {
    return ReadSetup<T>(Technique::RectangleLtc, origin, corner, ex, ey, normal, two_sided,
                        LobeArguments{wo, py::float_(alpha)});
}

template <class T>
py::tuple LtcSampleImpl(const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
                        const py::object& uv_obj, const py::object& normal, const py::object& wo, double alpha,
                        bool two_sided) {
    const Setup<T> s = ReadLtcGlossyPartSetup<T>(origin, corner, ex, ey, normal, wo, alpha, two_sided);
    return SampleRows<T>(s, uv_obj, false,
                         [&](size_t n, auto&& per) { RunRows<LtcGlossyPart<T>>(s, s.light, n, per); });
}

template <class T>
py::array LtcPDFImpl(const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
                     const py::object& points_obj, const py::object& normal, const py::object& wo, double alpha,
                     bool two_sided) {
    const Setup<T> s = ReadLtcGlossyPartSetup<T>(origin, corner, ex, ey, normal, wo, alpha, two_sided);
    return PDFRows<T>(s, points_obj, [&](size_t n, auto&& per) { RunRows<LtcGlossyPart<T>>(s, s.light, n, per); });
}

void BindCore(py::module_& m) {
    using py::arg;
    m.attr("techniques") = NameTuple(kAllTechniques, TechniqueName);
    m.attr("patterns") = NameTuple(kAllPatterns, PatternName);

    m.def(
        "solid_angle",
        [](const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
           const py::object& dtype, bool two_sided) -> py::object {
            if (ToPrecision(dtype) == Precision::Float64)
                return SolidAngleImpl<double>(origin, corner, ex, ey, two_sided);
            return SolidAngleImpl<float>(origin, corner, ex, ey, two_sided);
        },
        arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"), arg("dtype") = "float32", arg("two_sided") = true,
        R"doc(Solid angle subtended by the rectangle (corner, edge_x, edge_y) seen from origin.

origin: shape (3,) -> float; shape (N, 3) -> array [N] of dtype.  0 for a degenerate light,
an origin in the light's plane, or behind a one-sided (two_sided=False) light.)doc");

    auto sample = [](bool with_directions) {
        return
            [with_directions](const std::string& technique, const py::object& origin, const py::object& corner,
                              const py::object& ex, const py::object& ey, const py::object& uv,
                              const py::object& normal, const py::object& dtype, bool two_sided, const py::object& wo,
                              const py::object& alpha, double glossy_weight, double rest_weight) -> py::tuple {
                const Technique t = ToTechnique(technique);
                const LobeArguments lobe{wo, alpha, glossy_weight, rest_weight};
                if (ToPrecision(dtype) == Precision::Float64)
                    return SampleImpl<double>(t, origin, corner, ex, ey, uv, normal, two_sided, with_directions, lobe);
                return SampleImpl<float>(t, origin, corner, ex, ey, uv, normal, two_sided, with_directions, lobe);
            };
    };
    m.def("sample", sample(false), arg("technique"), arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"),
          arg("uv"), arg("normal") = py::none(), arg("dtype") = "float32", arg("two_sided") = true,
          arg("wo") = py::none(), arg("alpha") = py::none(), arg("glossy_weight") = 1.0, arg("rest_weight") = 0.0,
          R"doc(Warp points uv [N, 2] of [0,1]^2 onto the rectangle with a technique.

Returns (points [N, 3], pdf [N]); pdf is with respect to solid angle at origin, 0 for an
invalid sample.  origin (and normal) may be (3,) or (N, 3).  technique is one of
sphrect.techniques; 'rectangle_cosine', 'rectangle_projected' and 'rectangle_ltc' need the shading normal.  dtype
'float32' runs the renderer's single-precision code, 'float64' the double-precision one.  rectangle_ltc follows the
GGX lobe of roughness parameter alpha seen from wo (shape (3,), towards the viewer) mixed with rectangle_projected by
the weights glossy_weight and rest_weight (the renderer's: the lobe's sampling probability and the rest's); without
wo and alpha it samples as rectangle_projected.)doc");
    m.def("sample_directions", sample(true), arg("technique"), arg("origin"), arg("corner"), arg("edge_x"),
          arg("edge_y"), arg("uv"), arg("normal") = py::none(), arg("dtype") = "float32", arg("two_sided") = true,
          arg("wo") = py::none(), arg("alpha") = py::none(), arg("glossy_weight") = 1.0, arg("rest_weight") = 0.0,
          "Like sample(), but returns (points [N, 3], directions [N, 3], distances [N], pdf [N]).");

    m.def(
        "pdf",
        [](const std::string& technique, const py::object& origin, const py::object& corner, const py::object& ex,
           const py::object& ey, const py::object& points, const py::object& normal, const py::object& dtype,
           bool two_sided, const py::object& wo, const py::object& alpha, double glossy_weight,
           double rest_weight) -> py::array {
            const Technique t = ToTechnique(technique);
            const LobeArguments lobe{wo, alpha, glossy_weight, rest_weight};
            if (ToPrecision(dtype) == Precision::Float64)
                return PDFImpl<double>(t, origin, corner, ex, ey, points, normal, two_sided, lobe);
            return PDFImpl<float>(t, origin, corner, ex, ey, points, normal, two_sided, lobe);
        },
        arg("technique"), arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"), arg("points"),
        arg("normal") = py::none(), arg("dtype") = "float32", arg("two_sided") = true, arg("wo") = py::none(),
        arg("alpha") = py::none(), arg("glossy_weight") = 1.0, arg("rest_weight") = 0.0,
        R"doc(Solid-angle pdf [N] with which the technique picks each of points [N, 3] (on the light) from origin.

A point off the light -- farther than 1e-3 of its longest edge plus 1e-5 of the point's largest
coordinate from its plane or beyond its edges -- gets pdf 0.)doc");

    m.def(
        "invert",
        [](const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
           const py::object& points, const py::object& dtype, bool two_sided, const std::string& technique,
           const py::object& normal) -> py::array {
            const Technique t = ToTechnique(technique);
            const bool f64 = ToPrecision(dtype) == Precision::Float64;
            if (t == Technique::RectangleProjected)
                return f64 ? InvertProjectedImpl<double>(origin, corner, ex, ey, points, normal, two_sided)
                           : InvertProjectedImpl<float>(origin, corner, ex, ey, points, normal, two_sided);
            if (t != Technique::Rectangle)
                throw py::value_error("invert supports technique 'rectangle' or 'rectangle_projected', got '" +
                                      technique + "'");
            return f64 ? InvertImpl<double>(origin, corner, ex, ey, points, two_sided)
                       : InvertImpl<float>(origin, corner, ex, ey, points, two_sided);
        },
        arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"), arg("points"), arg("dtype") = "float32",
        arg("two_sided") = true, arg("technique") = "rectangle", arg("normal") = py::none(),
        R"doc(Inverse of a technique's map (technique 'rectangle', the default, or 'rectangle_projected',
which needs normal=): points [N, 3] on the light -> uv [N, 2].

Where the map switches formulation for an extreme configuration (as sample() does), the
inverse of that.  Rows whose configuration the map does not cover (degenerate light, origin in
the light's plane or behind a one-sided light) are NaN, and so are points off the light (the
tolerance of pdf()).)doc");

    m.def(
        "projected_solid_angle",
        [](const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
           const py::object& normal, const py::object& dtype, bool two_sided) -> py::object {
            if (ToPrecision(dtype) == Precision::Float64)
                return ProjectedSolidAngleImpl<double>(origin, corner, ex, ey, normal, two_sided);
            return ProjectedSolidAngleImpl<float>(origin, corner, ex, ey, normal, two_sided);
        },
        arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"), arg("normal"), arg("dtype") = "float32",
        arg("two_sided") = true,
        R"doc(Projected solid angle (integral of cos theta over the light's solid angle, the part above the
horizon of normal) of the rectangle seen from origin: the irradiance of a unit-radiance light,
Lambert's polygon formula.  origin (3,) -> float (computed in double), (N, 3) -> array [N].)doc");

    m.def(
        "_rectangle_ltc_sample",
        [](const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
           const py::object& uv, const py::object& normal, const py::object& wo, double alpha, const py::object& dtype,
           bool two_sided) -> py::tuple {
            if (ToPrecision(dtype) == Precision::Float64)
                return LtcSampleImpl<double>(origin, corner, ex, ey, uv, normal, wo, alpha, two_sided);
            return LtcSampleImpl<float>(origin, corner, ex, ey, uv, normal, wo, alpha, two_sided);
        },
        arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"), arg("uv"), arg("normal"), arg("wo"), arg("alpha"),
        arg("dtype") = "float32", arg("two_sided") = true,
        R"doc(rectangle_ltc's glossy part alone (the technique mixes it with rectangle_projected: sample();
docs/rectangle_ltc.md): points on the light with density proportional to the linearly transformed cosine fitted to
the isotropic GGX lobe of roughness alpha seen from wo (away from the surface like normal; wo: (3,)).

Returns (points [N, 3], pdf [N]) as sample().)doc");
    m.def(
        "_rectangle_ltc_pdf",
        [](const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
           const py::object& points, const py::object& normal, const py::object& wo, double alpha,
           const py::object& dtype, bool two_sided) -> py::array {
            if (ToPrecision(dtype) == Precision::Float64)
                return LtcPDFImpl<double>(origin, corner, ex, ey, points, normal, wo, alpha, two_sided);
            return LtcPDFImpl<float>(origin, corner, ex, ey, points, normal, wo, alpha, two_sided);
        },
        arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"), arg("points"), arg("normal"), arg("wo"),
        arg("alpha"), arg("dtype") = "float32", arg("two_sided") = true,
        R"doc(rectangle_ltc's glossy part's solid-angle pdf [N] of points [N, 3] on the light (0 off it, as pdf());
see _rectangle_ltc_sample.)doc");

    m.attr("ellipse_techniques") = NameTuple(kAllEllipseTechniques, EllipseTechniqueName);
    m.def(
        "ellipse_solid_angle",
        [](const py::object& origin, const py::object& center, const py::object& au, const py::object& av,
           const py::object& dtype, bool two_sided) -> py::object {
            if (ToPrecision(dtype) == Precision::Float64)
                return EllipseSolidAngleImpl<double>(origin, center, au, av, two_sided);
            return EllipseSolidAngleImpl<float>(origin, center, au, av, two_sided);
        },
        arg("origin"), arg("center"), arg("axis_u"), arg("axis_v"), arg("dtype") = "float32", arg("two_sided") = true,
        R"doc(Solid angle subtended by the ellipse (center, semi-axes axis_u, axis_v) seen from origin.

origin: shape (3,) -> float (computed in double from the dtype's inputs); shape (N, 3) -> array
[N] of dtype.  0 for an origin in the light's plane or behind a one-sided (two_sided=False)
light.  The axes must be non-zero and orthogonal (ValueError otherwise).)doc");
    m.def(
        "sample_ellipse",
        [](const std::string& technique, const py::object& origin, const py::object& center, const py::object& au,
           const py::object& av, const py::object& uv, const py::object& normal, const py::object& dtype,
           bool two_sided) -> py::tuple {
            const EllipseTechnique t = ToEllipseTechnique(technique);
            if (ToPrecision(dtype) == Precision::Float64)
                return SampleEllipseImpl<double>(t, origin, center, au, av, uv, normal, two_sided);
            return SampleEllipseImpl<float>(t, origin, center, au, av, uv, normal, two_sided);
        },
        arg("technique"), arg("origin"), arg("center"), arg("axis_u"), arg("axis_v"), arg("uv"),
        arg("normal") = py::none(), arg("dtype") = "float32", arg("two_sided") = true,
        R"doc(Warp points uv [N, 2] of [0,1]^2 onto the ellipse with an ellipse technique.

Returns (points [N, 3], pdf [N]); pdf is with respect to solid angle at origin, 0 for an invalid
sample.  technique is one of sphrect.ellipse_techniques ('area', 'spherical_ellipse'); origin
(and normal, unused by both) may be (3,) or (N, 3).  dtype 'float32' runs the renderer's
single-precision code, 'float64' the double-precision one.)doc");
    m.def(
        "ellipse_pdf",
        [](const std::string& technique, const py::object& origin, const py::object& center, const py::object& au,
           const py::object& av, const py::object& points, const py::object& normal, const py::object& dtype,
           bool two_sided) -> py::array {
            const EllipseTechnique t = ToEllipseTechnique(technique);
            if (ToPrecision(dtype) == Precision::Float64)
                return EllipsePDFImpl<double>(t, origin, center, au, av, points, normal, two_sided);
            return EllipsePDFImpl<float>(t, origin, center, au, av, points, normal, two_sided);
        },
        arg("technique"), arg("origin"), arg("center"), arg("axis_u"), arg("axis_v"), arg("points"),
        arg("normal") = py::none(), arg("dtype") = "float32", arg("two_sided") = true,
        "Solid-angle pdf [N] with which the ellipse technique picks each of points [N, 3] (on the light) from origin; "
        "0 off the light (pdf()'s tolerance).");
    m.def(
        "invert_ellipse",
        [](const py::object& origin, const py::object& center, const py::object& au, const py::object& av,
           const py::object& points, const py::object& dtype, bool two_sided) -> py::array {
            if (ToPrecision(dtype) == Precision::Float64)
                return InvertEllipseImpl<double>(origin, center, au, av, points, two_sided);
            return InvertEllipseImpl<float>(origin, center, au, av, points, two_sided);
        },
        arg("origin"), arg("center"), arg("axis_u"), arg("axis_v"), arg("points"), arg("dtype") = "float32",
        arg("two_sided") = true,
        R"doc(Inverse of the 'spherical_ellipse' map: points [N, 3] on the light -> uv [N, 2].

Where the map switches to area sampling for an extreme configuration (as sample_ellipse() does),
the inverse of that.  Rows whose configuration the map does not cover (origin in the light's
plane or behind a one-sided light) are NaN.)doc");

    m.def("pattern", &PatternImpl, arg("name"), arg("n"), arg("seed") = 0,
          R"doc(n points of a 2D sample pattern in [0,1)^2, float32 [n, 2].

name is one of sphrect.patterns; different seeds give decorrelated point sets.)doc");

    // The block sampler of textured rectangle lights (core/rectangle_blocks.h), float32: for its chi-square test.
    struct BlocksSetup {
        std::vector<float> radiance;
        RectangleBlocks b;
        RectLightFrame<float> frame;
        Vec3f origin;
        RectangleBlocksAt at;
    };
    auto setup = [](const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
                    const py::object& radiance_obj) {
        const ArrayD w = ArrayOf<double>(radiance_obj, "radiance");
        if (w.ndim() != 2 || w.shape(0) < 1 || w.shape(1) < 1 || w.shape(0) > kMaxRectangleBlocksPerSide ||
            w.shape(1) > kMaxRectangleBlocksPerSide)
            throw py::value_error("radiance must have shape (ny, nx), each in 1.." +
                                  std::to_string(kMaxRectangleBlocksPerSide) + ", got " + ShapeString(w));
        auto s = std::make_unique<BlocksSetup>();
        for (py::ssize_t k = 0; k < w.size(); ++k) {
            if (!(w.data()[k] >= 0) || !std::isfinite(w.data()[k])) throw py::value_error("radiance must be >= 0");
            s->radiance.push_back(float(w.data()[k]));
        }
        s->b = {int(w.shape(1)), int(w.shape(0)), s->radiance.data()};
        s->frame = MakeRectLightFrame(ReadLight<float>(corner, ex, ey, true));
        s->origin = ReadVec3s<float>(origin, "origin", false)[0];
        MakeRectangleBlocksAt(s->origin, s->frame, s->b, s->at);
        return s;
    };
    // The soft lights' sampler (core/cone.h): for measurements against other strategies.
    m.def(
        "sample_uniform_cone",
        [](double one_minus_cos, const py::object& uv_obj) {
            if (!(one_minus_cos > 0 && one_minus_cos <= 2)) throw py::value_error("one_minus_cos must be in (0, 2]");
            const auto uv = ReadUV<double>(uv_obj);
            py::array_t<double> dirs = NewArray<double>(uv.size(), 3), pdf = NewArray<double>(uv.size(), 0);
            double* D = dirs.mutable_data();
            double* Q = pdf.mutable_data();
            for (size_t i = 0; i < uv.size(); ++i) {
                const Vec3<double> w = SampleUniformCone(Point2<double>{uv[i][0], uv[i][1]}, one_minus_cos);
                D[3 * i] = w.x, D[3 * i + 1] = w.y, D[3 * i + 2] = w.z;
                Q[i] = UniformConePDF(one_minus_cos);
            }
            return py::make_tuple(dirs, pdf);
        },
        arg("one_minus_cos"), arg("uv"),
        "Directions uniform in the cone about +z of 1 - cos(half-angle) = one_minus_cos (core/cone.h, double): "
        "(directions [N, 3], solid-angle pdf [N]).  The sampler of soft point, spot and sun lights.");
    m.def(
        "sample_rectangle_blocks",
        [setup](const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
                const py::object& radiance, const py::object& uv_obj) {
            const auto s = setup(origin, corner, ex, ey, radiance);
            const auto uv = ReadUV<float>(uv_obj);
            py::array_t<float> points = NewArray<float>(uv.size(), 3), pdf = NewArray<float>(uv.size(), 0);
            float* P = points.mutable_data();
            float* Q = pdf.mutable_data();
            for (size_t i = 0; i < uv.size(); ++i) {
                const LightSample<float> ls =
                    SampleRectangleBlocks(s->origin, s->frame, s->b, s->at, Point2<float>{uv[i][0], uv[i][1]});
                P[3 * i] = ls.point.x, P[3 * i + 1] = ls.point.y, P[3 * i + 2] = ls.point.z;
                Q[i] = ls.pdf;
            }
            return py::make_tuple(points, pdf);
        },
        arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"), arg("radiance"), arg("uv"),
        "Points of the rectangle by block (radiance [ny, nx]: block (i, j) along (edge_x, edge_y)) by radiance x "
        "estimated solid angle, then by solid angle in the block: (points [N, 3], solid-angle pdf [N]).  The sampler "
        "of textured rectangle lights.");
    m.def(
        "rectangle_blocks_pdf",
        [setup](const py::object& origin, const py::object& corner, const py::object& ex, const py::object& ey,
                const py::object& radiance, const py::object& points_obj) {
            const auto s = setup(origin, corner, ex, ey, radiance);
            const auto pts = ReadRows<float, 3>(points_obj, "points", false);
            py::array_t<float> pdf = NewArray<float>(pts.size(), 0);
            float* Q = pdf.mutable_data();
            for (size_t i = 0; i < pts.size(); ++i)
                Q[i] = RectangleBlocksPDF(s->origin, s->frame, s->b, s->at, Vec3f(pts[i][0], pts[i][1], pts[i][2]));
            return pdf;
        },
        arg("origin"), arg("corner"), arg("edge_x"), arg("edge_y"), arg("radiance"), arg("points"),
        "Solid-angle pdf of sample_rectangle_blocks at points of the rectangle.");
}

}  // namespace sphrect::python
