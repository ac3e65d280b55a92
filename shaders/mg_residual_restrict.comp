// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_residual_restrict": mg_residual and mg_restrict in one pass. Per coarse cell, the
// fine residual b - A x of each fluid child (A as in mg_smooth.comp, the same arithmetic as
// mg_residual.comp) summed and scaled as mg_restrict.comp does: b_c = u_scale * sum. The fine
// residual is never stored (one full-grid write and read and one dispatch fewer per level).
// Dispatched over the coarse grid (u_res is the coarse resolution).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_x);
IMAGE_RO(r32f, 2, u_b);
UIMAGE_RO(r8ui, 3, u_mask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_faces);
IMAGE_WO(r32f, 0, u_coarse_b);

UNIFORM(ivec3, u_fine_size);  // fine cells per axis
UNIFORM(float, u_scale);      // coarse operator scaling (see MultigridVCycle::kCoarseScale)

// The fine residual b - A x at fine cell c (residualAt: 0 in a solid cell).
float fineResidual(ivec3 c) {
  FACE_OPEN_LO_HI(u_faces, c, w_lo, w_hi);
  NEIGHBOURS_LO_HI(u_x, c, x_lo, x_hi);
  return residualAt(imageLoad(u_mask, c).x, w_lo, w_hi, imageLoad(u_x, c).x, x_lo, x_hi, imageLoad(u_b, c).x);
}

// A coarse cell's sum of its children's residuals, children in the order of o's bits (x, y, z),
// those past the fine grid left out: the CPU's row loop (cpu/kernels/mg_residual_restrict.cpp)
// adds them in this order too.
void main() {
  ivec3 C = ivec3(gl_GlobalInvocationID);
  if (!inGrid(C)) return;
  float sum = 0.0f;
  UNROLL for (int o = 0; o < 8; ++o) {
    ivec3 c = 2 * C + ivec3(o & 1, (o >> 1) & 1, (o >> 2) & 1);
    if (any(greaterThanEqual(c, u_fine_size))) continue;
    sum += fineResidual(c);
  }
  imageStore(u_coarse_b, C, vec4(u_scale * sum));
}
