// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The engine's exception types. Every failure that crosses the API is one of these or a subclass
// defined by its layer (obstacle::MeshNotClosed, falcon::UsbUnplugged, io::VdbError, ...); the
// Python bindings (python/bind_errors.cpp) give each its own Python class under
// hapticfluid.HapticFluidError, so callers decide by type, never by message text.
#include <stdexcept>
#include <string>

namespace hf {

// Any engine failure: GL/EGL errors, shader compile errors, resource exhaustion.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A caller passed a value the engine cannot use; the message says which and what to do.
class InvalidArgument : public Error {
 public:
  using Error::Error;
};

// A GL or EGL call failed; the message names the stage that made it.
class GlError : public Error {
 public:
  using Error::Error;
};

// A haptic device could not be found, opened or kept (the haptic loop's failures are these).
class DeviceError : public Error {
 public:
  using Error::Error;
};

}  // namespace hf
