// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "scalar_headroom": per row of cells along x (j, k), for smoke (partials[row]) and heat
// (partials[rows + row]) after advection: the total (x), the room to rise (y: sum over fluid
// cells of the local max minus the value) and to fall (z: the value minus the local min), where
// the local max and min are over the cell and its fluid neighbours (nbmask bits 0-5). The
// first level of scalar_correct's redistribution (fluid/scalar_conservation.h).
LOCAL_SIZE(ROW_X, ROW_Y, 1);

IMAGE_RO(r32f, 1, u_density);
IMAGE_RO(r32f, 2, u_temperature);
UIMAGE_RO(r8ui, 3, u_nbmask);
BUFFER_WO(Partials, vec4, 0, partials);

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 d_acc = vec4(0.0f);
  vec4 t_acc = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    float d = imageLoad(u_density, c).x;
    float t = imageLoad(u_temperature, c).x;
    d_acc.x += d;
    t_acc.x += t;
    uint nb = imageLoad(u_nbmask, c).x;
    if ((nb & NB_SOLID) != 0u) continue;
    vec2 hi = vec2(d, t);
    vec2 lo = hi;
    for (int n = 0; n < 6; ++n) {
      if ((nb & (1u << uint(n))) == 0u) continue;
      ivec3 q = c + NEIGHBOUR[n];
      vec2 v = vec2(imageLoad(u_density, q).x, imageLoad(u_temperature, q).x);
      hi = max(hi, v);
      lo = min(lo, v);
    }
    d_acc.y += hi.x - d;
    d_acc.z += d - lo.x;
    t_acc.y += hi.y - t;
    t_acc.z += t - lo.y;
  }
  int rows = u_res.y * u_res.z;
  partials[row.x + u_res.y * row.y] = d_acc;
  partials[rows + row.x + u_res.y * row.y] = t_acc;
}
