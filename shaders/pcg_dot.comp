// Stage "pcg_dot": per workgroup, the dot product a.b over fluid cells into partials[].
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_a;
layout(r32f, binding = 2) readonly uniform image3D u_b;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  vec4 mine = vec4(0.0);
  if (inGrid(c) && (imageLoad(u_nbmask, c).r & NB_SOLID) == 0u) {
    mine = vec4(imageLoad(u_a, c).r * imageLoad(u_b, c).r, 0.0, 0.0, 0.0);
  }
  writeGroupSum(mine);
}
