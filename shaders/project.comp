// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "project": subtracts (dt/rho) grad p from one velocity component on faces with an open
// part (both cells beside them then hold a pressure unknown), and on the open top (ghost pressure
// 0). The stored velocity is the face's fluid part; the covered part carries the solid's velocity
// (divergence.comp). Fully covered faces keep the solid's velocity and closed walls stay at 0
// (set by enforce_boundaries); per-texel update only.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_pressure;
layout(r8ui, binding = 2) readonly uniform uimage3D u_nbmask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_face_open;
layout(r32f, binding = 0) uniform image3D u_vel;

uniform int u_axis;
uniform int u_open_top;
uniform float u_scale;  // dt / (rho h): metres per second of velocity per pascal of difference

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, faceSize(u_axis)))) return;
  int i = idx[u_axis];
  bool top = u_open_top != 0 && u_axis == 2 && i == u_res.z;
  if ((i == 0 || i == u_res[u_axis]) && !top) return;
  if (imageLoad(u_face_open, idx)[u_axis] <= 0.0) return;
  ivec3 lo = idx - unitAxis(u_axis);
  if ((imageLoad(u_nbmask, lo).r & NB_SOLID) != 0u) return;
  float p_lo = imageLoad(u_pressure, lo).r;
  float p_hi = 0.0;
  if (!top) {
    if ((imageLoad(u_nbmask, idx).r & NB_SOLID) != 0u) return;
    p_hi = imageLoad(u_pressure, idx).r;
  }
  float v = imageLoad(u_vel, idx).r;
  imageStore(u_vel, idx, vec4(v - u_scale * (p_hi - p_lo)));
}
