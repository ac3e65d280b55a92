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

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  if ((imageLoad(u_nbmask, c).x & NB_SOLID) != 0u) {
    imageStore(u_force, c, vec4(0.0f));
    return;
  }
  float d = imageLoad(u_density, c).x;
  float t = imageLoad(u_temperature, c).x;
  vec3 f = u_up * (u_heat_buoyancy * t - u_smoke_weight * d);
  if (u_confinement > 0.0f) {
    vec3 grad = vec3(vortMag(c + ivec3(1, 0, 0)) - vortMag(c - ivec3(1, 0, 0)),
                     vortMag(c + ivec3(0, 1, 0)) - vortMag(c - ivec3(0, 1, 0)),
                     vortMag(c + ivec3(0, 0, 1)) - vortMag(c - ivec3(0, 0, 1)));
    float g = length(grad);
    if (g > 1.0e-20f) {
      vec3 n = grad / g;
      vec3 w = vec3(imageLoad(u_vorticity, c));
      f += u_confinement * u_cell_size * cross(n, w);
    }
  }
  imageStore(u_force, c, vec4(f, 0.0f));
}
