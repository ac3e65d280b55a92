// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "scalar_correct": gives smoke and heat back the total that advection lost or gained.
// For each field, the target total is decay * (total before - outflow through an open top)
// (results[0], scalar_total) and the advected total, rise and fall room are results[1] (smoke)
// and results[2] (heat), scalar_headroom. A deficit D > 0 is added to every fluid cell in
// proportion to its room to rise, phi += a (max_local - phi) with a = min(D / rise room, 1); a
// surplus is taken in proportion to the room to fall, phi -= a (phi - min_local). Each value
// stays within its neighbours' range, so the correction makes no new extremum (and nothing
// negative from non-negative data). Reads the advected fields, writes the corrected ones.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_density);
IMAGE_RO(r32f, 2, u_temperature);
UIMAGE_RO(r8ui, 3, u_nbmask);
IMAGE_WO(r32f, 4, u_density_out);
IMAGE_WO(r32f, 5, u_temperature_out);
BUFFER_RO(Results, vec4, 1, results);

UNIFORM(float, u_decay);   // smoke's dissipation multiplier of this step
UNIFORM(float, u_decay2);  // heat's

// The fractions of the rise room (x) and fall room (y) to apply for a field whose target total
// is `target` and whose advected sums are s (total, rise room, fall room).
vec2 fractions(float target, vec4 s) {
  float deficit = target - s.x;
  bool up = deficit > 0.0f && s.y > 0.0f;
  bool down = deficit < 0.0f && s.z > 0.0f;
  float f_up = min(deficit / (up ? s.y : 1.0f), 1.0f);
  float f_down = min(-deficit / (down ? s.z : 1.0f), 1.0f);
  return vec2(up ? f_up : 0.0f, down ? f_down : 0.0f);  // deficit's sign makes them exclusive
}

// Cell c's corrected (smoke, heat) from its values v, its mask nb and the fractions fd (smoke's)
// and ft (heat's) of its rise and fall rooms to apply. Branch-free (every neighbour loaded, the
// linked ones taken), so the CPU's row loop (cpu/kernels/scalar_correct.cpp) vectorizes it, and
// runs it with nb a constant on rows wholly linked.
vec2 correctedFrom(ivec3 c, vec2 v, uint nb, vec2 fd, vec2 ft) {
  vec2 hi = v;
  vec2 lo = v;
  UNROLL for (int n = 0; n < 6; ++n) {
    ivec3 q = c + NEIGHBOUR[n];
    vec2 w = vec2(imageLoad(u_density, q).x, imageLoad(u_temperature, q).x);
    bool linked = (nb & (1u << uint(n))) != 0u;
    hi = linked ? max(hi, w) : hi;
    lo = linked ? min(lo, w) : lo;
  }
  vec2 corrected = v + vec2(fd.x, ft.x) * (hi - v) - vec2(fd.y, ft.y) * (v - lo);
  return (nb & NB_SOLID) != 0u ? v : corrected;
}

// The fractions of smoke's (xy) and heat's (zw) rooms to apply this step: the same for every cell.
vec4 stepFractions() {
  vec4 before = results[0];
  return vec4(fractions((before.x - before.z) * u_decay, results[1]),
              fractions((before.y - before.w) * u_decay2, results[2]));
}

// Cell c's corrected (smoke, heat).
vec2 correctedValues(ivec3 c) {
  vec4 f = stepFractions();
  return correctedFrom(c, vec2(imageLoad(u_density, c).x, imageLoad(u_temperature, c).x),
                       imageLoad(u_nbmask, c).x, vec2(f.x, f.y), vec2(f.z, f.w));
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  vec2 v = correctedValues(c);
  imageStore(u_density_out, c, vec4(v.x));
  imageStore(u_temperature_out, c, vec4(v.y));
}
