// Stage "classify": from the solid mask, writes the seed's four cell classes and, for the
// pressure stages, each cell's neighbour mask (see common.glsl).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r8ui, binding = 2) readonly uniform uimage3D u_solid;
layout(r8ui, binding = 0) uniform writeonly uimage3D u_class;
layout(r8ui, binding = 1) uniform writeonly uimage3D u_nbmask;

uniform int u_open_top;  // 1: the +z wall is open (pressure 0 beyond it)

bool solidAt(ivec3 c) { return imageLoad(u_solid, c).r != 0u; }

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  bool solid = solidAt(c);
  uint mask = solid ? NB_SOLID : 0u;
  bool fluid_nb = false;
  bool solid_nb = false;
  for (int d = 0; d < 6; ++d) {
    ivec3 q = c + NEIGHBOUR[d];
    if (!inGrid(q)) {
      if (d == 5 && u_open_top != 0) mask |= NB_OPEN_TOP;
      continue;
    }
    if (solidAt(q)) {
      solid_nb = true;
    } else {
      fluid_nb = true;
      mask |= 1u << uint(d);
    }
  }
  uint cls = solid ? (fluid_nb ? CELL_BOUNDARY : CELL_INSIDE)
                   : (solid_nb ? CELL_SURROUNDING : CELL_OUTSIDE);
  imageStore(u_class, c, uvec4(cls));
  imageStore(u_nbmask, c, uvec4(mask));
}
