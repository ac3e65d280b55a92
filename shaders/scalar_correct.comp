// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "scalar_correct": gives smoke and heat back the total that advection lost or gained.
// For each field, the target total is decay * (total before - outflow through an open top)
// (results[0], scalar_total) and the advected total, rise and fall room are results[1] (smoke)
// and results[2] (heat), scalar_headroom. A deficit D > 0 is added to every fluid cell in
// proportion to its room to rise, phi += a (max_local - phi) with a = min(D / rise room, 1); a
// surplus is taken in proportion to the room to fall, phi -= a (phi - min_local). Each value
// stays within its neighbours' range, so the correction makes no new extremum (and nothing
// negative from non-negative data). Reads the advected fields, writes the corrected ones.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_density;
layout(r32f, binding = 2) readonly uniform image3D u_temperature;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 4) uniform writeonly image3D u_density_out;
layout(r32f, binding = 5) uniform writeonly image3D u_temperature_out;
layout(std430, binding = 1) readonly buffer Results { vec4 results[]; };

uniform float u_decay;   // smoke's dissipation multiplier of this step
uniform float u_decay2;  // heat's

// The fractions of the rise room (x) and fall room (y) to apply for a field whose target total
// is `target` and whose advected sums are s (total, rise room, fall room).
vec2 fractions(float target, vec4 s) {
  float deficit = target - s.x;
  if (deficit > 0.0 && s.y > 0.0) return vec2(min(deficit / s.y, 1.0), 0.0);
  if (deficit < 0.0 && s.z > 0.0) return vec2(0.0, min(-deficit / s.z, 1.0));
  return vec2(0.0);
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  vec2 v = vec2(imageLoad(u_density, c).r, imageLoad(u_temperature, c).r);
  uint nb = imageLoad(u_nbmask, c).r;
  if ((nb & NB_SOLID) == 0u) {
    vec4 before = results[0];
    vec2 fd = fractions((before.x - before.z) * u_decay, results[1]);
    vec2 ft = fractions((before.y - before.w) * u_decay2, results[2]);
    vec2 hi = v;
    vec2 lo = v;
    for (int n = 0; n < 6; ++n) {
      if ((nb & (1u << uint(n))) == 0u) continue;
      ivec3 q = c + NEIGHBOUR[n];
      vec2 w = vec2(imageLoad(u_density, q).r, imageLoad(u_temperature, q).r);
      hi = max(hi, w);
      lo = min(lo, w);
    }
    v += vec2(fd.x, ft.x) * (hi - v) - vec2(fd.y, ft.y) * (v - lo);
  }
  imageStore(u_density_out, c, vec4(v.x));
  imageStore(u_temperature_out, c, vec4(v.y));
}
