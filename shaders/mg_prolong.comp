// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_prolong": x_fine += x_coarse of the parent cell (piecewise-constant interpolation)
// on fluid cells; per-texel update of the fine level. Dispatched over the fine grid.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) uniform image3D u_fine_x;
layout(r32f, binding = 1) readonly uniform image3D u_coarse_x;
layout(r8ui, binding = 2) readonly uniform uimage3D u_fine_mask;

void main() {
  ivec3 f = ivec3(gl_GlobalInvocationID);
  if (!inGrid(f)) return;
  if ((imageLoad(u_fine_mask, f).r & NB_SOLID) != 0u) return;
  imageStore(u_fine_x, f, vec4(imageLoad(u_fine_x, f).r + imageLoad(u_coarse_x, f / 2).r));
}
