// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "jacobi": one Jacobi sweep of sum_nb w (p_nb - p) = rhs over the cells with a pressure
// unknown (Pa), w the open fraction of the face to that neighbour (cut cells). Solid neighbours
// and closed walls are Neumann (left out of the sum); the open top is a Dirichlet ghost at 0 Pa
// (counted with its face's fraction, contributing nothing). Cells without an unknown hold 0.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_pressure);
IMAGE_RO(r32f, 2, u_rhs);
UIMAGE_RO(r8ui, 3, u_nbmask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);
IMAGE_WO(r32f, 0, u_out);

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  uint m = imageLoad(u_nbmask, c).x;
  float sum = 0.0f;
  float n = (m & NB_OPEN_TOP) != 0u ? FACE_OPEN(u_face_open, c, 5) : 0.0f;
  UNROLL for (int d = 0; d < 6; ++d) {
    if (((m >> uint(d)) & 1u) == 0u) continue;
    float w = FACE_OPEN(u_face_open, c, d);
    sum += w * imageLoad(u_pressure, c + NEIGHBOUR[d]).x;
    n += w;
  }
  float p = ((m & NB_SOLID) != 0u || n == 0.0f) ? 0.0f : (sum - imageLoad(u_rhs, c).x) / n;
  imageStore(u_out, c, vec4(p));
}
