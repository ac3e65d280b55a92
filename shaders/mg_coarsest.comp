// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_coarsest": the V-cycle's coarsest-level solve in one dispatch, the same arithmetic as
// 4 x u_pairs dispatches of mg_smooth.comp (u_pairs symmetric pairs: red->black u_pairs times,
// the first from x = 0, then black->red u_pairs times), so the result is the same to the bit.
// The level has at most COARSEST cells per axis: one workgroup, one invocation per cell, x in
// shared memory, a barrier between half-sweeps (one dispatch instead of 4 u_pairs, each with its
// barrier and launch; on llvmpipe a dispatch of 48 cells costs about as much as one of 48 000).
LOCAL_SIZE(COARSEST, COARSEST, COARSEST);

IMAGE_WO(r32f, 0, u_x);
IMAGE_RO(r32f, 1, u_b);
UIMAGE_RO(r8ui, 2, u_mask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_faces);

UNIFORM(int, u_pairs);  // symmetric pairs of red-black sweeps (MultigridVCycle::kCoarsestSweeps)

shared float s_x[COARSEST * COARSEST * COARSEST];

int slot(ivec3 c) { return c.x + COARSEST * (c.y + COARSEST * c.z); }

// What one cell's update needs, read once before the sweeps.
struct CoarseCell {
  uint m;       // neighbour mask (NB_SOLID outside the level)
  float w[6];   // open fractions of its faces
  float n;      // the diagonal: linked faces' and the open top's fractions
  float b;
  bool live;    // it has an unknown
};

CoarseCell coarseCell(ivec3 c) {
  CoarseCell cell;
  bool in_grid = inGrid(c);
  cell.m = in_grid ? imageLoad(u_mask, c).x : NB_SOLID;
  UNROLL for (int d = 0; d < 6; ++d) cell.w[d] = 0.0f;
  if (in_grid) FACE_OPEN_ALL(u_faces, c, cell.w);
  cell.n = (cell.m & NB_OPEN_TOP) != 0u ? cell.w[5] : 0.0f;
  UNROLL for (int d = 0; d < 6; ++d) {
    if (((cell.m >> uint(d)) & 1u) != 0u) cell.n += cell.w[d];
  }
  cell.live = (cell.m & NB_SOLID) == 0u && cell.n != 0.0f;
  cell.b = in_grid ? imageLoad(u_b, c).x : 0.0f;
  return cell;
}

// The colour half-sweep h updates: red, black for the first u_pairs pairs, then black, red.
int colourOfHalfSweep(int h) { return h < 2 * u_pairs ? (h & 1) : 1 - (h & 1); }

// Cell c's new x from its neighbours' in s_x (mg_smooth.comp's arithmetic).
float coarseUpdate(ivec3 c, CoarseCell cell) {
  float sum = 0.0f;
  UNROLL for (int d = 0; d < 6; ++d) {
    if (((cell.m >> uint(d)) & 1u) != 0u) sum += cell.w[d] * s_x[slot(c + NEIGHBOUR[d])];
  }
  return (cell.b + sum) / cell.n;
}

// One invocation per cell of the level, a barrier between half-sweeps (the CPU's runner,
// cpu/kernels/mg_coarsest.cpp, runs the same functions cell by cell without them).
void main() {
  ivec3 c = ivec3(gl_LocalInvocationID);
  CoarseCell cell = coarseCell(c);
  int colour = (c.x + c.y + c.z) & 1;
  s_x[slot(c)] = 0.0f;
  memoryBarrierShared();
  barrier();
  for (int h = 0; h < 4 * u_pairs; ++h) {
    if (colour == colourOfHalfSweep(h) && cell.live) s_x[slot(c)] = coarseUpdate(c, cell);
    memoryBarrierShared();
    barrier();
  }
  if (inGrid(c)) imageStore(u_x, c, vec4(s_x[slot(c)]));
}
