// Stage "residual": per workgroup, the sums of r^2 and rhs^2 of the pressure equation
// (r = rhs - sum_nb (p_nb - p)), written to partials[] for reduce.comp.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r32f, binding = 2) readonly uniform image3D u_rhs;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  vec4 mine = vec4(0.0);
  if (inGrid(c)) {
    uint m = imageLoad(u_nbmask, c).r;
    if ((m & NB_SOLID) == 0u) {
      float p = imageLoad(u_pressure, c).r;
      float lap = 0.0;
      for (int d = 0; d < 6; ++d) {
        float use = float((m >> uint(d)) & 1u);
        lap += use * (imageLoad(u_pressure, c + NEIGHBOUR[d]).r - p);
      }
      if ((m & NB_OPEN_TOP) != 0u) lap -= p;
      float b = imageLoad(u_rhs, c).r;
      float r = b - lap;
      mine = vec4(r * r, b * b, 0.0, 0.0);
    }
  }
  writeGroupSum(mine);
}
