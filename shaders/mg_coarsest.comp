// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_coarsest": the V-cycle's coarsest-level solve in one dispatch, the same arithmetic as
// 4 x u_pairs dispatches of mg_smooth.comp (u_pairs symmetric pairs: red->black u_pairs times,
// the first from x = 0, then black->red u_pairs times), so the result is the same to the bit.
// The level has at most COARSEST cells per axis: one workgroup, one invocation per cell, x in
// shared memory, a barrier between half-sweeps (one dispatch instead of 4 u_pairs, each with its
// barrier and launch; on llvmpipe a dispatch of 48 cells costs about as much as one of 48 000).
layout(local_size_x = COARSEST, local_size_y = COARSEST, local_size_z = COARSEST) in;

layout(r32f, binding = 0) uniform writeonly image3D u_x;
layout(r32f, binding = 1) readonly uniform image3D u_b;
layout(r8ui, binding = 2) readonly uniform uimage3D u_mask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_faces;

uniform int u_pairs;  // symmetric pairs of red-black sweeps (MultigridVCycle::kCoarsestSweeps)

shared float s_x[COARSEST * COARSEST * COARSEST];

int slot(ivec3 c) { return c.x + COARSEST * (c.y + COARSEST * c.z); }

void main() {
  ivec3 c = ivec3(gl_LocalInvocationID);
  bool in_grid = inGrid(c);
  uint m = in_grid ? imageLoad(u_mask, c).r : NB_SOLID;
  float w[6] = float[6](0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  if (in_grid) FACE_OPEN_ALL(u_faces, c, w);
  float n = (m & NB_OPEN_TOP) != 0u ? w[5] : 0.0;
  for (int d = 0; d < 6; ++d) {
    if (((m >> uint(d)) & 1u) != 0u) n += w[d];
  }
  bool live = (m & NB_SOLID) == 0u && n != 0.0;
  float b = in_grid ? imageLoad(u_b, c).r : 0.0;
  int colour = (c.x + c.y + c.z) & 1;
  s_x[slot(c)] = 0.0;
  memoryBarrierShared();
  barrier();
  // Half-sweep h updates colour order[h % 2]: red, black for the first u_pairs pairs, then
  // black, red.
  for (int h = 0; h < 4 * u_pairs; ++h) {
    int want = h < 2 * u_pairs ? (h & 1) : 1 - (h & 1);
    if (colour == want && live) {
      float sum = 0.0;
      for (int d = 0; d < 6; ++d) {
        if (((m >> uint(d)) & 1u) != 0u) sum += w[d] * s_x[slot(c + NEIGHBOUR[d])];
      }
      s_x[slot(c)] = (b + sum) / n;
    }
    memoryBarrierShared();
    barrier();
  }
  if (in_grid) imageStore(u_x, c, vec4(s_x[slot(c)]));
}
