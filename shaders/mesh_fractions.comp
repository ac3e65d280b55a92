// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mesh_fractions": the open fraction of every MAC face (common.glsl's face-fraction image)
// of a mesh probe with cut cells, from its fine voxelization (voxelize_mesh_winding: the winding
// number at the centres of u_fine^3 fine cells per cell over the probe's cell box). A face's
// covered fraction is the solid share of the fine cells in its control volume, the cell-sized box
// centred on the face (half of each cell beside it): the fluid volume weights of Batty, Bertails
// and Bridson 2007. Fractions under u_min_open go to 0 continuously (cutOffOpen); faces whose box
// lies outside the fine grid are open.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

BUFFER_RO(Winding, int, 0, winding);
IMAGE_WO(rgba32f, 0, u_face_open);

UNIFORM(ivec3, u_box_origin);  // first cell of the fine grid's box
UNIFORM(ivec3, u_fine_res);    // fine cells per axis (u_fine x the box's cells)
UNIFORM(int, u_fine);          // fine cells per cell and axis (even)
UNIFORM(float, u_min_open);    // obstacle::kMinOpenFraction
UNIFORM(ivec3, u_first);       // the dispatch's first face texel (StepPipeline: the probe's move)

float openFraction(ivec3 idx, int axis) {
  ivec3 lo = (idx - u_box_origin) * u_fine;  // fine index of the face's corner
  lo[axis] -= u_fine / 2;
  ivec3 hi = lo + u_fine;  // exclusive
  if (any(lessThanEqual(hi, ivec3(0))) || any(greaterThanEqual(lo, u_fine_res))) return 1.0f;
  ivec3 a = max(lo, ivec3(0)), b = min(hi, u_fine_res);
  int solid = 0;
  for (int k = a.z; k < b.z; ++k)
    for (int j = a.y; j < b.y; ++j)
      for (int i = a.x; i < b.x; ++i) {
        if (winding[i + u_fine_res.x * (j + u_fine_res.y * k)] != 0) ++solid;
      }
  return cutOffOpen(1.0f - float(solid) / float(u_fine * u_fine * u_fine), u_min_open);
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID) + u_first;
  if (any(greaterThan(idx, u_res))) return;
  vec4 w = vec4(1.0f);
  UNROLL for (int a = 0; a < 3; ++a) {
    if (all(lessThan(idx, faceSize(a)))) w[a] = openFraction(idx, a);
  }
  imageStore(u_face_open, idx, w);
}
