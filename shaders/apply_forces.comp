// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "apply_forces": adds dt times the body acceleration, averaged from the two cells that
// share each face, to one velocity component (per-texel read-modify-write).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(rgba32f, 1, u_force);
IMAGE_RW(r32f, 0, u_vel);

UNIFORM(int, u_axis);    // 0 = u (x faces), 1 = v, 2 = w
UNIFORM(float, u_dt);    // s

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, faceSize(u_axis)))) return;
  ivec3 lo = clampCell(idx - unitAxis(u_axis));
  ivec3 hi = clampCell(idx);
  float a = 0.5f * (imageLoad(u_force, lo)[u_axis] + imageLoad(u_force, hi)[u_axis]);
  float v = imageLoad(u_vel, idx).x;
  imageStore(u_vel, idx, vec4(v + u_dt * a));
}
