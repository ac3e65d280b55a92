// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_init": the starting residual of the preconditioned conjugate gradient solve,
// r = b - A p with b = -rhs (A p = sum over linked neighbours of w (p - p_nb), w the face's open
// fraction (cut cells), plus w p at the open
// top, so A is positive (semi)definite and A p = -rhs is the pressure equation
// sum_nb (p_nb - p) = rhs). Per row, (sum of r, fluid cells, r.r, b.b) into partials[] (x / y
// is the mean a closed box removes with pressure_shift.comp), and where u_predictor_sums is not 0
// (the solve's start, not the check of its end) (b.r, Ap.Ap, b.Ap, 0) into partials[ny nz + row]
// for the predictor (pcg_predict.comp). 0 in solid cells.
// One invocation per row of cells along x (j, k), summing into partials[j + ny k]: llvmpipe
// runs workgroup barriers slowly, and a row loop needs none (see PressureMultigrid).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_pressure);
IMAGE_RO(r32f, 2, u_rhs);
UIMAGE_RO(r8ui, 3, u_nbmask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);
IMAGE_WO(r32f, 0, u_r);
BUFFER_WO(Partials, vec4, 0, partials);

UNIFORM(int, u_predictor_sums);  // 1: the predictor's sums too
UNIFORM(int, u_store_r);         // 1: r is written to u_r; 0: only its sums (the end check)

// One cell's starting residual r = b - A p with b = -rhs (0 in a solid cell); b and A p go out
// for the sums (startSums, startApSums).
float startResidual(uint m, vec3 w_lo, vec3 w_hi, float p, vec3 p_lo, vec3 p_hi, float rhs, OUT(float) b,
                    OUT(float) ap) {
  ap = operatorAt(m, w_lo, w_hi, p, p_lo, p_hi);
  b = -rhs;
  return (m & NB_SOLID) != 0u ? 0.0f : b - ap;
}

// A cell's parts of the row's sums: (r, 1, r r, b b) (startSums) and (b r, Ap Ap, b Ap, 0)
// (startApSums); 0 from a solid cell. Selects per component (the CPU's row loop vectorizes them).
vec4 startSums(uint m, float r, float b) {
  bool fluid = (m & NB_SOLID) == 0u;
  return vec4(fluid ? r : 0.0f, fluid ? 1.0f : 0.0f, fluid ? r * r : 0.0f, fluid ? b * b : 0.0f);
}
vec4 startApSums(uint m, float r, float b, float ap) {
  bool fluid = (m & NB_SOLID) == 0u;
  return vec4(fluid ? b * r : 0.0f, fluid ? ap * ap : 0.0f, fluid ? b * ap : 0.0f, 0.0f);
}

// The row's cells, their parts summed by parts (common.glsl, ROW_PARTS; cpu/kernels/pcg_init.cpp
// sums the same way).
void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 parts[ROW_PARTS];
  vec4 parts_ap[ROW_PARTS];
  UNROLL for (int l = 0; l < ROW_PARTS; ++l) {
    parts[l] = vec4(0.0f);
    parts_ap[l] = vec4(0.0f);
  }
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    FACE_OPEN_LO_HI(u_face_open, c, w_lo, w_hi);
    NEIGHBOURS_LO_HI(u_pressure, c, p_lo, p_hi);
    uint m = imageLoad(u_nbmask, c).x;
    float b;
    float ap;
    float r = startResidual(m, w_lo, w_hi, imageLoad(u_pressure, c).x, p_lo, p_hi, imageLoad(u_rhs, c).x, b, ap);
    parts[i % ROW_PARTS] += startSums(m, r, b);
    if (u_predictor_sums != 0) parts_ap[i % ROW_PARTS] += startApSums(m, r, b, ap);
    if (u_store_r != 0) imageStore(u_r, c, vec4(r));
  }
  partials[row.x + u_res.y * row.y] = rowPartsTotal(parts);
  if (u_predictor_sums != 0) partials[u_res.y * u_res.z + row.x + u_res.y * row.y] = rowPartsTotal(parts_ap);
}
