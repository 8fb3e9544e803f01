// PLACEHOLDER: bindings of the sampling core (to be written).
#include <pybind11/pybind11.h>
namespace sphrect::python {
void BindCore(pybind11::module_& m) {}
}
