// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// numpy conversion that keeps MemoryError. pybind11's array::ensure() and array_t::ensure()
// return a null array on *any* failure and clear the Python error, so a copy that could not be
// allocated looked like "not an array" at best and was used as a null pointer at worst. Here a
// MemoryError propagates (as MemoryError, numpy's message saying how much was asked); any other
// failure gives a null array, which the caller reports naming its argument.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace hf::python {

namespace py = pybind11;

// A = py::array or py::array_t<T, Flags>.
template <class A>
A ensureArray(const py::handle& obj) {
  try {
    return A(py::reinterpret_borrow<py::object>(obj));  // the converting constructor throws on failure
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_MemoryError)) throw;
    return py::reinterpret_steal<A>(py::handle());  // null: not convertible
  }
}

}  // namespace hf::python
