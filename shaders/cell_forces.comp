// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "cell_forces": body accelerations at cell centres (m/s^2): Boussinesq buoyancy of hot
// smoke and, when enabled, vorticity confinement (Fedkiw, Stam & Jensen 2001).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 1, u_density);
IMAGE_RO(r32f, 2, u_temperature);
IMAGE_RO(rgba32f, 3, u_vorticity);
UIMAGE_RO(r8ui, 4, u_nbmask);
IMAGE_WO(rgba32f, 0, u_force);

UNIFORM(vec3, u_up);               // unit vector against gravity
UNIFORM(float, u_smoke_weight);    // m/s^2 per unit smoke concentration (pulls down)
UNIFORM(float, u_heat_buoyancy);   // m/s^2 per kelvin above ambient (pushes up)
UNIFORM(float, u_confinement);     // dimensionless epsilon; 0 disables
UNIFORM(float, u_cell_size);       // m

float vortMag(ivec3 c) { return imageLoad(u_vorticity, clampCell(c)).w; }

// The force per unit mass on cell c: buoyancy, plus the confinement where it is on and the
// vorticity magnitude's gradient is not 0; 0 in a solid cell. Branch-free, its lookups clamped to
// the grid, so the CPU's row loop (cpu/kernels/cell_forces.cpp) runs it unchecked and
// vectorized (the same arithmetic as branching: the other values are computed, then not taken).
vec3 cellForce(ivec3 c) {
  bool solid = (imageLoad(u_nbmask, c).x & NB_SOLID) != 0u;
  float d = imageLoad(u_density, c).x;
  float t = imageLoad(u_temperature, c).x;
  vec3 f = u_up * (u_heat_buoyancy * t - u_smoke_weight * d);
  vec3 grad = vec3(vortMag(c + ivec3(1, 0, 0)) - vortMag(c - ivec3(1, 0, 0)),
                   vortMag(c + ivec3(0, 1, 0)) - vortMag(c - ivec3(0, 1, 0)),
                   vortMag(c + ivec3(0, 0, 1)) - vortMag(c - ivec3(0, 0, 1)));
  float g = length(grad);
  bool confine = u_confinement > 0.0f && g > 1.0e-20f;
  vec3 n = grad / (confine ? g : 1.0f);
  vec3 w = vec3(imageLoad(u_vorticity, c));
  vec3 confined = f + u_confinement * u_cell_size * cross(n, w);
  return solid ? vec3(0.0f) : (confine ? confined : f);
}

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  imageStore(u_force, c, vec4(cellForce(c), 0.0f));
}
