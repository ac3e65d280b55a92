// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "scalar_total": per row of cells along x (j, k), the totals of smoke and heat before
// advection (x, y of partials[j + ny k]) and, with an open top, the amount of each that the
// velocity carries out through the top faces in this step (z, w; negative where it flows in):
// phi * w * dt / h per top cell, in the same units as the totals (value x cells). The first level
// of the conservation that scalar_correct restores (fluid/scalar_conservation.h).
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 1) readonly uniform image3D u_density;
layout(r32f, binding = 2) readonly uniform image3D u_temperature;
layout(r32f, binding = 3) readonly uniform image3D u_vel_z;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };

uniform int u_open_top;      // 1: the +z wall is open
uniform float u_dt_over_h;   // time step / cell size (s/m)

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0);
  bool top = u_open_top != 0 && row.y == u_res.z - 1;
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    float d = imageLoad(u_density, c).r;
    float t = imageLoad(u_temperature, c).r;
    acc.xy += vec2(d, t);
    if (top) acc.zw += vec2(d, t) * (imageLoad(u_vel_z, c + ivec3(0, 0, 1)).r * u_dt_over_h);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
