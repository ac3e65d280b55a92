// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_dot": per row, the dot product a.b over fluid cells into partials[].
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 1) readonly uniform image3D u_a;
layout(r32f, binding = 2) readonly uniform image3D u_b;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  float acc = 0.0;
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    if ((imageLoad(u_nbmask, c).r & NB_SOLID) == 0u) acc += imageLoad(u_a, c).r * imageLoad(u_b, c).r;
  }
  partials[row.x + u_res.y * row.y] = vec4(acc, 0.0, 0.0, 0.0);
}
