#pragma once
// The engine's exception types. Every failure that crosses the API is one of these; the
// Python bindings map InvalidArgument to hapticfluid.InvalidArgumentError (a ValueError) and
// every other Error to hapticfluid.HapticFluidError.
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

}  // namespace hf
