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
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_pressure);
IMAGE_RO(r32f, 2, u_rhs);
UIMAGE_RO(r8ui, 3, u_nbmask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);
IMAGE_WO(r32f, 0, u_r);
BUFFER_WO(Partials, vec4, 0, partials);

// One cell's starting residual r = b - A p with b = -rhs (0 in a solid cell); b and A p go out
// for the sums (addStartSums).
float startResidual(uint m, vec3 w_lo, vec3 w_hi, float p, vec3 p_lo, vec3 p_hi, float rhs, OUT(float) b,
                    OUT(float) ap) {
  ap = operatorAt(m, w_lo, w_hi, p, p_lo, p_hi);
  b = -rhs;
  return (m & NB_SOLID) != 0u ? 0.0f : b - ap;
}

// A cell's parts of the row's sums: (r, 1, r r, b b) into acc, (b r, Ap Ap, b Ap, 0) into acc_ap;
// nothing from a solid cell (adding 0 is exact).
void addStartSums(INOUT(vec4) acc, INOUT(vec4) acc_ap, uint m, float r, float b, float ap) {
  bool solid = (m & NB_SOLID) != 0u;
  acc += solid ? vec4(0.0f) : vec4(r, 1.0f, r * r, b * b);
  acc_ap += solid ? vec4(0.0f) : vec4(b * r, ap * ap, b * ap, 0.0f);
}

// The row's cells in order, their parts summed in that order (cpu/kernels/pcg_init.cpp sums in
// it too).
void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0f);
  vec4 acc_ap = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    FACE_OPEN_LO_HI(u_face_open, c, w_lo, w_hi);
    NEIGHBOURS_LO_HI(u_pressure, c, p_lo, p_hi);
    uint m = imageLoad(u_nbmask, c).x;
    float b;
    float ap;
    float r = startResidual(m, w_lo, w_hi, imageLoad(u_pressure, c).x, p_lo, p_hi, imageLoad(u_rhs, c).x, b, ap);
    addStartSums(acc, acc_ap, m, r, b, ap);
    imageStore(u_r, c, vec4(r));
  }
  partials[row.x + u_res.y * row.y] = acc;
  partials[u_res.y * u_res.z + row.x + u_res.y * row.y] = acc_ap;
}
