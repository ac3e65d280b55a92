// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_smooth": one colour of a red-black Gauss-Seidel sweep of A x = b on one multigrid
// level, where A x = n x - sum of the linked neighbours' w x (w the face's open fraction, n = the
// sum of the linked faces' and the open top's fractions; the mask bits and face fractions of
// common.glsl; coarse levels' fractions from mg_coarsen_faces). Cells of colour (i + j + k) & 1 == u_colour are
// updated in place; they read only the other colour, so the dispatch has no read/write race.
// The dispatch covers ceil(nx / 2) x ny x nz invocations: one per cell of that colour.
// With PROLONG defined (the first sweep after the coarse correction) the neighbours are read as
// x + the coarse x of their parent: mg_prolong.comp's piecewise-constant correction folded into
// the sweep. The cells this sweep writes need no correction (their update does not read their
// own x), and the other colour's cells are rewritten by the next sweep from this one's values,
// so the result is that of mg_prolong then mg_smooth, without the prolongation's full-grid pass.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) uniform image3D u_x;
layout(r32f, binding = 1) readonly uniform image3D u_b;
layout(r8ui, binding = 2) readonly uniform uimage3D u_mask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_faces;

#ifdef PROLONG
layout(r32f, binding = 3) readonly uniform image3D u_coarse_x;
#define NEIGHBOUR_X(q) (imageLoad(u_x, q).r + imageLoad(u_coarse_x, (q) / 2).r)
#else
#define NEIGHBOUR_X(q) imageLoad(u_x, q).r
#endif

uniform int u_colour;      // 0 or 1
uniform int u_zero_guess;  // 1: x starts at 0, so the other colour's values are taken as 0

void main() {
  ivec3 g = ivec3(gl_GlobalInvocationID);
  ivec3 c = ivec3(2 * g.x + ((g.y + g.z + u_colour) & 1), g.y, g.z);
  if (!inGrid(c)) return;
  uint m = imageLoad(u_mask, c).r;
  float w[6];
  FACE_OPEN_ALL(u_faces, c, w);
  float n = (m & NB_OPEN_TOP) != 0u ? w[5] : 0.0;
  for (int d = 0; d < 6; ++d) {
    if (((m >> uint(d)) & 1u) != 0u) n += w[d];
  }
  if ((m & NB_SOLID) != 0u || n == 0.0) {
    imageStore(u_x, c, vec4(0.0));
    return;
  }
  float sum = 0.0;
  if (u_zero_guess == 0) {
    for (int d = 0; d < 6; ++d) {
      if (((m >> uint(d)) & 1u) != 0u) sum += w[d] * NEIGHBOUR_X(c + NEIGHBOUR[d]);
    }
  }
  imageStore(u_x, c, vec4((imageLoad(u_b, c).r + sum) / n));
}
