// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "project": subtracts (dt/rho) grad p from one velocity component on faces with an open
// part (both cells beside them then hold a pressure unknown), and on the open top (ghost pressure
// 0). The stored velocity is the face's fluid part; the covered part carries the solid's velocity
// (divergence.comp). Fully covered faces keep the solid's velocity and closed walls stay at 0
// (set by enforce_boundaries); per-texel update only.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_pressure);
UIMAGE_RO(r8ui, 2, u_nbmask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);
IMAGE_RW(r32f, 0, u_vel);

UNIFORM(int, u_axis);
UNIFORM(int, u_open_top);
UNIFORM(float, u_scale);  // dt / (rho h): metres per second of velocity per pascal of difference

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, faceSize(u_axis)))) return;
  int i = idx[u_axis];
  bool top = u_open_top != 0 && u_axis == 2 && i == u_res.z;
  if ((i == 0 || i == u_res[u_axis]) && !top) return;
  if (imageLoad(u_face_open, idx)[u_axis] <= 0.0f) return;
  ivec3 lo = idx - unitAxis(u_axis);
  if ((imageLoad(u_nbmask, lo).x & NB_SOLID) != 0u) return;
  float p_lo = imageLoad(u_pressure, lo).x;
  float p_hi = 0.0f;
  if (!top) {
    if ((imageLoad(u_nbmask, idx).x & NB_SOLID) != 0u) return;
    p_hi = imageLoad(u_pressure, idx).x;
  }
  float v = imageLoad(u_vel, idx).x;
  imageStore(u_vel, idx, vec4(v - u_scale * (p_hi - p_lo)));
}
