// Stage "vorticity": curl of the cell-centred velocity (1/s) by central differences;
// w holds its magnitude for the confinement stage.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_vel_x;
layout(r32f, binding = 2) readonly uniform image3D u_vel_y;
layout(r32f, binding = 3) readonly uniform image3D u_vel_z;
layout(rgba32f, binding = 0) uniform writeonly image3D u_vorticity;

uniform float u_cell_size;  // m

vec3 centred(ivec3 c) {
  c = clampCell(c);
  return 0.5 * vec3(imageLoad(u_vel_x, c).r + imageLoad(u_vel_x, c + ivec3(1, 0, 0)).r,
                    imageLoad(u_vel_y, c).r + imageLoad(u_vel_y, c + ivec3(0, 1, 0)).r,
                    imageLoad(u_vel_z, c).r + imageLoad(u_vel_z, c + ivec3(0, 0, 1)).r);
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  // Central differences inside, one-sided at the walls (divided by the cells actually spanned).
  ivec3 hi = clampCell(c + 1);
  ivec3 lo = clampCell(c - 1);
  vec3 span = vec3(max(hi - lo, ivec3(1))) * u_cell_size;
  vec3 dx = (centred(ivec3(hi.x, c.y, c.z)) - centred(ivec3(lo.x, c.y, c.z))) / span.x;
  vec3 dy = (centred(ivec3(c.x, hi.y, c.z)) - centred(ivec3(c.x, lo.y, c.z))) / span.y;
  vec3 dz = (centred(ivec3(c.x, c.y, hi.z)) - centred(ivec3(c.x, c.y, lo.z))) / span.z;
  vec3 w = vec3(dy.z - dz.y, dz.x - dx.z, dx.y - dy.x);
  imageStore(u_vorticity, c, vec4(w, length(w)));
}
