// The `sphrect._native` extension: one module, bound in two parts so the
// sampling core does not depend on the renderer.
#include <pybind11/pybind11.h>

namespace sphrect::python {
void BindCore(pybind11::module_& m);         // bind_core.cpp: techniques, patterns
void BindRender(pybind11::module_& m);       // bind_render.cpp: the renderer
void BindMaterial(pybind11::module_& m);     // bind_material.cpp: materials
void BindStudy(pybind11::module_& m);        // bind_study.cpp: baselines for the study's accuracy table
void BindSvmColor(pybind11::module_& m);     // bind_svm_color.cpp: colour and shading-input nodes (svm_color)
void BindSvmTextures(pybind11::module_& m);  // bind_svm_textures.cpp: Cycles' procedural textures, for tests
}  // namespace sphrect::python

PYBIND11_MODULE(_native, m) {
    m.doc() = "sphrect native core: spherical-rectangle sampling and the Embree renderer";
    sphrect::python::BindCore(m);
    sphrect::python::BindRender(m);
    sphrect::python::BindMaterial(m);
    sphrect::python::BindStudy(m);
    sphrect::python::BindSvmColor(m);
    sphrect::python::BindSvmTextures(m);
}
