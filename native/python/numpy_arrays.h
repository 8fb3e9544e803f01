// Arrays from Python (numpy arrays or anything array-like), read one way by every binding file.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

namespace sphrect::python {

namespace py = pybind11;

// A C-contiguous array of T: a view of the caller's array, or a converted copy when its dtype or layout differ.
template <class T>
using CArray = py::array_t<T, py::array::c_style | py::array::forcecast>;

// "(2, 3)" / "(3,)": an array's shape as numpy prints it, for messages.
inline std::string ShapeString(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

// `obj` as a CArray<T>, or ValueError naming `what`.
template <class T>
CArray<T> ArrayOf(const py::handle& obj, const std::string& what) {
    if (obj.is_none()) throw py::value_error(what + " is required");
    CArray<T> a = CArray<T>::ensure(obj);
    if (!a) {
        PyErr_Clear();
        throw py::value_error(what + " must be a numeric array-like, got " + std::string(py::repr(obj)));
    }
    return a;
}

// ArrayOf of shape (N, width), or also (width,) -- one row -- when allow_single.
template <class T>
CArray<T> RowsOf(const py::handle& obj, py::ssize_t width, const std::string& what, bool allow_single = false) {
    CArray<T> a = ArrayOf<T>(obj, what);
    const bool single = allow_single && a.ndim() == 1 && a.shape(0) == width;
    if (!single && !(a.ndim() == 2 && a.shape(1) == width)) {
        const std::string w = std::to_string(width);
        throw py::value_error(what + " must have shape " + (allow_single ? "(" + w + ",) or " : "") + "(N, " + w +
                              "), got " + ShapeString(a));
    }
    return a;
}

}  // namespace sphrect::python
