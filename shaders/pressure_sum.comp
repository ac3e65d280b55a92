// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pressure_sum": per row of cells along x (j, k), the sum of a cell-centred scalar (the
// pressure, or the rhs for the compatibility condition of a closed box) over its fluid cells and
// their count (x, y of partials[j + ny k]), the first level of the mean that pressure_shift
// removes. A row loop instead of a workgroup tree (fluid/row_reduction.h).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_pressure);
UIMAGE_RO(r8ui, 2, u_nbmask);
BUFFER_WO(Partials, vec4, 0, partials);

// One cell's terms of the row's sums (v, 1, 0, 0), 0 from a solid cell.
vec4 sumTerms(uint m, float v) {
  bool fluid = (m & NB_SOLID) == 0u;
  return vec4(fluid ? v : 0.0f, fluid ? 1.0f : 0.0f, 0.0f, 0.0f);
}

// The row's cells, their terms summed by parts (common.glsl, ROW_PARTS; cpu/kernels/
// pressure_sum.cpp sums the same way).
void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 parts[ROW_PARTS];
  UNROLL for (int l = 0; l < ROW_PARTS; ++l) parts[l] = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    parts[i % ROW_PARTS] += sumTerms(imageLoad(u_nbmask, c).x, imageLoad(u_pressure, c).x);
  }
  partials[row.x + u_res.y * row.y] = rowPartsTotal(parts);
}
