// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_apply": q = A s (the operator of pcg_init.comp) and, per row, s.q into
// partials[]. 0 in solid cells.
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_s);
UIMAGE_RO(r8ui, 3, u_nbmask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);
IMAGE_WO(r32f, 0, u_q);
BUFFER_WO(Partials, vec4, 0, partials);

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    uint m = imageLoad(u_nbmask, c).x;
    float q = 0.0f;
    if ((m & NB_SOLID) == 0u) {
      float s = imageLoad(u_s, c).x;
      float w[6];
      FACE_OPEN_ALL(u_face_open, c, w);
      q = (m & NB_OPEN_TOP) != 0u ? w[5] * s : 0.0f;
      UNROLL for (int d = 0; d < 6; ++d) {
        if (((m >> uint(d)) & 1u) != 0u) q += w[d] * (s - imageLoad(u_s, c + NEIGHBOUR[d]).x);
      }
      acc.x += s * q;
    }
    imageStore(u_q, c, vec4(q));
  }
  partials[row.x + u_res.y * row.y] = acc;
}
