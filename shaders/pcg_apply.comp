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

// One cell's q = A s (operatorAt; 0 in a solid cell) and its part of s.q (0 in a solid cell).
vec2 appliedValues(uint m, vec3 w_lo, vec3 w_hi, float s, vec3 s_lo, vec3 s_hi) {
  bool solid = (m & NB_SOLID) != 0u;
  float q = solid ? 0.0f : operatorAt(m, w_lo, w_hi, s, s_lo, s_hi);
  return vec2(q, solid ? 0.0f : s * q);
}

// The row's cells, their parts of s.q summed by parts (common.glsl, ROW_PARTS; cpu/kernels/
// pcg_apply.cpp sums the same way).
void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 parts[ROW_PARTS];
  UNROLL for (int l = 0; l < ROW_PARTS; ++l) parts[l] = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    FACE_OPEN_LO_HI(u_face_open, c, w_lo, w_hi);
    NEIGHBOURS_LO_HI(u_s, c, s_lo, s_hi);
    vec2 v = appliedValues(imageLoad(u_nbmask, c).x, w_lo, w_hi, imageLoad(u_s, c).x, s_lo, s_hi);
    imageStore(u_q, c, vec4(v.x));
    parts[i % ROW_PARTS].x += v.y;
  }
  partials[row.x + u_res.y * row.y] = rowPartsTotal(parts);
}
