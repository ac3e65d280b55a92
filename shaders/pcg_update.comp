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

// alpha = r.z / s.q from the reduction results (0 where s.q is not positive).
float stepAlpha() {
  float sq = results[u_slot_sq].x;
  return sq > 0.0f ? results[u_slot_rz].x / sq : 0.0f;
}

// One cell's update: p + alpha s and r - alpha q in a fluid cell, both kept in a solid one; its
// terms of the row's sums (r, 1, r r, 0), 0 from a solid cell.
vec4 updateCell(uint m, float alpha, float s, float q, INOUT(float) p, INOUT(float) r) {
  bool fluid = (m & NB_SOLID) == 0u;
  float r_new = r - alpha * q;
  p = fluid ? p + alpha * s : p;
  r = fluid ? r_new : r;
  return vec4(fluid ? r_new : 0.0f, fluid ? 1.0f : 0.0f, fluid ? r_new * r_new : 0.0f, 0.0f);
}

// The row's cells, their terms summed by parts (common.glsl, ROW_PARTS; cpu/kernels/
// pcg_update.cpp sums the same way).
void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  float alpha = stepAlpha();
  vec4 parts[ROW_PARTS];
  UNROLL for (int l = 0; l < ROW_PARTS; ++l) parts[l] = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    float p = imageLoad(u_pressure, c).x;
    float r = imageLoad(u_r, c).x;
    parts[i % ROW_PARTS] += updateCell(imageLoad(u_nbmask, c).x, alpha, imageLoad(u_s, c).x, imageLoad(u_q, c).x, p, r);
    imageStore(u_pressure, c, vec4(p));
    imageStore(u_r, c, vec4(r));
  }
  partials[row.x + u_res.y * row.y] = rowPartsTotal(parts);
}
