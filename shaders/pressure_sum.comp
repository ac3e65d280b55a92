// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pressure_sum": per row of cells along x (j, k), the sum of a cell-centred scalar (the
// pressure, or the rhs for the compatibility condition of a closed box) over its fluid cells and
// their count (x, y of partials[j + ny k]), the first level of the mean that pressure_shift
// removes. A row loop instead of a workgroup tree (fluid/row_reduction.h).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_pressure);
UIMAGE_RO(r8ui, 2, u_nbmask);
BUFFER_WO(Partials, vec4, 0, partials);

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    if ((imageLoad(u_nbmask, c).x & NB_SOLID) == 0u) acc += vec4(imageLoad(u_pressure, c).x, 1.0f, 0.0f, 0.0f);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
