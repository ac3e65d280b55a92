// Stage "sphere_fractions": the open fraction of every MAC face (common.glsl's face-fraction
// image) from the probe sphere's geometry. The sphere cuts the plane of a face in a disk; the
// covered part of the unit square is the integral over one in-plane axis of the disk's chord
// clipped to the square, taken with SAMPLES midpoint samples of the exact chord length, so the
// fraction changes continuously as the sphere moves. Fractions under MIN_OPEN are set to 0
// (a nearly covered face would make its cell's pressure row nearly singular).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(rgba32f, binding = 0) uniform writeonly image3D u_face_open;

uniform vec3 u_centre;   // sphere centre, grid units
uniform float u_radius;  // grid units

const int SAMPLES = 16;
const float MIN_OPEN = 0.01;

float openFraction(ivec3 idx, int axis) {
  int b = (axis + 1) % 3;
  int c = (axis + 2) % 3;
  float d = float(idx[axis]) - u_centre[axis];
  float rho2 = u_radius * u_radius - d * d;
  if (rho2 <= 0.0) return 1.0;
  float rho = sqrt(rho2);
  float y0 = float(idx[b]) - u_centre[b];
  float z0 = float(idx[c]) - u_centre[c];
  if (y0 >= rho || y0 + 1.0 <= -rho || z0 >= rho || z0 + 1.0 <= -rho) return 1.0;
  float covered = 0.0;
  for (int s = 0; s < SAMPLES; ++s) {
    float y = y0 + (float(s) + 0.5) / float(SAMPLES);
    float h2 = rho2 - y * y;
    if (h2 <= 0.0) continue;
    float half_chord = sqrt(h2);
    covered += max(0.0, min(z0 + 1.0, half_chord) - max(z0, -half_chord));
  }
  float open = 1.0 - covered / float(SAMPLES);
  return open < MIN_OPEN ? 0.0 : min(open, 1.0);
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThan(idx, u_res))) return;
  vec4 w = vec4(1.0);
  for (int a = 0; a < 3; ++a) {
    if (all(lessThan(idx, faceSize(a)))) w[a] = openFraction(idx, a);
  }
  imageStore(u_face_open, idx, w);
}
