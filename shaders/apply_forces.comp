// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "apply_forces": adds dt times the body acceleration, averaged from the two cells that
// share each face, to one velocity component (per-texel read-modify-write).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(rgba32f, binding = 1) readonly uniform image3D u_force;
layout(r32f, binding = 0) uniform image3D u_vel;

uniform int u_axis;    // 0 = u (x faces), 1 = v, 2 = w
uniform float u_dt;    // s

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, faceSize(u_axis)))) return;
  ivec3 lo = clampCell(idx - unitAxis(u_axis));
  ivec3 hi = clampCell(idx);
  float a = 0.5 * (imageLoad(u_force, lo)[u_axis] + imageLoad(u_force, hi)[u_axis]);
  float v = imageLoad(u_vel, idx).r;
  imageStore(u_vel, idx, vec4(v + u_dt * a));
}
