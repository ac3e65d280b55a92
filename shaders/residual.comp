// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "residual": per row of cells along x (j, k), the sums of r^2 and rhs^2 of the pressure
// equation (r = rhs - sum_nb w (p_nb - p), w the face's open fraction) over its fluid cells, written to partials[j + ny k]
// for reduce.comp. A row loop instead of a workgroup tree: llvmpipe runs barriers slowly
// (fluid/row_reduction.h).
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r32f, binding = 2) readonly uniform image3D u_rhs;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_face_open;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    uint m = imageLoad(u_nbmask, c).r;
    if ((m & NB_SOLID) != 0u) continue;
    float p = imageLoad(u_pressure, c).r;
    float w[6];
    FACE_OPEN_ALL(u_face_open, c, w);
    float lap = (m & NB_OPEN_TOP) != 0u ? -w[5] * p : 0.0;
    for (int d = 0; d < 6; ++d) {
      if (((m >> uint(d)) & 1u) != 0u) lap += w[d] * (imageLoad(u_pressure, c + NEIGHBOUR[d]).r - p);
    }
    float b = imageLoad(u_rhs, c).r;
    float r = b - lap;
    acc += vec4(r * r, b * b, 0.0, 0.0);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
