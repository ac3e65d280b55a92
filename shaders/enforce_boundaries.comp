// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "enforce_boundaries": on one velocity component, closed domain walls get zero normal
// velocity (the +z wall stays free when the top is open), and every fully covered face (open
// fraction 0) gets the solid's velocity (the average over the solid cells on its two sides; at
// least one cell beside a covered face has its centre in the body). Partly open faces keep the
// fluid's velocity: divergence.comp weights the two parts.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

UIMAGE_RO(r8ui, 1, u_solid);
IMAGE_RO(rgba32f, 2, u_solid_velocity);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);
IMAGE_RW(r32f, 0, u_vel);

UNIFORM(int, u_axis);
UNIFORM(int, u_open_top);

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, faceSize(u_axis)))) return;
  int i = idx[u_axis];
  if (i == 0 || i == u_res[u_axis]) {
    bool open = u_open_top != 0 && u_axis == 2 && i == u_res.z;
    if (!open) {
      imageStore(u_vel, idx, vec4(0.0f));
      return;
    }
  }
  if (imageLoad(u_face_open, idx)[u_axis] > 0.0f) return;
  // Clamping makes both sides of an open-top face the cell below it.
  ivec3 lo = clampCell(idx - unitAxis(u_axis));
  ivec3 hi = clampCell(idx);
  bool slo = imageLoad(u_solid, lo).x != 0u;
  bool shi = imageLoad(u_solid, hi).x != 0u;
  if (!slo && !shi) {  // not reached for a sphere or a voxelized body; the mean of both sides
    slo = true;
    shi = true;
  }
  float sum = 0.0f;
  if (slo) sum += imageLoad(u_solid_velocity, lo)[u_axis];
  if (shi) sum += imageLoad(u_solid_velocity, hi)[u_axis];
  imageStore(u_vel, idx, vec4(sum / float(int(slo) + int(shi))));
}
