// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "sources": the sphere smoke emitter. Cells whose centre lies in the emitter sphere are
// raised to at least the emitter's density and temperature (Hold), or get them added per second
// (Rate, fluid/fluid_params.h SourceEmission); per-texel read-modify-write only.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RW(r32f, 0, u_density);
IMAGE_RW(r32f, 1, u_temperature);
UIMAGE_RO(r8ui, 2, u_nbmask);

UNIFORM(ivec3, u_origin);       // first cell of the dispatched box
UNIFORM(vec3, u_centre);        // emitter centre, grid units
UNIFORM(float, u_radius);       // grid units
UNIFORM(float, u_density_value);      // smoke concentration (dimensionless)
UNIFORM(float, u_temperature_value);  // K above ambient (Hold), K/s (Rate)
UNIFORM(int, u_rate);                 // 1: add value x dt (Rate), 0: raise to at least value (Hold)
UNIFORM(float, u_dt);                 // s

void main() {
  ivec3 c = u_origin + ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  vec3 r = vec3(c) + 0.5f - u_centre;
  if (dot(r, r) > u_radius * u_radius) return;
  if ((imageLoad(u_nbmask, c).x & NB_SOLID) != 0u) return;
  float d = imageLoad(u_density, c).x;
  float t = imageLoad(u_temperature, c).x;
  if (u_rate != 0) {
    imageStore(u_density, c, vec4(d + u_density_value * u_dt));
    imageStore(u_temperature, c, vec4(t + u_temperature_value * u_dt));
  } else {
    imageStore(u_density, c, vec4(max(d, u_density_value)));
    imageStore(u_temperature, c, vec4(max(t, u_temperature_value)));
  }
}
