// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "vorticity": curl of the cell-centred velocity (1/s) by central differences;
// w holds its magnitude for the confinement stage.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_vel_x);
IMAGE_RO(r32f, 2, u_vel_y);
IMAGE_RO(r32f, 3, u_vel_z);
IMAGE_WO(rgba32f, 0, u_vorticity);

UNIFORM(float, u_cell_size);  // m

// One component of the cell-centred velocity (m/s) at cell c, clamped into the grid. The curl
// needs each component only along the two other axes: 24 loads instead of 36 for whole vectors.
float centredU(ivec3 c) { c = clampCell(c); return 0.5f * (imageLoad(u_vel_x, c).x + imageLoad(u_vel_x, c + ivec3(1, 0, 0)).x); }
float centredV(ivec3 c) { c = clampCell(c); return 0.5f * (imageLoad(u_vel_y, c).x + imageLoad(u_vel_y, c + ivec3(0, 1, 0)).x); }
float centredW(ivec3 c) { c = clampCell(c); return 0.5f * (imageLoad(u_vel_z, c).x + imageLoad(u_vel_z, c + ivec3(0, 0, 1)).x); }

// The vorticity at cell c and its magnitude. Its lookups are clamped to the grid, so the CPU's
// row loop (cpu/kernels/vorticity.cpp) runs it unchecked and vectorized.
vec4 vorticityAt(ivec3 c) {
  // Central differences inside, one-sided at the walls (divided by the cells actually spanned).
  ivec3 hi = clampCell(c + 1);
  ivec3 lo = clampCell(c - 1);
  vec3 span = vec3(max(hi - lo, ivec3(1))) * u_cell_size;
  ivec3 xh = ivec3(hi.x, c.y, c.z), xl = ivec3(lo.x, c.y, c.z);
  ivec3 yh = ivec3(c.x, hi.y, c.z), yl = ivec3(c.x, lo.y, c.z);
  ivec3 zh = ivec3(c.x, c.y, hi.z), zl = ivec3(c.x, c.y, lo.z);
  float dv_dx = (centredV(xh) - centredV(xl)) / span.x;
  float dw_dx = (centredW(xh) - centredW(xl)) / span.x;
  float du_dy = (centredU(yh) - centredU(yl)) / span.y;
  float dw_dy = (centredW(yh) - centredW(yl)) / span.y;
  float du_dz = (centredU(zh) - centredU(zl)) / span.z;
  float dv_dz = (centredV(zh) - centredV(zl)) / span.z;
  vec3 w = vec3(dw_dy - dv_dz, du_dz - dw_dx, dv_dx - du_dy);
  return vec4(w, length(w));
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  imageStore(u_vorticity, c, vorticityAt(c));
}
