// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_direction": the next search direction s = z + beta s, beta = (r.z)_new / (r.z)_old
// from the reduction results (beta = 0 on the first iteration); per-texel update, 0 in solids.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) uniform image3D u_s;
layout(r32f, binding = 1) readonly uniform image3D u_z;
layout(r8ui, binding = 2) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 1) readonly buffer Results { vec4 results[]; };

uniform uint u_slot_new;  // results[u_slot_new].x = r.z of this iteration
uniform uint u_slot_old;  // results[u_slot_old].x = r.z of the previous one
uniform int u_first;      // 1: s = z

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) {
    imageStore(u_s, c, vec4(0.0));
    return;
  }
  float old_rz = results[u_slot_old].x;
  float beta = (u_first != 0 || old_rz <= 0.0) ? 0.0 : results[u_slot_new].x / old_rz;
  float s = u_first != 0 ? 0.0 : imageLoad(u_s, c).r;
  imageStore(u_s, c, vec4(imageLoad(u_z, c).r + beta * s));
}
