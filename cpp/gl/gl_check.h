// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Turns the GL error flag into an exception naming the stage that raised it, the GL debug
// mode (the dispatch and sync counts are compute/device.h's).
#include <cstdint>
#include <string>

namespace hf::gl {

// Throws hf::GlError("<stage>: GL_INVALID_OPERATION ...") if glGetError() reports anything.
// Used always where it costs no pipeline drain: allocation, compile/link, uploads and read-backs
// (every step reads something back, so a step's errors surface by its end).
void checkGl(const std::string& stage);

// Name of a GL error enum, e.g. "GL_OUT_OF_MEMORY".
const char* glErrorName(unsigned int code);

// The environment variable that turns the debug mode on ("1").
inline constexpr const char* kGlDebugEnv = "HAPTICFLUID_GL_DEBUG";

// Debug mode: every dispatch checks glGetError and the KHR_debug messages of type error (a
// debug context is asked for, with synchronous output), throwing hf::GlError naming the
// stage. Off by default: glGetError after a dispatch waits for the driver on a GPU. Starts as
// HAPTICFLUID_GL_DEBUG=1 says; setDebugMode() changes it for contexts made afterwards too.
bool debugMode();
void setDebugMode(bool on);
// On the current context: enables KHR_debug output into the callback checkDebug() reads.
void installDebugOutput();
// In debug mode, checkGl(stage) plus the debug messages of type error since the last check.
void checkDebug(const std::string& stage);

}  // namespace hf::gl
