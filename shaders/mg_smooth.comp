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
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RW(r32f, 0, u_x);
IMAGE_RO(r32f, 1, u_b);
UIMAGE_RO(r8ui, 2, u_mask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_faces);

#ifdef PROLONG
IMAGE_RO(r32f, 3, u_coarse_x);
#define NEIGHBOUR_X(q) (imageLoad(u_x, q).x + imageLoad(u_coarse_x, (q) / 2).x)
#else
#define NEIGHBOUR_X(q) imageLoad(u_x, q).x
#endif

UNIFORM(int, u_colour);      // 0 or 1
UNIFORM(int, u_zero_guess);  // 1: x starts at 0, so the other colour's values are taken as 0

void main() {
  ivec3 g = ivec3(gl_GlobalInvocationID);
  ivec3 c = ivec3(2 * g.x + ((g.y + g.z + u_colour) & 1), g.y, g.z);
  if (!inGrid(c)) return;
  uint m = imageLoad(u_mask, c).x;
  float w[6];
  FACE_OPEN_ALL(u_faces, c, w);
  float n = (m & NB_OPEN_TOP) != 0u ? w[5] : 0.0f;
  UNROLL for (int d = 0; d < 6; ++d) {
    if (((m >> uint(d)) & 1u) != 0u) n += w[d];
  }
  if ((m & NB_SOLID) != 0u || n == 0.0f) {
    imageStore(u_x, c, vec4(0.0f));
    return;
  }
  float sum = 0.0f;
  if (u_zero_guess == 0) {
    UNROLL for (int d = 0; d < 6; ++d) {
      if (((m >> uint(d)) & 1u) != 0u) sum += w[d] * NEIGHBOUR_X(c + NEIGHBOUR[d]);
    }
  }
  imageStore(u_x, c, vec4((imageLoad(u_b, c).x + sum) / n));
}
