// SPDX-License-Identifier: GPL-3.0-or-later
// Engine exceptions -> Python, one class each, so callers decide by type, never by message text:
//   hf::Error                     -> HapticFluidError (a RuntimeError)
//   hf::InvalidArgument           -> InvalidArgumentError (also a ValueError)
//   obstacle::MeshNotClosed       -> MeshNotClosedError (an InvalidArgumentError)
//   hf::GlError                   -> GlError
//   falcon::UsbNotFound           -> DeviceNotFoundError      (a DeviceError)
//   falcon::UsbAccessDenied       -> DeviceAccessDeniedError  (a DeviceError)
//   falcon::UsbUnplugged          -> DeviceUnpluggedError     (a DeviceError)
//   hf::DeviceError (any other)   -> DeviceError
//   io::VdbError                  -> VdbError
#include <Python.h>

#include <cstring>

#include "common/error.h"
#include "haptics/falcon/usb_transport.h"
#include "io/vdb_writer.h"
#include "obstacle/triangle_mesh.h"
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

// A new exception class hapticfluid._core.<name>, added to the module.
py::handle newError(py::module_& m, const char* name, const char* doc, py::tuple bases) {
  const std::string qualified = std::string("hapticfluid._core.") + name;
  py::handle type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  m.add_object(name, type);
  return type;
}

struct Types {
  py::handle base, invalid, mesh_not_closed, gl, device, not_found, access_denied, unplugged, vdb;
};

}  // namespace

void addErrors(py::module_& m) {
  static Types t;  // the classes live as long as the module (held by it)
  t.base = newError(m, "HapticFluidError", "A failure of the engine; the message says what to change.",
                    py::make_tuple(py::handle(PyExc_RuntimeError)));
  t.invalid = newError(m, "InvalidArgumentError", "An argument the engine cannot use; the message names it.",
                       py::make_tuple(t.base, py::handle(PyExc_ValueError)));
  t.mesh_not_closed = newError(m, "MeshNotClosedError",
                               "A mesh that is not closed and consistently oriented; the message says where.",
                               py::make_tuple(t.invalid));
  t.gl = newError(m, "GlError", "A GL or EGL call failed (driver, context, shader); the message names the stage.",
                  py::make_tuple(t.base));
  t.device = newError(m, "DeviceError", "A haptic device could not be found, opened or kept.", py::make_tuple(t.base));
  t.not_found = newError(m, "DeviceNotFoundError", "No device of the kind asked for is plugged in.",
                         py::make_tuple(t.device));
  t.access_denied = newError(m, "DeviceAccessDeniedError",
                             "This user may not open the device; the message ends with the udev rule to install.",
                             py::make_tuple(t.device));
  t.unplugged = newError(m, "DeviceUnpluggedError", "The device was unplugged or powered off.",
                         py::make_tuple(t.device));
  t.vdb = newError(m, "VdbError", "An OpenVDB file could not be written or read (disk, permissions, format).",
                   py::make_tuple(t.base));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const obstacle::MeshNotClosed& e) {
      setError(t.mesh_not_closed, e.what());
    } catch (const InvalidArgument& e) {
      setError(t.invalid, e.what());
    } catch (const GlError& e) {
      setError(t.gl, e.what());
    } catch (const haptics::falcon::UsbNotFound& e) {
      setError(t.not_found, e.what());
    } catch (const haptics::falcon::UsbAccessDenied& e) {
      setError(t.access_denied, e.what());
    } catch (const haptics::falcon::UsbUnplugged& e) {
      setError(t.unplugged, e.what());
    } catch (const DeviceError& e) {
      setError(t.device, e.what());
    } catch (const io::VdbError& e) {
      setError(t.vdb, e.what());
    } catch (const Error& e) {
      setError(t.base, e.what());
    }
  });
}

}  // namespace hf::python
