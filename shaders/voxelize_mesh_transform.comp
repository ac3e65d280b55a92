// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "voxelize_mesh_transform": the mesh's local vertices (m) -> grid units with the pose's
// matrix (local -> world -> grid). Done once per vertex, so every triangle sharing a vertex
// sees bit-identical coordinates (the exact column tests of the next stage rely on it).
LOCAL_SIZE(WG_LINEAR, 1, 1);

BUFFER_RO(Local, vec4, 0, local_vertices);
BUFFER_WO(Grid, vec4, 1, grid_vertices);

UNIFORM(mat4, u_to_grid);
UNIFORM(uint, u_count);  // vertices

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  grid_vertices[i] = vec4(vec3(u_to_grid * vec4(vec3(local_vertices[i]), 1.0f)), 1.0f);
}
