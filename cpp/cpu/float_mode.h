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
// The device's thread (the one that makes it: makeCpuDevice) and the pool's workers set the mode
// for good; a dispatch holds a FlushDenormals besides, which sets the mode on a thread without it
// for the dispatch and restores the thread's own after (writing MXCSR costs: on the device's
// thread it writes nothing).
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace hf::cpu {

#if defined(__x86_64__) || defined(__i386__)
inline constexpr unsigned kFlushDenormalsBits = 0x8040u;  // MXCSR: FTZ (bit 15), DAZ (bit 6)

// Sets the mode on the calling thread for good (the device's thread, the pool's workers).
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
