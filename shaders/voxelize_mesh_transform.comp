// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "voxelize_mesh_transform": the mesh's local vertices (m) -> grid units with the pose's
// matrix (local -> world -> grid). Done once per vertex, so every triangle sharing a vertex
// sees bit-identical coordinates (the exact column tests of the next stage rely on it).
layout(local_size_x = WG_LINEAR) in;

layout(std430, binding = 0) readonly buffer Local { vec4 local_vertices[]; };
layout(std430, binding = 1) writeonly buffer Grid { vec4 grid_vertices[]; };

uniform mat4 u_to_grid;
uniform uint u_count;  // vertices

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  grid_vertices[i] = vec4((u_to_grid * vec4(local_vertices[i].xyz, 1.0)).xyz, 1.0);
}
