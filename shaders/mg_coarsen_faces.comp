// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_coarsen_faces": the face fractions (common.glsl) of a coarse multigrid level from the
// next finer one: a coarse face's open fraction is the sum of the open fractions of the (up to
// four) fine faces it is made of, over four. With piecewise-constant transfer this is the
// Galerkin coarse operator up to the level's fixed scale (mg_restrict.comp), so the coarse levels
// see the cut cells' partly open faces. The top faces (z = the coarse grid's top) are the open
// top's, where a box has one: their fraction is also scaled by u_top_scale (the ratio of the open
// top's weight on this level to the finer level's: MultigridVCycle::openTopWeight). Dispatched over a box of the coarse face texels
// (coarse resolution + 1) that starts at u_origin: all of them, or those a moved obstacle can change
// (MultigridVCycle::buildMasks).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(rgba32f, 1, u_fine_faces);
IMAGE_WO(rgba32f, 0, u_coarse_faces);

UNIFORM(ivec3, u_fine_size);  // fine cells per axis
UNIFORM(ivec3, u_origin);     // first face texel of the box dispatched
UNIFORM(float, u_top_scale);  // the open top's weight here over the finer level's (see above)

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID) + u_origin;
  if (any(greaterThan(idx, u_res))) return;
  vec4 w = vec4(1.0f);
  UNROLL for (int a = 0; a < 3; ++a) {
    if (any(greaterThanEqual(idx, faceSize(a)))) continue;
    int b = (a + 1) % 3;
    int c = (a + 2) % 3;
    float sum = 0.0f;
    for (int o = 0; o < 4; ++o) {
      ivec3 f = 2 * idx;
      f[a] = min(2 * idx[a], u_fine_size[a]);  // the far wall of an odd fine size
      f[b] += o & 1;
      f[c] += o >> 1;
      if (f[b] >= u_fine_size[b] || f[c] >= u_fine_size[c]) continue;
      sum += imageLoad(u_fine_faces, f)[a];
    }
    w[a] = 0.25f * sum;
    if (a == 2 && idx.z == u_res.z) w[a] *= u_top_scale;
  }
  imageStore(u_coarse_faces, idx, w);
}
