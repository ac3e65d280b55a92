// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "emit_coverage" (emitter/mesh_emitter.h): the mesh smoke source emits into the cells of
// its box by their coverage c (0..1): Hold raises smoke and heat to at least c x the values, Rate
// adds c x the values x dt (fluid/fluid_params.h SourceEmission). Cells with no open face (inside
// the probe) are left alone. Per-texel read-modify-write only.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RW(r32f, 0, u_density);
IMAGE_RW(r32f, 1, u_temperature);
UIMAGE_RO(r8ui, 2, u_nbmask);
IMAGE_RO(r32f, 3, u_coverage);

UNIFORM(ivec3, u_origin);             // first cell of the dispatched box
UNIFORM(float, u_density_value);      // concentration (Hold), per second (Rate)
UNIFORM(float, u_temperature_value);  // K above ambient (Hold), K/s (Rate)
UNIFORM(int, u_rate);                 // 1: Rate, 0: Hold
UNIFORM(float, u_dt);                 // s

void main() {
  ivec3 c = u_origin + ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  float cover = imageLoad(u_coverage, c).x;
  if (cover <= 0.0f) return;
  if ((imageLoad(u_nbmask, c).x & NB_SOLID) != 0u) return;
  float d = imageLoad(u_density, c).x;
  float t = imageLoad(u_temperature, c).x;
  if (u_rate != 0) {
    imageStore(u_density, c, vec4(d + cover * u_density_value * u_dt));
    imageStore(u_temperature, c, vec4(t + cover * u_temperature_value * u_dt));
  } else {
    imageStore(u_density, c, vec4(max(d, cover * u_density_value)));
    imageStore(u_temperature, c, vec4(max(t, cover * u_temperature_value)));
  }
}
