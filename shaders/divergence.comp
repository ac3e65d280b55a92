// Stage "divergence": right-hand side of the pressure equation in pascals,
// rhs = (rho h^2 / dt) div(u) = (rho h / dt) * (sum of outgoing face velocities), 0 in solids.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_vel_x;
layout(r32f, binding = 2) readonly uniform image3D u_vel_y;
layout(r32f, binding = 3) readonly uniform image3D u_vel_z;
layout(r8ui, binding = 4) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 0) uniform writeonly image3D u_rhs;

uniform float u_scale;  // rho * h / dt, kg/(m^2 s)

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) {
    imageStore(u_rhs, c, vec4(0.0));
    return;
  }
  float flux = imageLoad(u_vel_x, c + ivec3(1, 0, 0)).r - imageLoad(u_vel_x, c).r +
               imageLoad(u_vel_y, c + ivec3(0, 1, 0)).r - imageLoad(u_vel_y, c).r +
               imageLoad(u_vel_z, c + ivec3(0, 0, 1)).r - imageLoad(u_vel_z, c).r;
  imageStore(u_rhs, c, vec4(u_scale * flux));
}
