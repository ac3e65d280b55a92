// Stage "pressure_sum": per workgroup, the sum of a cell-centred scalar (the pressure, or the
// rhs for the compatibility condition of a closed box) over fluid cells and their count (x, y of
// partials[]), the first level of the mean that pressure_shift removes.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r8ui, binding = 2) readonly uniform uimage3D u_nbmask;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  vec4 mine = vec4(0.0);
  if (inGrid(c) && (imageLoad(u_nbmask, c).r & NB_SOLID) == 0u) mine = vec4(imageLoad(u_pressure, c).r, 1.0, 0.0, 0.0);
  writeGroupSum(mine);
}
