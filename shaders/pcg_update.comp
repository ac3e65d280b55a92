// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_update": alpha = (r.z) / (s.q) from the reduction results, then p += alpha s and
// r -= alpha q on fluid cells (per-texel updates), and per row (sum of the new r, fluid cells,
// r.r) into partials[] (x / y is the mean that a closed box removes).
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RW(r32f, 0, u_pressure);
IMAGE_RW(r32f, 1, u_r);
IMAGE_RO(r32f, 2, u_s);
IMAGE_RO(r32f, 3, u_q);
UIMAGE_RO(r8ui, 4, u_nbmask);
BUFFER_WO(Partials, vec4, 0, partials);
BUFFER_RO(Results, vec4, 1, results);

UNIFORM(uint, u_slot_rz);  // results[u_slot_rz].x = r.z
UNIFORM(uint, u_slot_sq);  // results[u_slot_sq].x = s.q

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  float sq = results[u_slot_sq].x;
  float alpha = sq > 0.0f ? results[u_slot_rz].x / sq : 0.0f;
  vec4 acc = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    if ((imageLoad(u_nbmask, c).x & NB_SOLID) != 0u) continue;
    imageStore(u_pressure, c, vec4(imageLoad(u_pressure, c).x + alpha * imageLoad(u_s, c).x));
    float r = imageLoad(u_r, c).x - alpha * imageLoad(u_q, c).x;
    imageStore(u_r, c, vec4(r));
    acc += vec4(r, 1.0f, r * r, 0.0f);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
