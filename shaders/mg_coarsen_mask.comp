// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "mg_coarsen_mask": the neighbour mask (bits of common.glsl) of a coarse multigrid level
// from the next finer one. A coarse cell is fluid if any of its fine children is; it is linked
// to its coarse neighbour across side d if a fluid child on that side is linked across it (so
// walls, solids and the open top carry down exactly, and regions the fine grid keeps apart stay
// apart); it sees the open top if a fluid child does. Dispatched over a box of the coarse grid
// that starts at u_origin: all of it, or the cells a moved obstacle can change
// (MultigridVCycle::buildMasks).
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

UIMAGE_RO(r8ui, 1, u_fine_mask);
UIMAGE_WO(r8ui, 0, u_coarse_mask);

UNIFORM(ivec3, u_fine_size);  // fine cells per axis
UNIFORM(ivec3, u_origin);     // first coarse cell of the box dispatched

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID) + u_origin;
  if (!inGrid(c)) return;
  bool fluid = false;
  uint mask = 0u;
  UNROLL for (int o = 0; o < 8; ++o) {
    ivec3 off = ivec3(o & 1, (o >> 1) & 1, (o >> 2) & 1);
    ivec3 f = 2 * c + off;
    if (any(greaterThanEqual(f, u_fine_size))) continue;
    uint m = imageLoad(u_fine_mask, f).x;
    if ((m & NB_SOLID) != 0u) continue;
    fluid = true;
    mask |= m & NB_OPEN_TOP;
    UNROLL for (int a = 0; a < 3; ++a) {
      // Side -a is the children with offset 0 on axis a, side +a those with offset 1 (a
      // coarse cell with only offset-0 children on an axis is the last one: no +a neighbour).
      mask |= m & (1u << uint(2 * a + off[a]));
    }
  }
  imageStore(u_coarse_mask, c, uvec4(fluid ? mask : NB_SOLID));
}
