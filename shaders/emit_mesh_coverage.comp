// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "emit_mesh_coverage" (emitter/mesh_emitter.h): one invocation per cell column sums the
// smoke source's crossings bottom-up. The winding number of sub-column s along z is the sum of
// the crossings below, so its integral over cell k is (crossings in cells below k) + (the signed
// lengths above the hits in cell k); summed over the S^2 sub-columns and divided by S^2 that is
// the fraction of the cell inside the mesh (for shells that do not overlap; an inside-out mesh
// gives its negative). Writes |that| clamped to [0, 1] into every cell.
LOCAL_SIZE(WG_X, WG_Y, 1);

BUFFER_RO(Crossings, int, 0, crossings);  // per cell: count, length
IMAGE_WO(r32f, 0, u_coverage);

UNIFORM(int, u_samples);  // S

CONST float kLength = 65536.0f;  // fixed-point units per cell of length (emit_mesh_crossings.comp)

void main() {
  ivec2 col = ivec2(gl_GlobalInvocationID);
  if (any(greaterThanEqual(col, ivec2(u_res)))) return;
  float per_cell = float(u_samples * u_samples);
  int below = 0;  // crossings in the cells below, over the column's sub-columns
  for (int k = 0; k < u_res.z; ++k) {
    int cell = col.x + u_res.x * (col.y + u_res.y * k);
    float inside = float(below) + float(crossings[2 * cell + 1]) / kLength;
    below += crossings[2 * cell];
    imageStore(u_coverage, ivec3(col, k), vec4(clamp(abs(inside) / per_cell, 0.0f, 1.0f)));
  }
}
