// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "divergence": right-hand side of the pressure equation in pascals,
// rhs = (rho h^2 / dt) div(u) = (rho h / dt) * (sum of outgoing face fluxes), 0 in cells without
// a pressure unknown. A face's flux is its open fraction w times the fluid velocity plus the
// covered part (1 - w) times the solid's velocity there (cut cells); a fully covered face already
// holds the solid's velocity (enforce_boundaries).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_vel_x);
IMAGE_RO(r32f, 2, u_vel_y);
IMAGE_RO(r32f, 3, u_vel_z);
UIMAGE_RO(r8ui, 4, u_nbmask);
IMAGE_RO(rgba32f, 5, u_solid_velocity);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);
IMAGE_WO(r32f, 0, u_rhs);

UNIFORM(float, u_scale);  // rho * h / dt, kg/(m^2 s)

float faceVelocity(ivec3 idx, int axis) {
  if (axis == 0) return imageLoad(u_vel_x, idx).x;
  if (axis == 1) return imageLoad(u_vel_y, idx).x;
  return imageLoad(u_vel_z, idx).x;
}

// Flux (m/s) through the face with index idx on `axis`, the fluid and solid parts weighted.
float faceFlux(ivec3 idx, int axis) {
  float u = faceVelocity(idx, axis);
  float w = component(imageLoad(u_face_open, idx), axis);
  // The rigid velocity is linear in position: the face's is the mean of its two cells'.
  float us = 0.5f * (component(imageLoad(u_solid_velocity, clampCell(idx - unitAxis(axis))), axis) +
                     component(imageLoad(u_solid_velocity, clampCell(idx)), axis));
  return (w <= 0.0f || w >= 1.0f) ? u : w * u + (1.0f - w) * us;
}

// Cell c's right-hand side (Pa), 0 without a pressure unknown. Branch-free: the CPU's row loop
// (cpu/kernels/divergence.cpp) vectorizes it.
float divergenceRhs(ivec3 c) {
  float flux = 0.0f;
  UNROLL for (int a = 0; a < 3; ++a) flux += faceFlux(c + unitAxis(a), a) - faceFlux(c, a);
  return (imageLoad(u_nbmask, c).x & NB_SOLID) != 0u ? 0.0f : u_scale * flux;
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  imageStore(u_rhs, c, vec4(divergenceRhs(c)));
}
