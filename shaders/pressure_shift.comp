// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pressure_shift": in a closed box the pressure is defined up to a constant, and float
// rounding makes that constant drift from step to step; this subtracts the mean over fluid cells
// (summed by pressure_sum + reduce into results[u_slot]) so it stays at 0. The same removes the
// rhs's mean before the solve (the closed box's compatibility condition). Per-texel update.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RW(r32f, 0, u_pressure);
UIMAGE_RO(r8ui, 2, u_nbmask);
BUFFER_RO(Results, vec4, 1, results);

UNIFORM(uint, u_slot);

// The mean the sum stage found over the fluid cells (results[u_slot]: sum, fluid cells).
float fluidMean() { return meanOverFluid(results[u_slot]); }

// Cell c's pressure with `mean` taken from it in a fluid cell (unchanged in a solid one).
// Branch-free: the CPU's row loop (cpu/kernels/pressure_shift.cpp) vectorizes it.
float shiftedPressure(ivec3 c, float mean) {
  float p = imageLoad(u_pressure, c).x;
  return (imageLoad(u_nbmask, c).x & NB_SOLID) != 0u ? p : p - mean;
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  imageStore(u_pressure, c, vec4(shiftedPressure(c, fluidMean())));
}
