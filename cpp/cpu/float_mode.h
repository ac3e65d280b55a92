// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The CPU backend runs its kernels with denormal floats flushed to zero (MXCSR's FTZ and DAZ): GLSL
// lets a shader flush any denormal input or result to 0 (GLSL 4.60, 4.7.1), and many GPUs do.
// Without it a decaying field's tiny values take the x86 cores' slow path for denormal operands
// and results: after 40 steps of the 32^3 live scene 9 % of the density and temperature cells are
// denormal, the scalar pair's advection cost three times a velocity component's (at the seed grid,
// where they are not, 1.3 times, as its lookups say) and the step 7.8 ms against 6.2. llvmpipe
// keeps them, so there the backends differ by at most the smallest normal float (1.2e-38).
//
// A dispatch holds a FlushDenormals (CpuProgram::dispatch, dispatchSeries): the dispatching thread
// flushes for the dispatch only, so the host code that the device's thread runs between them
// keeps IEEE denormals, as it does beside the GL device (GLSL's licence is the shader's); the two
// MXCSR writes a dispatch cost nothing measurable (32^3 on one thread 6.20-6.27 ms a step against
// 6.14-6.43 with the mode set for good). The pool's workers run nothing but kernels' chunks and
// set the mode for good.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace hf::cpu {

#if defined(__x86_64__) || defined(__i386__)
inline constexpr unsigned kFlushDenormalsBits = 0x8040u;  // MXCSR: FTZ (bit 15), DAZ (bit 6)

// Sets the mode on the calling thread for good (the pool's workers).
inline void flushDenormalsOnThisThread() { _mm_setcsr(_mm_getcsr() | kFlushDenormalsBits); }

class FlushDenormals {
 public:
  FlushDenormals() : saved_(_mm_getcsr()) {
    if ((saved_ & kFlushDenormalsBits) != kFlushDenormalsBits) _mm_setcsr(saved_ | kFlushDenormalsBits);
  }
  ~FlushDenormals() {
    if ((saved_ & kFlushDenormalsBits) != kFlushDenormalsBits) _mm_setcsr(saved_);
  }
  FlushDenormals(const FlushDenormals&) = delete;
  FlushDenormals& operator=(const FlushDenormals&) = delete;

 private:
  unsigned saved_;
};
#else
inline void flushDenormalsOnThisThread() {}
class FlushDenormals {};
#endif

}  // namespace hf::cpu
