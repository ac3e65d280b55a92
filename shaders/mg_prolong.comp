// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_prolong": x_fine += x_coarse of the parent cell (piecewise-constant interpolation)
// on fluid cells; per-texel update of the fine level. Dispatched over the fine grid.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RW(r32f, 0, u_fine_x);
IMAGE_RO(r32f, 1, u_coarse_x);
UIMAGE_RO(r8ui, 2, u_fine_mask);

void main() {
  ivec3 f = ivec3(gl_GlobalInvocationID);
  if (!inGrid(f)) return;
  if ((imageLoad(u_fine_mask, f).x & NB_SOLID) != 0u) return;
  imageStore(u_fine_x, f, vec4(imageLoad(u_fine_x, f).x + imageLoad(u_coarse_x, f / 2).x));
}
