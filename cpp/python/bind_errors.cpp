// Engine exceptions -> Python: hf::InvalidArgument -> InvalidArgumentError (a ValueError and a
// HapticFluidError); every other hf::Error -> HapticFluidError (a RuntimeError).
#include <Python.h>

#include <cstring>

#include "common/error.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace hf::python {
namespace {

// Sets the Python error from an engine message. The message may quote input bytes that are not
// UTF-8 (a line of a CSV file, a path); PyErr_SetString would then fail to decode it and leave an
// exception with no message at all, so bad bytes are shown as \xNN escapes instead.
void setError(py::handle type, const char* what) {
  PyObject* text = PyUnicode_DecodeUTF8(what, static_cast<Py_ssize_t>(std::strlen(what)), "backslashreplace");
  if (!text) {
    PyErr_Clear();
    PyErr_SetString(type.ptr(), "(the engine's error message could not be decoded)");
    return;
  }
  PyErr_SetObject(type.ptr(), text);
  Py_DECREF(text);
}

}  // namespace

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
      setError(invalid, e.what());
    } catch (const Error& e) {
      setError(base, e.what());
    }
  });
}

}  // namespace hf::python
