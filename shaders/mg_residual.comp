// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_residual": out = b - A x on one multigrid level (A as in mg_smooth.comp); 0 in
// solid cells.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_x);
IMAGE_RO(r32f, 2, u_b);
UIMAGE_RO(r8ui, 3, u_mask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_faces);
IMAGE_WO(r32f, 0, u_out);

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  FACE_OPEN_LO_HI(u_faces, c, w_lo, w_hi);
  NEIGHBOURS_LO_HI(u_x, c, x_lo, x_hi);
  float r = residualAt(imageLoad(u_mask, c).x, w_lo, w_hi, imageLoad(u_x, c).x, x_lo, x_hi, imageLoad(u_b, c).x);
  imageStore(u_out, c, vec4(r));
}
