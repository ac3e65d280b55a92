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
  vec3 dx = centred(c + ivec3(1, 0, 0)) - centred(c - ivec3(1, 0, 0));
  vec3 dy = centred(c + ivec3(0, 1, 0)) - centred(c - ivec3(0, 1, 0));
  vec3 dz = centred(c + ivec3(0, 0, 1)) - centred(c - ivec3(0, 0, 1));
  vec3 w = vec3(dy.z - dz.y, dz.x - dx.z, dx.y - dy.x) / (2.0 * u_cell_size);
  imageStore(u_vorticity, c, vec4(w, length(w)));
}
