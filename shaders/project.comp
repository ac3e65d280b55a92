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

// Face idx's velocity after the pressure's gradient is taken from it: only an open face between
// two fluid cells, or under the open top (whose ghost holds 0 Pa), changes; the domain's walls,
// covered faces and faces of a solid cell keep theirs. Every load is made whatever the face
// (branch-free: the CPU's row loop, cpu/kernels/project.cpp, vectorizes it; GL reads 0 past
// the grid, the CPU a guard band, and the value is then not used).
float projectedVelocity(ivec3 idx) {
  int i = component(idx, u_axis);
  bool top = u_open_top != 0 && u_axis == 2 && i == u_res.z;
  bool wall = (i == 0 || i == component(u_res, u_axis)) && !top;
  bool open = component(imageLoad(u_face_open, idx), u_axis) > 0.0f;
  ivec3 lo = idx - unitAxis(u_axis);
  bool lo_fluid = (imageLoad(u_nbmask, lo).x & NB_SOLID) == 0u;
  bool idx_fluid = (imageLoad(u_nbmask, idx).x & NB_SOLID) == 0u;  // loads outside the selects
  float p_lo = imageLoad(u_pressure, lo).x;
  float p_idx = imageLoad(u_pressure, idx).x;
  bool hi_fluid = top || idx_fluid;
  float p_hi = top ? 0.0f : p_idx;
  float v = imageLoad(u_vel, idx).x;
  return (!wall && open && lo_fluid && hi_fluid) ? v - u_scale * (p_hi - p_lo) : v;
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, faceSize(u_axis)))) return;
  imageStore(u_vel, idx, vec4(projectedVelocity(idx)));
}
