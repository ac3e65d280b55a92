// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "sources": the sphere smoke emitter. Cells whose centre lies in the emitter sphere are
// raised to at least the emitter's density and temperature (Hold), or get them added per second
// (Rate, fluid/fluid_params.h SourceEmission); per-texel read-modify-write only.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) uniform image3D u_density;
layout(r32f, binding = 1) uniform image3D u_temperature;
layout(r8ui, binding = 2) readonly uniform uimage3D u_nbmask;

uniform ivec3 u_origin;       // first cell of the dispatched box
uniform vec3 u_centre;        // emitter centre, grid units
uniform float u_radius;       // grid units
uniform float u_density_value;      // smoke concentration (dimensionless)
uniform float u_temperature_value;  // K above ambient (Hold), K/s (Rate)
uniform int u_rate;                 // 1: add value x dt (Rate), 0: raise to at least value (Hold)
uniform float u_dt;                 // s

void main() {
  ivec3 c = u_origin + ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  vec3 r = vec3(c) + 0.5 - u_centre;
  if (dot(r, r) > u_radius * u_radius) return;
  if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) return;
  float d = imageLoad(u_density, c).r;
  float t = imageLoad(u_temperature, c).r;
  if (u_rate != 0) {
    imageStore(u_density, c, vec4(d + u_density_value * u_dt));
    imageStore(u_temperature, c, vec4(t + u_temperature_value * u_dt));
  } else {
    imageStore(u_density, c, vec4(max(d, u_density_value)));
    imageStore(u_temperature, c, vec4(max(t, u_temperature_value)));
  }
}
