// Stage "advect": semi-Lagrangian transport of one field (a velocity component or a scalar)
// through the velocity field, with a second-order (midpoint) back-trace.
// Also the forward and backward passes of MacCormack (u_dt_over_h < 0 for the backward one).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(binding = 0) uniform sampler3D u_vel_x;
layout(binding = 1) uniform sampler3D u_vel_y;
layout(binding = 2) uniform sampler3D u_vel_z;
layout(binding = 3) uniform sampler3D u_src;
layout(r8ui, binding = 1) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 0) uniform writeonly image3D u_dst;

uniform ivec3 u_field_size;   // texels of this field
uniform vec3 u_field_offset;  // grid-unit offset of texel (0,0,0)
uniform float u_dt_over_h;    // time step / cell size (s/m); negative traces forward
uniform float u_decay;        // multiplier applied to the result (dissipation), 1 for none
uniform int u_zero_in_solid;  // 1: cells covered by the solid get 0 (scalars only)

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, u_field_size))) return;
  if (u_zero_in_solid != 0 && (imageLoad(u_nbmask, idx).r & NB_SOLID) != 0u) {
    imageStore(u_dst, idx, vec4(0.0));
    return;
  }
  vec3 X = vec3(idx) + u_field_offset;
  vec3 mid = X - 0.5 * u_dt_over_h * sampleVelocity(u_vel_x, u_vel_y, u_vel_z, X);
  vec3 back = X - u_dt_over_h * sampleVelocity(u_vel_x, u_vel_y, u_vel_z, mid);
  back = clamp(back, vec3(0.0), vec3(u_res));
  float value = texture(u_src, fieldCoord(back, vec3(u_field_size), u_field_offset)).r;
  imageStore(u_dst, idx, vec4(value * u_decay));
}
