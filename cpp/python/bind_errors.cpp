// Engine exceptions -> Python: hf::InvalidArgument -> InvalidArgumentError (a ValueError and a
// HapticFluidError); every other hf::Error -> HapticFluidError (a RuntimeError).
#include <Python.h>

#include "common/error.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace hf::python {

void addErrors(py::module_& m) {
  static py::handle base;
  static py::handle invalid;
  base = PyErr_NewExceptionWithDoc("hapticfluid._core.HapticFluidError",
                                   "A failure of the engine (GL/EGL, shaders, resources).", PyExc_RuntimeError, nullptr);
  py::tuple bases = py::make_tuple(base, py::handle(PyExc_ValueError));
  invalid = PyErr_NewExceptionWithDoc("hapticfluid._core.InvalidArgumentError",
                                      "An argument the engine cannot use; the message says what to change.",
                                      bases.ptr(), nullptr);
  m.add_object("HapticFluidError", base);
  m.add_object("InvalidArgumentError", invalid);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidArgument& e) {
      PyErr_SetString(invalid.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(base.ptr(), e.what());
    }
  });
}

}  // namespace hf::python
