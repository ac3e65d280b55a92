// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_apply": q = A s (the operator of pcg_init.comp) and, per row, s.q into
// partials[]. 0 in solid cells.
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 1) readonly uniform image3D u_s;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_face_open;
layout(r32f, binding = 0) uniform writeonly image3D u_q;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    uint m = imageLoad(u_nbmask, c).r;
    float q = 0.0;
    if ((m & NB_SOLID) == 0u) {
      float s = imageLoad(u_s, c).r;
      float w[6];
      FACE_OPEN_ALL(u_face_open, c, w);
      q = (m & NB_OPEN_TOP) != 0u ? w[5] * s : 0.0;
      for (int d = 0; d < 6; ++d) {
        if (((m >> uint(d)) & 1u) != 0u) q += w[d] * (s - imageLoad(u_s, c + NEIGHBOUR[d]).r);
      }
      acc.x += s * q;
    }
    imageStore(u_q, c, vec4(q));
  }
  partials[row.x + u_res.y * row.y] = acc;
}
