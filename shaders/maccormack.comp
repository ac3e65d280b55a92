// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "maccormack": the correction of MacCormack advection,
// phi_new = phi_fwd + (phi - phi_back) / 2, clamped to the range of the eight texels of phi
// around the back-traced point so the scheme stays stable (Selle et al. 2008). The back-trace
// is advect.comp's (velocityAt() of common.glsl, interpolated from imageLoad()s), so the
// limiter's texels are those the forward pass sampled on every device.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 5) readonly uniform image3D u_vel_x;
layout(r32f, binding = 6) readonly uniform image3D u_vel_y;
layout(r32f, binding = 7) readonly uniform image3D u_vel_z;
layout(r8ui, binding = 1) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 2) readonly uniform image3D u_forward;   // semi-Lagrangian result
layout(r32f, binding = 3) readonly uniform image3D u_backward;  // forward result traced back
layout(r32f, binding = 4) readonly uniform image3D u_phi;       // field before advection
layout(r32f, binding = 0) uniform writeonly image3D u_dst;

uniform ivec3 u_field_size;
uniform vec3 u_field_offset;
uniform float u_dt_over_h;
uniform float u_decay;        // dissipation multiplier (the passes before it use 1)
uniform int u_zero_in_solid;

DEFINE_VELOCITY_AT(u_vel_x, u_vel_y, u_vel_z)

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, u_field_size))) return;
  if (u_zero_in_solid != 0 && (imageLoad(u_nbmask, idx).r & NB_SOLID) != 0u) {
    imageStore(u_dst, idx, vec4(0.0));
    return;
  }
  vec3 X = vec3(idx) + u_field_offset;
  vec3 mid = X - 0.5 * u_dt_over_h * velocityAt(X);
  vec3 back = X - u_dt_over_h * velocityAt(mid);
  back = clamp(back, vec3(0.0), vec3(u_res));
  // The eight texels around the back-traced point bound the corrected value.
  vec3 t = back - u_field_offset;
  ivec3 base = clamp(ivec3(floor(t)), ivec3(0), u_field_size - 1);
  float lo = 3.0e38;
  float hi = -3.0e38;
  for (int n = 0; n < 8; ++n) {
    ivec3 q = min(base + ivec3(n & 1, (n >> 1) & 1, (n >> 2) & 1), u_field_size - 1);
    float s = imageLoad(u_phi, q).r;
    lo = min(lo, s);
    hi = max(hi, s);
  }
  float fwd = imageLoad(u_forward, idx).r;
  float bwd = imageLoad(u_backward, idx).r;
  float phi = imageLoad(u_phi, idx).r;
  float value = clamp(fwd + 0.5 * (phi - bwd), lo, hi) * u_decay;
  imageStore(u_dst, idx, vec4(value));
}
