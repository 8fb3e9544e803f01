// The names of an enum's values as a Python tuple: how the module exports every name list
// (techniques, patterns, MIS modes, medium sampling) once, for the package and the add-on.
#pragma once

#include <pybind11/pybind11.h>

namespace sphrect::python {

template <class Values, class NameOf>
pybind11::tuple NameTuple(const Values& values, NameOf name_of) {
    pybind11::list l;
    for (auto v : values) l.append(name_of(v));
    return pybind11::tuple(l);
}

}  // namespace sphrect::python
