// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "emit_coverage" (emitter/mesh_emitter.h): the mesh smoke source emits into the cells of
// its box by their coverage c (0..1): Hold raises smoke and heat to at least c x the values, Rate
// adds c x the values x dt (fluid/fluid_params.h SourceEmission). Cells with no open face (inside
// the probe) are left alone. Per-texel read-modify-write only.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) uniform image3D u_density;
layout(r32f, binding = 1) uniform image3D u_temperature;
layout(r8ui, binding = 2) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 3) readonly uniform image3D u_coverage;

uniform ivec3 u_origin;             // first cell of the dispatched box
uniform float u_density_value;      // concentration (Hold), per second (Rate)
uniform float u_temperature_value;  // K above ambient (Hold), K/s (Rate)
uniform int u_rate;                 // 1: Rate, 0: Hold
uniform float u_dt;                 // s

void main() {
  ivec3 c = u_origin + ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  float cover = imageLoad(u_coverage, c).r;
  if (cover <= 0.0) return;
  if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) return;
  float d = imageLoad(u_density, c).r;
  float t = imageLoad(u_temperature, c).r;
  if (u_rate != 0) {
    imageStore(u_density, c, vec4(d + cover * u_density_value * u_dt));
    imageStore(u_temperature, c, vec4(t + cover * u_temperature_value * u_dt));
  } else {
    imageStore(u_density, c, vec4(max(d, cover * u_density_value)));
    imageStore(u_temperature, c, vec4(max(t, cover * u_temperature_value)));
  }
}
