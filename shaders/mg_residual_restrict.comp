// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_residual_restrict": mg_residual and mg_restrict in one pass. Per coarse cell, the
// fine residual b - A x of each fluid child (A as in mg_smooth.comp, the same arithmetic as
// mg_residual.comp) summed and scaled as mg_restrict.comp does: b_c = u_scale * sum. The fine
// residual is never stored (one full-grid write and read and one dispatch fewer per level).
// Dispatched over the coarse grid (u_res is the coarse resolution).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_x;
layout(r32f, binding = 2) readonly uniform image3D u_b;
layout(r8ui, binding = 3) readonly uniform uimage3D u_mask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_faces;
layout(r32f, binding = 0) uniform writeonly image3D u_coarse_b;

uniform ivec3 u_fine_size;  // fine cells per axis
uniform float u_scale;      // coarse operator scaling (see MultigridVCycle::kCoarseScale)

void main() {
  ivec3 C = ivec3(gl_GlobalInvocationID);
  if (!inGrid(C)) return;
  float sum = 0.0;
  for (int o = 0; o < 8; ++o) {
    ivec3 c = 2 * C + ivec3(o & 1, (o >> 1) & 1, (o >> 2) & 1);
    if (any(greaterThanEqual(c, u_fine_size))) continue;
    uint m = imageLoad(u_mask, c).r;
    if ((m & NB_SOLID) != 0u) continue;
    float x = imageLoad(u_x, c).r;
    float w[6];
    FACE_OPEN_ALL(u_faces, c, w);
    float ax = (m & NB_OPEN_TOP) != 0u ? w[5] * x : 0.0;
    for (int d = 0; d < 6; ++d) {
      if (((m >> uint(d)) & 1u) != 0u) ax += w[d] * (x - imageLoad(u_x, c + NEIGHBOUR[d]).r);
    }
    sum += imageLoad(u_b, c).r - ax;
  }
  imageStore(u_coarse_b, C, vec4(u_scale * sum));
}
