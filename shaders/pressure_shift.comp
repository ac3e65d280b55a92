// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pressure_shift": in a closed box the pressure is defined up to a constant, and float
// rounding makes that constant drift from step to step; this subtracts the mean over fluid cells
// (summed by pressure_sum + reduce into results[u_slot]) so it stays at 0. The same removes the
// rhs's mean before the solve (the closed box's compatibility condition). Per-texel update.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) uniform image3D u_pressure;
layout(r8ui, binding = 2) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 1) readonly buffer Results { vec4 results[]; };

uniform uint u_slot;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c) || (imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) return;
  vec4 sum = results[u_slot];
  float mean = sum.y > 0.0 ? sum.x / sum.y : 0.0;
  imageStore(u_pressure, c, vec4(imageLoad(u_pressure, c).r - mean));
}
