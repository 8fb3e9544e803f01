// PLACEHOLDER: bindings of the renderer (to be written).
#include <pybind11/pybind11.h>
namespace sphrect::python {
void BindRender(pybind11::module_& m) {}
}
