// Stage "jacobi": one Jacobi sweep of sum_nb (p_nb - p) = rhs over the fluid cells (Pa).
// Solid neighbours and closed walls are Neumann (left out of the sum); the open top is a
// Dirichlet ghost at 0 Pa (counted, contributing nothing). Solid cells hold 0.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r32f, binding = 2) readonly uniform image3D u_rhs;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 0) uniform writeonly image3D u_out;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  uint m = imageLoad(u_nbmask, c).r;
  float sum = 0.0;
  for (int d = 0; d < 6; ++d) {
    float use = float((m >> uint(d)) & 1u);
    sum += use * imageLoad(u_pressure, c + NEIGHBOUR[d]).r;
  }
  float n = float(bitCount(m & 63u) + int((m & NB_OPEN_TOP) != 0u));
  float p = ((m & NB_SOLID) != 0u || n == 0.0) ? 0.0 : (sum - imageLoad(u_rhs, c).r) / n;
  imageStore(u_out, c, vec4(p));
}
