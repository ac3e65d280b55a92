// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "classify": from the solid mask, writes the seed's four cell classes (by cell centre)
// and, for the pressure stages, each cell's neighbour mask (see common.glsl) from the face
// fractions: cells are linked across a face with an open part, and a cell with no open face
// has no pressure unknown (NB_SOLID). With binary fractions this is the solid mask's own rule.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

UIMAGE_RO(r8ui, 2, u_solid);
UIMAGE_WO(r8ui, 0, u_class);
UIMAGE_WO(r8ui, 1, u_nbmask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);

UNIFORM(int, u_open_top);  // 1: the +z wall is open (pressure 0 beyond it)
UNIFORM(ivec3, u_origin);  // first cell of the region dispatched (StepPipeline: the probe's move)

bool solidAt(ivec3 c) { return imageLoad(u_solid, c).x != 0u; }

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID) + u_origin;
  if (!inGrid(c)) return;
  bool solid = solidAt(c);
  uint mask = 0u;
  bool fluid_nb = false;
  bool solid_nb = false;
  UNROLL for (int d = 0; d < 6; ++d) {
    ivec3 q = c + NEIGHBOUR[d];
    bool open = FACE_OPEN(u_face_open, c, d) > 0.0f;
    if (!inGrid(q)) {
      if (d == 5 && u_open_top != 0 && open) mask |= NB_OPEN_TOP;
      continue;
    }
    if (open) mask |= 1u << uint(d);
    if (solidAt(q)) {
      solid_nb = true;
    } else {
      fluid_nb = true;
    }
  }
  if (mask == 0u) mask = NB_SOLID;
  uint cls = solid ? (fluid_nb ? CELL_BOUNDARY : CELL_INSIDE)
                   : (solid_nb ? CELL_SURROUNDING : CELL_OUTSIDE);
  imageStore(u_class, c, uvec4(cls));
  imageStore(u_nbmask, c, uvec4(mask));
}
