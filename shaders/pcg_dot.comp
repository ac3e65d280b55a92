// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_dot": per row, the dot product a.b over fluid cells into partials[].
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_a);
IMAGE_RO(r32f, 2, u_b);
UIMAGE_RO(r8ui, 3, u_nbmask);
BUFFER_WO(Partials, vec4, 0, partials);

// One cell's term of a.b: 0 from a solid cell.
float dotTerm(uint m, float a, float b) { return (m & NB_SOLID) == 0u ? a * b : 0.0f; }

// The row's cells, their terms summed by parts (common.glsl, ROW_PARTS; cpu/kernels/pcg_dot.cpp
// sums the same way).
void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 parts[ROW_PARTS];
  UNROLL for (int l = 0; l < ROW_PARTS; ++l) parts[l] = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    parts[i % ROW_PARTS].x += dotTerm(imageLoad(u_nbmask, c).x, imageLoad(u_a, c).x, imageLoad(u_b, c).x);
  }
  partials[row.x + u_res.y * row.y] = rowPartsTotal(parts);
}
