// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "voxelize_sphere": marks the cells whose centre lies in the probe sphere as solid and
// stores the rigid velocity v + w x r of the body at every cell centre (m/s; cut faces outside
// the body's cells take their covered part's velocity from it).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

UIMAGE_WO(r8ui, 0, u_solid);
IMAGE_WO(rgba32f, 1, u_solid_velocity);

UNIFORM(vec3, u_centre);         // sphere centre, grid units
UNIFORM(float, u_radius);        // grid units
UNIFORM(vec3, u_velocity);       // m/s
UNIFORM(vec3, u_angular);        // rad/s
UNIFORM(float, u_cell_size);     // m
UNIFORM(ivec3, u_origin);        // first cell of the region dispatched (StepPipeline: the probe's move)

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID) + u_origin;
  if (!inGrid(c)) return;
  vec3 r = vec3(c) + 0.5f - u_centre;
  bool solid = dot(r, r) <= u_radius * u_radius;
  vec3 v = u_velocity + cross(u_angular, r * u_cell_size);
  imageStore(u_solid, c, uvec4(solid ? 1u : 0u));
  imageStore(u_solid_velocity, c, vec4(v, 0.0f));
}
