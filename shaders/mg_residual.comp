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
  uint m = imageLoad(u_mask, c).x;
  if ((m & NB_SOLID) != 0u) {
    imageStore(u_out, c, vec4(0.0f));
    return;
  }
  float x = imageLoad(u_x, c).x;
  float w[6];
  FACE_OPEN_ALL(u_faces, c, w);
  float ax = (m & NB_OPEN_TOP) != 0u ? w[5] * x : 0.0f;  // sum of differences: no cancellation
  UNROLL for (int d = 0; d < 6; ++d) {
    if (((m >> uint(d)) & 1u) != 0u) ax += w[d] * (x - imageLoad(u_x, c + NEIGHBOUR[d]).x);
  }
  imageStore(u_out, c, vec4(imageLoad(u_b, c).x - ax));
}
