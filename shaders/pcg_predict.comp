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
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 0) uniform image3D u_pressure;
layout(r32f, binding = 1) uniform image3D u_r;
layout(r32f, binding = 2) readonly uniform image3D u_rhs;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };
layout(std430, binding = 1) readonly buffer Results { vec4 results[]; };

uniform uint u_slot_ap;

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 ap = results[u_slot_ap];
  float alpha = ap.y > 0.0 ? ap.z / ap.y : 0.0;
  if (isinf(alpha) || isnan(alpha)) alpha = 0.0;
  vec4 acc = vec4(0.0);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) continue;
    float b = -imageLoad(u_rhs, c).r;
    float r = b;
    if (alpha == 0.0) {  // p = 0: written, not scaled, so a huge old r cannot leave 0 * inf behind
      imageStore(u_pressure, c, vec4(0.0));
    } else {
      r = (1.0 - alpha) * b + alpha * imageLoad(u_r, c).r;
      imageStore(u_pressure, c, vec4(alpha * imageLoad(u_pressure, c).r));
    }
    imageStore(u_r, c, vec4(r));
    acc += vec4(r, 1.0, r * r, b * b);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
