// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "apply_forces": adds dt times the body acceleration, averaged from the two cells that
// share each face, to one velocity component (per-texel read-modify-write).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(rgba32f, 1, u_force);
IMAGE_RW(r32f, 0, u_vel);

UNIFORM(int, u_axis);    // 0 = u (x faces), 1 = v, 2 = w
UNIFORM(float, u_dt);    // s

// Face idx's velocity after the step's forces: the mean of its two cells' accelerations (clamped
// to the grid) times dt added. Branch-free: the CPU's row loop (cpu/kernels/apply_forces.cpp)
// vectorizes it.
float acceleratedVelocity(ivec3 idx) {
  ivec3 lo = clampCell(idx - unitAxis(u_axis));
  ivec3 hi = clampCell(idx);
  float a = 0.5f * (component(imageLoad(u_force, lo), u_axis) + component(imageLoad(u_force, hi), u_axis));
  return imageLoad(u_vel, idx).x + u_dt * a;
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, faceSize(u_axis)))) return;
  imageStore(u_vel, idx, vec4(acceleratedVelocity(idx)));
}
