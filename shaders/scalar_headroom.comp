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

// Cell c's room to rise and to fall against its own and its fluid neighbours' values (nbmask bits
// 0-5): smoke's in .xy, heat's in .zw; 0 in a solid cell. d and t: the cell's smoke and heat.
// Branch-free (every neighbour is loaded; one across an unlinked face counts as the cell itself,
// which moves neither the max nor the min; both are exact in any order), so the CPU's row loop
// (cpu/kernels/scalar_headroom.cpp) vectorizes it.
vec4 headroomAt(ivec3 c, uint nb, float d, float t) {
  vec2 hi = vec2(d, t);
  vec2 lo = hi;
  UNROLL for (int n = 0; n < 6; ++n) {
    ivec3 q = c + NEIGHBOUR[n];
    vec2 v = vec2(imageLoad(u_density, q).x, imageLoad(u_temperature, q).x);
    v = ((nb >> uint(n)) & 1u) != 0u ? v : vec2(d, t);
    hi = max(hi, v);
    lo = min(lo, v);
  }
  return (nb & NB_SOLID) != 0u ? vec4(0.0f) : vec4(hi.x - d, d - lo.x, hi.y - t, t - lo.y);
}

// A cell's parts of the row's sums: (d, rise, fall, 0) into d_acc, (t, rise, fall, 0) into t_acc
// (a solid cell adds 0 to the rooms: exact, the sums are never -0).
void addHeadroom(INOUT(vec4) d_acc, INOUT(vec4) t_acc, float d, float t, vec4 room) {
  d_acc += vec4(d, room.x, room.y, 0.0f);
  t_acc += vec4(t, room.z, room.w, 0.0f);
}

// The row's cells in order, their parts summed in that order (cpu/kernels/scalar_headroom.cpp
// sums in it too).
void main() {
  ivec2 row = ivec2(gl_GlobalInvocationID);
  if (row.x >= u_res.y || row.y >= u_res.z) return;
  vec4 d_acc = vec4(0.0f);
  vec4 t_acc = vec4(0.0f);
  for (int i = 0; i < u_res.x; ++i) {
    ivec3 c = ivec3(i, row);
    float d = imageLoad(u_density, c).x;
    float t = imageLoad(u_temperature, c).x;
    addHeadroom(d_acc, t_acc, d, t, headroomAt(c, imageLoad(u_nbmask, c).x, d, t));
  }
  int rows = u_res.y * u_res.z;
  partials[row.x + u_res.y * row.y] = d_acc;
  partials[rows + row.x + u_res.y * row.y] = t_acc;
}
