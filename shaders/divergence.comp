// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "divergence": right-hand side of the pressure equation in pascals,
// rhs = (rho h^2 / dt) div(u) = (rho h / dt) * (sum of outgoing face fluxes), 0 in cells without
// a pressure unknown. A face's flux is its open fraction w times the fluid velocity plus the
// covered part (1 - w) times the solid's velocity there (cut cells); a fully covered face already
// holds the solid's velocity (enforce_boundaries).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_vel_x;
layout(r32f, binding = 2) readonly uniform image3D u_vel_y;
layout(r32f, binding = 3) readonly uniform image3D u_vel_z;
layout(r8ui, binding = 4) readonly uniform uimage3D u_nbmask;
layout(rgba32f, binding = 5) readonly uniform image3D u_solid_velocity;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_face_open;
layout(r32f, binding = 0) uniform writeonly image3D u_rhs;

uniform float u_scale;  // rho * h / dt, kg/(m^2 s)

float faceVelocity(ivec3 idx, int axis) {
  if (axis == 0) return imageLoad(u_vel_x, idx).r;
  if (axis == 1) return imageLoad(u_vel_y, idx).r;
  return imageLoad(u_vel_z, idx).r;
}

// Flux (m/s) through the face with index idx on `axis`, the fluid and solid parts weighted.
float faceFlux(ivec3 idx, int axis) {
  float u = faceVelocity(idx, axis);
  float w = imageLoad(u_face_open, idx)[axis];
  if (w <= 0.0 || w >= 1.0) return u;
  // The rigid velocity is linear in position: the face's is the mean of its two cells'.
  float us = 0.5 * (imageLoad(u_solid_velocity, clampCell(idx - unitAxis(axis)))[axis] +
                    imageLoad(u_solid_velocity, clampCell(idx))[axis]);
  return w * u + (1.0 - w) * us;
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) {
    imageStore(u_rhs, c, vec4(0.0));
    return;
  }
  float flux = 0.0;
  for (int a = 0; a < 3; ++a) flux += faceFlux(c + unitAxis(a), a) - faceFlux(c, a);
  imageStore(u_rhs, c, vec4(u_scale * flux));
}
