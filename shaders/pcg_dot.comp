// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_dot": per row, the dot product a.b over fluid cells into partials[].
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_a);
IMAGE_RO(r32f, 2, u_b);
UIMAGE_RO(r8ui, 3, u_nbmask);
BUFFER_WO(Partials, vec4, 0, partials);

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  float acc = 0.0f;
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    if ((imageLoad(u_nbmask, c).x & NB_SOLID) == 0u) acc += imageLoad(u_a, c).x * imageLoad(u_b, c).x;
  }
  partials[row.x + u_res.y * row.y] = vec4(acc, 0.0f, 0.0f, 0.0f);
}
