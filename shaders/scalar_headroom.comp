// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "scalar_headroom": per row of cells along x (j, k), for smoke (partials[row]) and heat
// (partials[rows + row]) after advection: the total (x), the room to rise (y: sum over fluid
// cells of the local max minus the value) and to fall (z: the value minus the local min), where
// the local max and min are over the cell and its fluid neighbours (nbmask bits 0-5). The
// first level of scalar_correct's redistribution (fluid/scalar_conservation.h).
layout(local_size_x = ROW_X, local_size_y = ROW_Y) in;

layout(r32f, binding = 1) readonly uniform image3D u_density;
layout(r32f, binding = 2) readonly uniform image3D u_temperature;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };

void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID.xy);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 d_acc = vec4(0.0);
  vec4 t_acc = vec4(0.0);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    float d = imageLoad(u_density, c).r;
    float t = imageLoad(u_temperature, c).r;
    d_acc.x += d;
    t_acc.x += t;
    uint nb = imageLoad(u_nbmask, c).r;
    if ((nb & NB_SOLID) != 0u) continue;
    vec2 hi = vec2(d, t);
    vec2 lo = hi;
    for (int n = 0; n < 6; ++n) {
      if ((nb & (1u << uint(n))) == 0u) continue;
      ivec3 q = c + NEIGHBOUR[n];
      vec2 v = vec2(imageLoad(u_density, q).r, imageLoad(u_temperature, q).r);
      hi = max(hi, v);
      lo = min(lo, v);
    }
    d_acc.yz += vec2(hi.x - d, d - lo.x);
    t_acc.yz += vec2(hi.y - t, t - lo.y);
  }
  int rows = u_res.y * u_res.z;
  partials[row.x + u_res.y * row.y] = d_acc;
  partials[rows + row.x + u_res.y * row.y] = t_acc;
}
