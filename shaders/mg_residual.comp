// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_residual": out = b - A x on one multigrid level (A as in mg_smooth.comp); 0 in
// solid cells.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_x;
layout(r32f, binding = 2) readonly uniform image3D u_b;
layout(r8ui, binding = 3) readonly uniform uimage3D u_mask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_faces;
layout(r32f, binding = 0) uniform writeonly image3D u_out;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  uint m = imageLoad(u_mask, c).r;
  if ((m & NB_SOLID) != 0u) {
    imageStore(u_out, c, vec4(0.0));
    return;
  }
  float x = imageLoad(u_x, c).r;
  float w[6];
  FACE_OPEN_ALL(u_faces, c, w);
  float ax = (m & NB_OPEN_TOP) != 0u ? w[5] * x : 0.0;  // sum of differences: no cancellation
  for (int d = 0; d < 6; ++d) {
    if (((m >> uint(d)) & 1u) != 0u) ax += w[d] * (x - imageLoad(u_x, c + NEIGHBOUR[d]).r);
  }
  imageStore(u_out, c, vec4(imageLoad(u_b, c).r - ax));
}
