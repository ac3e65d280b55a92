// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "residual": per row of cells along x (j, k), the sums of r^2 and rhs^2 of the pressure
// equation (r = rhs - sum_nb w (p_nb - p), w the face's open fraction) over its fluid cells, written to partials[j + ny k]
// for reduce.comp. A row loop instead of a workgroup tree: llvmpipe runs barriers slowly
// (fluid/row_reduction.h).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_pressure);
IMAGE_RO(r32f, 2, u_rhs);
UIMAGE_RO(r8ui, 3, u_nbmask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);
BUFFER_WO(Partials, vec4, 0, partials);

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    uint m = imageLoad(u_nbmask, c).x;
    if ((m & NB_SOLID) != 0u) continue;
    float p = imageLoad(u_pressure, c).x;
    float w[6];
    FACE_OPEN_ALL(u_face_open, c, w);
    float lap = (m & NB_OPEN_TOP) != 0u ? -w[5] * p : 0.0f;
    UNROLL for (int d = 0; d < 6; ++d) {
      if (((m >> uint(d)) & 1u) != 0u) lap += w[d] * (imageLoad(u_pressure, c + NEIGHBOUR[d]).x - p);
    }
    float b = imageLoad(u_rhs, c).x;
    float r = b - lap;
    acc += vec4(r * r, b * b, 0.0f, 0.0f);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
