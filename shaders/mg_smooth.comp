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

// One cell's new x from its loaded neighbourhood: m its mask; w_lo, w_hi the open fractions of its
// -x, -y, -z and +x, +y, +z faces; x_lo, x_hi its neighbours' x across them (any value where m has
// no link: it is not used); b its right-hand side. Branch-free and on vectors, so the CPU's row
// loop (cpu/kernels/mg_smooth.cpp) vectorizes it; the same arithmetic as skipping the unlinked
// neighbours (adding 0 is exact).
float smoothedValue(uint m, vec3 w_lo, vec3 w_hi, vec3 x_lo, vec3 x_hi, float b) {
  float n = (m & NB_OPEN_TOP) != 0u ? w_hi.z : 0.0f;
  n += linkedPart(m, 0, w_lo.x);
  n += linkedPart(m, 1, w_hi.x);
  n += linkedPart(m, 2, w_lo.y);
  n += linkedPart(m, 3, w_hi.y);
  n += linkedPart(m, 4, w_lo.z);
  n += linkedPart(m, 5, w_hi.z);
  float sum = 0.0f;
  if (u_zero_guess == 0) {
    sum += linkedPart(m, 0, w_lo.x * x_lo.x);
    sum += linkedPart(m, 1, w_hi.x * x_hi.x);
    sum += linkedPart(m, 2, w_lo.y * x_lo.y);
    sum += linkedPart(m, 3, w_hi.y * x_hi.y);
    sum += linkedPart(m, 4, w_lo.z * x_lo.z);
    sum += linkedPart(m, 5, w_hi.z * x_hi.z);
  }
  return ((m & NB_SOLID) != 0u || n == 0.0f) ? 0.0f : (b + sum) / n;
}

void main() {
  ivec3 g = ivec3(gl_GlobalInvocationID);
  ivec3 c = ivec3(2 * g.x + ((g.y + g.z + u_colour) & 1), g.y, g.z);
  if (!inGrid(c)) return;
  vec3 w_lo = vec3(imageLoad(u_faces, c));
  vec3 w_hi = vec3(imageLoad(u_faces, c + ivec3(1, 0, 0)).x, imageLoad(u_faces, c + ivec3(0, 1, 0)).y,
                   imageLoad(u_faces, c + ivec3(0, 0, 1)).z);
  vec3 x_lo = vec3(NEIGHBOUR_X(c - ivec3(1, 0, 0)), NEIGHBOUR_X(c - ivec3(0, 1, 0)), NEIGHBOUR_X(c - ivec3(0, 0, 1)));
  vec3 x_hi = vec3(NEIGHBOUR_X(c + ivec3(1, 0, 0)), NEIGHBOUR_X(c + ivec3(0, 1, 0)), NEIGHBOUR_X(c + ivec3(0, 0, 1)));
  imageStore(u_x, c, vec4(smoothedValue(imageLoad(u_mask, c).x, w_lo, w_hi, x_lo, x_hi, imageLoad(u_b, c).x)));
}
