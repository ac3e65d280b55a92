// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "maccormack": the correction of MacCormack advection,
// phi_new = phi_fwd + (phi - phi_back) / 2, clamped to the range of the eight texels of phi
// around the back-traced point so the scheme stays stable (Selle et al. 2008). The back-trace
// is advect.comp's (velocityAt() of common.glsl, interpolated from imageLoad()s), so the
// limiter's texels are those the forward pass sampled on every device.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 5, u_vel_x);
IMAGE_RO(r32f, 6, u_vel_y);
IMAGE_RO(r32f, 7, u_vel_z);
UIMAGE_RO(r8ui, 1, u_nbmask);
IMAGE_RO(r32f, 2, u_forward);   // semi-Lagrangian result
IMAGE_RO(r32f, 3, u_backward);  // forward result traced back
IMAGE_RO(r32f, 4, u_phi);       // field before advection
IMAGE_WO(r32f, 0, u_dst);

UNIFORM(ivec3, u_field_size);
UNIFORM(vec3, u_field_offset);
UNIFORM(float, u_dt_over_h);
UNIFORM(float, u_decay);        // dissipation multiplier (the passes before it use 1)
UNIFORM(int, u_zero_in_solid);

DEFINE_VELOCITY_AT(u_vel_x, u_vel_y, u_vel_z)

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, u_field_size))) return;
  if (u_zero_in_solid != 0 && (imageLoad(u_nbmask, idx).x & NB_SOLID) != 0u) {
    imageStore(u_dst, idx, vec4(0.0f));
    return;
  }
  vec3 X = vec3(idx) + u_field_offset;
  vec3 mid = X - 0.5f * u_dt_over_h * velocityAt(X);
  vec3 back = X - u_dt_over_h * velocityAt(mid);
  back = clamp(back, vec3(0.0f), vec3(u_res));
  // The eight texels around the back-traced point bound the corrected value.
  vec3 t = back - u_field_offset;
  ivec3 base = clamp(ivec3(floor(t)), ivec3(0), u_field_size - 1);
  float lo = 3.0e38f;
  float hi = -3.0e38f;
  for (int n = 0; n < 8; ++n) {
    ivec3 q = min(base + ivec3(n & 1, (n >> 1) & 1, (n >> 2) & 1), u_field_size - 1);
    float s = imageLoad(u_phi, q).x;
    lo = min(lo, s);
    hi = max(hi, s);
  }
  float fwd = imageLoad(u_forward, idx).x;
  float bwd = imageLoad(u_backward, idx).x;
  float phi = imageLoad(u_phi, idx).x;
  float value = clamp(fwd + 0.5f * (phi - bwd), lo, hi) * u_decay;
  imageStore(u_dst, idx, vec4(value));
}
