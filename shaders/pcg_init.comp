// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_init": the starting residual of the preconditioned conjugate gradient solve,
// r = b - A p with b = -rhs (A p = sum over linked neighbours of w (p - p_nb), w the face's open
// fraction (cut cells), plus w p at the open
// top, so A is positive (semi)definite and A p = -rhs is the pressure equation
// sum_nb (p_nb - p) = rhs). Per row, (sum of r, fluid cells, r.r, b.b) into partials[] (x / y
// is the mean a closed box removes with pressure_shift.comp), and (b.r, Ap.Ap, b.Ap, 0) into
// partials[ny nz + row] for the predictor (pcg_predict.comp). 0 in solid cells.
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r32f, binding = 2) readonly uniform image3D u_rhs;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_face_open;
layout(r32f, binding = 0) uniform writeonly image3D u_r;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0);
  vec4 acc_ap = vec4(0.0);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    uint m = imageLoad(u_nbmask, c).r;
    float r = 0.0;
    if ((m & NB_SOLID) == 0u) {
      float p = imageLoad(u_pressure, c).r;
      float w[6];
      FACE_OPEN_ALL(u_face_open, c, w);
      float ap = (m & NB_OPEN_TOP) != 0u ? w[5] * p : 0.0;  // differences, not n p - sum: exact near 0
      for (int d = 0; d < 6; ++d) {
        if (((m >> uint(d)) & 1u) != 0u) ap += w[d] * (p - imageLoad(u_pressure, c + NEIGHBOUR[d]).r);
      }
      float b = -imageLoad(u_rhs, c).r;
      r = b - ap;
      acc += vec4(r, 1.0, r * r, b * b);
      acc_ap += vec4(b * r, ap * ap, b * ap, 0.0);
    }
    imageStore(u_r, c, vec4(r));
  }
  partials[row.x + u_res.y * row.y] = acc;
  partials[u_res.y * u_res.z + row.x + u_res.y * row.y] = acc_ap;
}
