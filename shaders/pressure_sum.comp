// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pressure_sum": per row of cells along x (j, k), the sum of a cell-centred scalar (the
// pressure, or the rhs for the compatibility condition of a closed box) over its fluid cells and
// their count (x, y of partials[j + ny k]), the first level of the mean that pressure_shift
// removes. A row loop instead of a workgroup tree (fluid/row_reduction.h).
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r8ui, binding = 2) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    if ((imageLoad(u_nbmask, c).r & NB_SOLID) == 0u) acc += vec4(imageLoad(u_pressure, c).r, 1.0, 0.0, 0.0);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
