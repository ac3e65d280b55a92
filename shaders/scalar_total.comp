// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "scalar_total": per row of cells along x (j, k), the totals of smoke and heat before
// advection (x, y of partials[j + ny k]) and, with an open top, the amount of each that the
// velocity carries out through the top faces in this step (z, w; negative where it flows in):
// phi * w * dt / h per top cell, in the same units as the totals (value x cells). The first level
// of the conservation that scalar_correct restores (fluid/scalar_conservation.h).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_density);
IMAGE_RO(r32f, 2, u_temperature);
IMAGE_RO(r32f, 3, u_vel_z);
BUFFER_WO(Partials, vec4, 0, partials);

UNIFORM(int, u_open_top);      // 1: the +z wall is open
UNIFORM(float, u_dt_over_h);   // time step / cell size (s/m)

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 acc = vec4(0.0f);
  bool top = u_open_top != 0 && row.y == u_res.z - 1;
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    float d = imageLoad(u_density, c).x;
    float t = imageLoad(u_temperature, c).x;
    acc += vec4(d, t, 0.0f, 0.0f);
    if (top) acc += vec4(0.0f, 0.0f, d, t) * (imageLoad(u_vel_z, c + ivec3(0, 0, 1)).x * u_dt_over_h);
  }
  partials[row.x + u_res.y * row.y] = acc;
}
