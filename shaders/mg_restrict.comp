// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_restrict": coarse right-hand side b_c = u_scale * (sum of the fine residuals of the
// fluid children), the transpose of mg_prolong's piecewise-constant interpolation (so the
// V-cycle is symmetric and can precondition CG). A coarse cell has the 2x2x2 fine children
// 2C + {0,1}^3 that lie inside the fine grid (fewer at the far faces of odd resolutions).
// Dispatched over the coarse grid (u_res is the coarse resolution).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_fine_res);
UIMAGE_RO(r8ui, 2, u_fine_mask);
IMAGE_WO(r32f, 0, u_coarse_b);

UNIFORM(ivec3, u_fine_size);  // fine cells per axis
UNIFORM(float, u_scale);      // coarse operator scaling (see PressureMultigrid)

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  float sum = 0.0f;
  UNROLL for (int o = 0; o < 8; ++o) {
    ivec3 f = 2 * c + ivec3(o & 1, (o >> 1) & 1, (o >> 2) & 1);
    if (any(greaterThanEqual(f, u_fine_size))) continue;
    if ((imageLoad(u_fine_mask, f).x & NB_SOLID) == 0u) sum += imageLoad(u_fine_res, f).x;
  }
  imageStore(u_coarse_b, c, vec4(u_scale * sum));
}
