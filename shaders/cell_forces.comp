// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "cell_forces": body accelerations at cell centres (m/s^2): Boussinesq buoyancy of hot
// smoke and, when enabled, vorticity confinement (Fedkiw, Stam & Jensen 2001).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_density;
layout(r32f, binding = 2) readonly uniform image3D u_temperature;
layout(rgba32f, binding = 3) readonly uniform image3D u_vorticity;
layout(r8ui, binding = 4) readonly uniform uimage3D u_nbmask;
layout(rgba32f, binding = 0) uniform writeonly image3D u_force;

uniform vec3 u_up;               // unit vector against gravity
uniform float u_smoke_weight;    // m/s^2 per unit smoke concentration (pulls down)
uniform float u_heat_buoyancy;   // m/s^2 per kelvin above ambient (pushes up)
uniform float u_confinement;     // dimensionless epsilon; 0 disables
uniform float u_cell_size;       // m

float vortMag(ivec3 c) { return imageLoad(u_vorticity, clampCell(c)).w; }

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) {
    imageStore(u_force, c, vec4(0.0));
    return;
  }
  float d = imageLoad(u_density, c).r;
  float t = imageLoad(u_temperature, c).r;
  vec3 f = u_up * (u_heat_buoyancy * t - u_smoke_weight * d);
  if (u_confinement > 0.0) {
    vec3 grad = vec3(vortMag(c + ivec3(1, 0, 0)) - vortMag(c - ivec3(1, 0, 0)),
                     vortMag(c + ivec3(0, 1, 0)) - vortMag(c - ivec3(0, 1, 0)),
                     vortMag(c + ivec3(0, 0, 1)) - vortMag(c - ivec3(0, 0, 1)));
    float g = length(grad);
    if (g > 1.0e-20) {
      vec3 n = grad / g;
      vec3 w = imageLoad(u_vorticity, c).xyz;
      f += u_confinement * u_cell_size * cross(n, w);
    }
  }
  imageStore(u_force, c, vec4(f, 0.0));
}
