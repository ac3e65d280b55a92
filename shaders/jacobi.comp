// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "jacobi": one Jacobi sweep of sum_nb w (p_nb - p) = rhs over the cells with a pressure
// unknown (Pa), w the open fraction of the face to that neighbour (cut cells). Solid neighbours
// and closed walls are Neumann (left out of the sum); the open top is a Dirichlet ghost at 0 Pa
// (counted with its face's fraction, contributing nothing). Cells without an unknown hold 0.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r32f, binding = 2) readonly uniform image3D u_rhs;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_face_open;
layout(r32f, binding = 0) uniform writeonly image3D u_out;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  uint m = imageLoad(u_nbmask, c).r;
  float sum = 0.0;
  float n = (m & NB_OPEN_TOP) != 0u ? FACE_OPEN(u_face_open, c, 5) : 0.0;
  for (int d = 0; d < 6; ++d) {
    if (((m >> uint(d)) & 1u) == 0u) continue;
    float w = FACE_OPEN(u_face_open, c, d);
    sum += w * imageLoad(u_pressure, c + NEIGHBOUR[d]).r;
    n += w;
  }
  float p = ((m & NB_SOLID) != 0u || n == 0.0) ? 0.0 : (sum - imageLoad(u_rhs, c).r) / n;
  imageStore(u_out, c, vec4(p));
}
