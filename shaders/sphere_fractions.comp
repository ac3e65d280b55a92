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
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(rgba32f, binding = 0) uniform writeonly image3D u_face_open;

uniform vec3 u_centre;        // sphere centre, grid units
uniform float u_ramp_radius;  // where the ramp is half covered, grid units
uniform float u_min_open;     // obstacle::kMinOpenFraction
uniform ivec3 u_origin;       // first face texel of the region dispatched

const int SAMPLES = 12;

float openFraction(ivec3 idx, int axis) {
  int b = (axis + 1) % 3;
  int c = (axis + 2) % 3;
  float d = float(idx[axis]) - u_centre[axis];
  float outer = u_ramp_radius + 0.5;
  float rho2 = outer * outer - d * d;
  if (rho2 <= 0.0) return 1.0;
  float rho = sqrt(rho2);
  float y0 = float(idx[b]) - u_centre[b];
  float z0 = float(idx[c]) - u_centre[c];
  if (y0 >= rho || y0 + 1.0 <= -rho || z0 >= rho || z0 + 1.0 <= -rho) return 1.0;
  float covered = 0.0;
  for (int s = 0; s < SAMPLES; ++s) {
    float y = y0 + (float(s) + 0.5) / float(SAMPLES);
    float dy2 = d * d + y * y;
    for (int t = 0; t < SAMPLES; ++t) {
      float z = z0 + (float(t) + 0.5) / float(SAMPLES);
      covered += clamp(outer - sqrt(dy2 + z * z), 0.0, 1.0);
    }
  }
  return cutOffOpen(1.0 - covered / float(SAMPLES * SAMPLES), u_min_open);
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID) + u_origin;
  if (any(greaterThan(idx, u_res))) return;
  vec4 w = vec4(1.0);
  for (int a = 0; a < 3; ++a) {
    if (all(lessThan(idx, faceSize(a)))) w[a] = openFraction(idx, a);
  }
  imageStore(u_face_open, idx, w);
}
