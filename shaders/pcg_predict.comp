// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_predict": the solve's starting guess is the previous pressure scaled by the alpha
// that minimises the starting residual, ||b - alpha A p||: alpha = <b, A p> / <A p, A p>. Then
// ||b - alpha A p||^2 = ||b||^2 - <b, A p>^2 / ||A p||^2 <= ||b||^2, so the start is never worse
// than p = 0 (alpha = 0; also when A p = 0) nor than the plain warm start (alpha = 1), and costs
// no matrix product: pcg_init already has A p = b - r. Per cell: p = alpha p and
// r = b - alpha A p = (1 - alpha) b + alpha r (r as pcg_init left it, its mean removed in a closed
// box; b = -rhs has zero mean there, so the new r keeps a zero mean).
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

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 ap = results[u_slot_ap];
  float alpha = ap.y > 0.0f ? ap.z / ap.y : 0.0f;
  if (isinf(alpha) || isnan(alpha)) alpha = 0.0f;
  vec4 acc = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    if ((imageLoad(u_nbmask, c).x & NB_SOLID) != 0u) continue;
    float b = -imageLoad(u_rhs, c).x;
    float r = b;
    if (alpha == 0.0f) {  // p = 0: written, not scaled, so a huge old r cannot leave 0 * inf behind
      imageStore(u_pressure, c, vec4(0.0f));
    } else {
      r = (1.0f - alpha) * b + alpha * imageLoad(u_r, c).x;
      imageStore(u_pressure, c, vec4(alpha * imageLoad(u_pressure, c).x));
    }
    imageStore(u_r, c, vec4(r));
    acc += vec4(r, 1.0f, r * r, b * b);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
