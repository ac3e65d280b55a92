// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "voxelize_mesh_winding": the fine voxelization of a mesh probe's cut cells. One
// invocation per column of the fine grid (the probe's cell box at u_fine samples per cell and
// axis, voxelize_mesh_crossings run on it) sums the signed crossings bottom-up in place: each
// entry becomes the mesh's winding number around that fine cell's centre (nonzero: solid).
LOCAL_SIZE(WG_X, WG_Y, 1);

BUFFER_RW(Crossings, int, 0, crossings);

void main() {
  ivec2 col = ivec2(gl_GlobalInvocationID);
  if (any(greaterThanEqual(col, ivec2(u_res)))) return;
  int winding = 0;
  for (int k = 0; k < u_res.z; ++k) {
    int n = col.x + u_res.x * (col.y + u_res.y * k);
    winding += crossings[n];
    crossings[n] = winding;
  }
}
