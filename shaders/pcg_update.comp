// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_update": alpha = (r.z) / (s.q) from the reduction results, then p += alpha s and
// r -= alpha q on fluid cells (per-texel updates), and per row (sum of the new r, fluid cells,
// r.r) into partials[] (x / y is the mean that a closed box removes).
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 0) uniform image3D u_pressure;
layout(r32f, binding = 1) uniform image3D u_r;
layout(r32f, binding = 2) readonly uniform image3D u_s;
layout(r32f, binding = 3) readonly uniform image3D u_q;
layout(r8ui, binding = 4) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };
layout(std430, binding = 1) readonly buffer Results { vec4 results[]; };

uniform uint u_slot_rz;  // results[u_slot_rz].x = r.z
uniform uint u_slot_sq;  // results[u_slot_sq].x = s.q

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  float sq = results[u_slot_sq].x;
  float alpha = sq > 0.0 ? results[u_slot_rz].x / sq : 0.0;
  vec4 acc = vec4(0.0);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) continue;
    imageStore(u_pressure, c, vec4(imageLoad(u_pressure, c).r + alpha * imageLoad(u_s, c).r));
    float r = imageLoad(u_r, c).r - alpha * imageLoad(u_q, c).r;
    imageStore(u_r, c, vec4(r));
    acc += vec4(r, 1.0, r * r, 0.0);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
