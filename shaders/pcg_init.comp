// Stage "pcg_init": the starting residual of the preconditioned conjugate gradient solve,
// r = b - A p with b = -rhs (A p = n p - sum of the linked neighbours' p, so A is positive
// (semi)definite and A p = -rhs is the pressure equation sum_nb (p_nb - p) = rhs). Per
// workgroup (r.r, b.b) into partials[]. 0 in solid cells.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r32f, binding = 2) readonly uniform image3D u_rhs;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 0) uniform writeonly image3D u_r;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  vec4 mine = vec4(0.0);
  if (inGrid(c)) {
    uint m = imageLoad(u_nbmask, c).r;
    float r = 0.0;
    if ((m & NB_SOLID) == 0u) {
      float p = imageLoad(u_pressure, c).r;
      float ap = (m & NB_OPEN_TOP) != 0u ? p : 0.0;  // differences, not n p - sum: exact near 0
      for (int d = 0; d < 6; ++d) {
        if (((m >> uint(d)) & 1u) != 0u) ap += p - imageLoad(u_pressure, c + NEIGHBOUR[d]).r;
      }
      float b = -imageLoad(u_rhs, c).r;
      r = b - ap;
      mine = vec4(r, 1.0, r * r, b * b);
    }
    imageStore(u_r, c, vec4(r));
  }
  writeGroupSum(mine);
}
