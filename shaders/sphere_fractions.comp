// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "sphere_fractions": the open fraction of every MAC face (common.glsl's face-fraction
// image) from the probe sphere's geometry. The sphere's indicator is smoothed along its normal
// into a linear ramp one cell wide (covered 1 at distance u_ramp_radius - 0.5 from the centre, 0
// at u_ramp_radius + 0.5), and a face's covered fraction is the mean of that ramp over the face,
// SAMPLES x SAMPLES midpoint samples. The ramp makes every fraction, and the body's sampled
// cross-sections, smooth functions of the sphere's position: with the sharp sphere the discrete
// body's added mass changed by 1.5% within a cell (its cap passing face planes) and the force on a
// body moving at constant speed rippled once per cell crossed. u_ramp_radius is chosen on the host
// so the ramp's volume is the sphere's (SphereProbe::rampRadius). Fractions under u_min_open go
// to 0 continuously (common.glsl's cutOffOpen).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_WO(rgba32f, 0, u_face_open);

UNIFORM(vec3, u_centre);        // sphere centre, grid units
UNIFORM(float, u_ramp_radius);  // where the ramp is half covered, grid units
UNIFORM(float, u_min_open);     // obstacle::kMinOpenFraction
UNIFORM(ivec3, u_origin);       // first face texel of the region dispatched

CONST int SAMPLES = 12;

float openFraction(ivec3 idx, int axis) {
  int b = (axis + 1) % 3;
  int c = (axis + 2) % 3;
  float d = float(idx[axis]) - u_centre[axis];
  float outer = u_ramp_radius + 0.5f;
  float rho2 = outer * outer - d * d;
  if (rho2 <= 0.0f) return 1.0f;
  float rho = sqrt(rho2);
  float y0 = float(idx[b]) - u_centre[b];
  float z0 = float(idx[c]) - u_centre[c];
  if (y0 >= rho || y0 + 1.0f <= -rho || z0 >= rho || z0 + 1.0f <= -rho) return 1.0f;
  float covered = 0.0f;
  for (int s = 0; s < SAMPLES; ++s) {
    float y = y0 + (float(s) + 0.5f) / float(SAMPLES);
    float dy2 = d * d + y * y;
    for (int t = 0; t < SAMPLES; ++t) {
      float z = z0 + (float(t) + 0.5f) / float(SAMPLES);
      covered += clamp(outer - sqrt(dy2 + z * z), 0.0f, 1.0f);
    }
  }
  return cutOffOpen(1.0f - covered / float(SAMPLES * SAMPLES), u_min_open);
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID) + u_origin;
  if (any(greaterThan(idx, u_res))) return;
  vec4 w = vec4(1.0f);
  UNROLL for (int a = 0; a < 3; ++a) {
    if (all(lessThan(idx, faceSize(a)))) w[a] = openFraction(idx, a);
  }
  imageStore(u_face_open, idx, w);
}
