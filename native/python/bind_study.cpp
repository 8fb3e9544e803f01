// Bindings for the comparative study only (python/sphrect/study/sampler_table.py): the textbook
// single-precision spherical-rectangle map (core/textbook_rectangle.h), which is a baseline and
// not a technique, the hard-case suite (core/hard_cases.h) and the cost table's timings
// (core/sampler_timing.h), so that the study needs nothing from a build tree.  They stay out of
// the public sampling API.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/hard_cases.h"
#include "core/rect_light.h"
#include "core/sampler_timing.h"
#include "core/textbook_rectangle.h"
#include "numpy_arrays.h"

namespace py = pybind11;

namespace sphrect::python {
namespace {

Vec3f ReadVec3f(const py::handle& obj, const char* name) {
    const CArray<float> a = ArrayOf<float>(obj, name);
    if (a.ndim() != 1 || a.shape(0) != 3)
        throw py::value_error(std::string(name) + " must have shape (3,), got " + ShapeString(a));
    const float* p = a.data();
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        throw py::value_error(std::string(name) + " contains NaN or Inf");
    return {p[0], p[1], p[2]};
}

// (points [N,3], pdf [N], solid angle) of the textbook float map, for uv [N,2].
py::tuple TextbookRectangleSample(const py::object& origin, const py::object& corner, const py::object& ex,
                                  const py::object& ey, const py::object& uv_rows) {
    const CArray<float> uv = RowsOf<float>(uv_rows, 2, "uv");
    RectLight<float> light{ReadVec3f(corner, "corner"), ReadVec3f(ex, "edge_x"), ReadVec3f(ey, "edge_y"), true};
    const Vec3f o = ReadVec3f(origin, "origin");
    const py::ssize_t n = uv.shape(0);
    py::array_t<float> points({n, py::ssize_t(3)}), pdf(n);
    float solid_angle;
    {
        py::gil_scoped_release release;
        const TextbookRectangle q = MakeTextbookRectangle(o, light);
        solid_angle = q.S;
        const float* in = uv.data();
        float* pts = points.mutable_data();
        float* pd = pdf.mutable_data();
        for (py::ssize_t i = 0; i < n; ++i) {
            const LightSample<float> s = SampleTextbookRectangle(q, in[2 * i], in[2 * i + 1]);
            pts[3 * i] = s.point.x;
            pts[3 * i + 1] = s.point.y;
            pts[3 * i + 2] = s.point.z;
            pd[i] = s.pdf;
        }
    }
    return py::make_tuple(points, pdf, solid_angle);
}

py::tuple ToTuple(const Vec3f& v) { return py::make_tuple(v.x, v.y, v.z); }

// [(name, origin, corner, edge_x, edge_y, normal, two_sided)] of the hard-case suite.
py::list HardCases() {
    py::list out;
    for (const HardCase& c : HardCaseSuite())
        out.append(py::make_tuple(c.name, ToTuple(c.origin), ToTuple(c.light.corner), ToTuple(c.light.ex),
                                  ToTuple(c.light.ey), ToTuple(c.normal), c.light.two_sided));
    return out;
}

// [(stage name, ns per call)] of the cost table, each stage run for at least min_seconds.
py::list SamplerTimings(double min_seconds) {
    std::vector<std::pair<std::string, double>> rows;
    {
        py::gil_scoped_release release;
        sampler_timing::ForEachStage([&](const std::string& name, const auto& stage) {
            rows.emplace_back(name, sampler_timing::NanosecondsPerCall(stage, min_seconds));
        });
    }
    py::list out;
    for (const auto& [name, ns] : rows) out.append(py::make_tuple(name, ns));
    return out;
}

}  // namespace

void BindStudy(py::module_& m) {
    m.def("_study_textbook_rectangle", &TextbookRectangleSample, py::arg("origin"), py::arg("corner"),
          py::arg("edge_x"), py::arg("edge_y"), py::arg("uv"),
          "Study baseline: the textbook single-precision rectangle map. Returns (points [N,3], pdf [N], "
          "solid angle). Not a technique; for sphrect.study's accuracy table only.");
    m.def("_study_hard_cases", &HardCases,
          "Study: the hard-case suite the C++ tests check, as [(name, origin, corner, edge_x, edge_y, normal, "
          "two_sided)] (float32 values).");
    m.attr("_study_hard_case_uv") = py::cast(HardCaseUV());
    m.def("_study_sampler_timings", &SamplerTimings, py::arg("min_seconds") = 0.2,
          "Study: [(\"<stage>/<technique>/<precision>\", ns per call)] of every technique's setup, sample and pdf "
          "and of the textbook map, as bench_sampling measures them.");
}

}  // namespace sphrect::python
