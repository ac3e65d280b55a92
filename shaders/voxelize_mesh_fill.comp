// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "voxelize_mesh_fill": one invocation per cell column sums the signed crossings bottom-up.
// A cell is solid where the sum (the mesh's winding number around its centre) is nonzero. The
// rigid velocity v + w x (x - origin) is written at every cell centre (m/s), solid or not: cut
// faces outside the body's cells take their covered part's velocity from it.
LOCAL_SIZE(WG_X, WG_Y, 1);

BUFFER_RO(Crossings, int, 0, crossings);
UIMAGE_WO(r8ui, 0, u_solid);
IMAGE_WO(rgba32f, 1, u_solid_velocity);

UNIFORM(vec3, u_origin);      // the body's origin (transform translation), grid units
UNIFORM(vec3, u_velocity);    // of the origin, m/s
UNIFORM(vec3, u_angular);     // rad/s, world frame
UNIFORM(float, u_cell_size);  // m
UNIFORM(ivec3, u_first_column);  // x, y: the dispatch's first column (StepPipeline: the probe's move)

void main() {
  ivec2 col = ivec2(gl_GlobalInvocationID) + ivec2(u_first_column);
  if (any(greaterThanEqual(col, ivec2(u_res)))) return;
  int winding = 0;
  for (int k = 0; k < u_res.z; ++k) {
    ivec3 c = ivec3(col, k);
    winding += crossings[c.x + u_res.x * (c.y + u_res.y * k)];
    bool solid = winding != 0;
    vec3 r = (vec3(c) + 0.5f - u_origin) * u_cell_size;
    vec3 v = u_velocity + cross(u_angular, r);
    imageStore(u_solid, c, uvec4(solid ? 1u : 0u));
    imageStore(u_solid_velocity, c, vec4(v, 0.0f));
  }
}
