// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_predict": the solve's starting guess is the previous pressure scaled by the alpha
// that minimises the starting residual, ||b - alpha A p||: alpha = <b, A p> / <A p, A p>. Then
// ||b - alpha A p||^2 = ||b||^2 - <b, A p>^2 / ||A p||^2 <= ||b||^2, so the start is never worse
// than p = 0 (alpha = 0; also when A p = 0) nor than the plain warm start (alpha = 1), and costs
// no matrix product: pcg_init already has A p = b - r. Per cell: p = alpha p and
// r = b - alpha A p = (1 - alpha) b + alpha r (r as pcg_init left it, in a closed box less its
// mean, which this pass removes as pressure_shift.comp would; b = -rhs has zero mean there, so the
// new r has a zero mean).
// results[u_slot_ap] = (b.r, Ap.Ap, b.Ap) from pcg_init. Decided on the GPU so the fixed-count mode needs no read-back. Per row, the new
// (sum r, fluid cells, r.r, b.b) into partials[] (as pcg_init): the host reads the new r.r from
// them, since the closed-form ||b||^2 - <b, A p>^2 / ||A p||^2 loses everything below ~1e-7 ||b||^2
// to cancellation.
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RW(r32f, 0, u_pressure);
IMAGE_RW(r32f, 1, u_r);
IMAGE_RO(r32f, 2, u_rhs);
UIMAGE_RO(r8ui, 3, u_nbmask);
BUFFER_WO(Partials, vec4, 0, partials);
BUFFER_RO(Results, vec4, 1, results);

UNIFORM(uint, u_slot_ap);
UNIFORM(int, u_remove_mean);  // 1 (a closed box): r's mean over the fluid cells is taken from it first
UNIFORM(uint, u_slot_mean);   // results[u_slot_mean] = (sum r, fluid cells) from pcg_init

// The alpha of the warm start (0 where it is undefined).
float predictorAlpha(vec4 ap) {
  float alpha = ap.y > 0.0f ? ap.z / ap.y : 0.0f;
  return isinf(alpha) || isnan(alpha) ? 0.0f : alpha;
}

// The mean taken from r first: pressure_shift.comp's (its pass folded in here), or 0.
float residualMean() { return u_remove_mean != 0 ? meanOverFluid(results[u_slot_mean]) : 0.0f; }

// One cell's start: in a fluid cell p = alpha p and r = (1 - alpha) b + alpha r, or with alpha 0
// p = 0 and r = b (chosen, not computed, so a huge old r cannot leave 0 * inf behind); a solid
// cell keeps both. Its terms of the row's sums (r, 1, r r, b b), 0 from a solid cell.
vec4 predictCell(uint m, float alpha, float mean, float b, INOUT(float) p, INOUT(float) r) {
  bool fluid = (m & NB_SOLID) == 0u;
  float r_new = alpha == 0.0f ? b : (1.0f - alpha) * b + alpha * (r - mean);
  float p_new = alpha == 0.0f ? 0.0f : alpha * p;
  p = fluid ? p_new : p;
  r = fluid ? r_new : r;
  return vec4(fluid ? r_new : 0.0f, fluid ? 1.0f : 0.0f, fluid ? r_new * r_new : 0.0f, fluid ? b * b : 0.0f);
}

// The row's cells, their terms summed by parts (common.glsl, ROW_PARTS; cpu/kernels/
// pcg_predict.cpp sums the same way).
void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  float alpha = predictorAlpha(results[u_slot_ap]);
  float mean = residualMean();
  vec4 parts[ROW_PARTS];
  UNROLL for (int l = 0; l < ROW_PARTS; ++l) parts[l] = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    float p = imageLoad(u_pressure, c).x;
    float r = imageLoad(u_r, c).x;
    parts[i % ROW_PARTS] += predictCell(imageLoad(u_nbmask, c).x, alpha, mean, -imageLoad(u_rhs, c).x, p, r);
    imageStore(u_pressure, c, vec4(p));
    imageStore(u_r, c, vec4(r));
  }
  partials[row.x + u_res.y * row.y] = rowPartsTotal(parts);
}
