// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "force_faces": the first level of the force, torque and centroid reductions. Over a box
// of cells, every MAC face with a covered part (open fraction w < 1, cut cells) adds the pressure
// force on that part of the body, F_f = -(1 - w) h^2 (P_hi - P_lo) e_axis (N): the body's
// surface integral -int p n dA written as the volume integral -int grad p dV over the covered
// face parts (Batty, Bertails & Bridson 2007), so it changes continuously as the body moves. P is
// the solved (dynamic) pressure of the cells beside the face (0 in cells without an unknown:
// their two faces on each axis are both covered, so they cancel) plus the hydrostatic pressure,
// whose difference across a face is rho g_axis h. The moment is (x_f - p0) x F_f (N m) about a
// point p0 near the body; every solid cell adds its centre relative to p0 (m). With binary
// fractions (u_cut_cells 0) a covered face with a cell on one side only counts half of the
// hydrostatic part (the voxel body fills half of that face's dual cell), and the sum equals the
// one over the faces between boundary and fluid cells. Each workgroup
// writes three sums: part 0 (force, faces with a covered part beside an unknown), part 1
// (torque, 0), part 2 (sum of x_c - p0, solid cells).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) readonly uniform image3D u_pressure;
layout(r8ui, binding = 1) readonly uniform uimage3D u_class;
layout(r8ui, binding = 2) readonly uniform uimage3D u_nbmask;
layout(rgba32f, binding = FACE_OPEN_UNIT) readonly uniform image3D u_face_open;

uniform ivec3 u_origin;         // first cell of the box
uniform ivec3 u_extent;         // cells in the box
uniform float u_face_area;      // h^2, m^2
uniform float u_cell_size;      // h, m
uniform vec3 u_rho_g;           // fluid density times gravity, N/m^3
uniform int u_cut_cells;        // 1: geometric face fractions; 0: binary (voxels)
uniform vec3 u_p0;              // grid-unit point the torque and centroid are summed about

bool unknownAt(ivec3 c) { return (imageLoad(u_nbmask, c).r & NB_SOLID) == 0u; }

void main() {
  ivec3 local = ivec3(gl_GlobalInvocationID);
  ivec3 c = u_origin + local;
  vec4 force = vec4(0.0);
  vec3 torque = vec3(0.0);
  vec4 cells = vec4(0.0);
  bool inside = all(lessThan(local, u_extent)) && inGrid(c);
  uint cls = inside ? imageLoad(u_class, c).r : CELL_OUTSIDE;
  vec3 centre = vec3(c) + 0.5;
  if (cls == CELL_BOUNDARY || cls == CELL_INSIDE) cells = vec4((centre - u_p0) * u_cell_size, 1.0);
  if (inside) {
    bool here = unknownAt(c);
    float p_here = here ? imageLoad(u_pressure, c).r : 0.0;
    for (int a = 0; a < 3; ++a) {
      if (c[a] == 0) continue;  // a domain wall: no cell below
      float covered = 1.0 - imageLoad(u_face_open, c)[a];
      if (covered <= 0.0) continue;
      ivec3 lo = c - unitAxis(a);
      bool below = unknownAt(lo);
      float p_lo = below ? imageLoad(u_pressure, lo).r : 0.0;
      float hydro = (u_cut_cells == 0 && here != below) ? 0.5 : 1.0;
      float dp = p_here - p_lo + hydro * u_rho_g[a] * u_cell_size;
      vec3 f = vec3(0.0);
      f[a] = -covered * u_face_area * dp;
      vec3 face = centre;
      face[a] = float(c[a]);
      force += vec4(f, (here || below) ? 1.0 : 0.0);
      torque += cross((face - u_p0) * u_cell_size, f);
    }
  }
  writeGroupSumAt(force, 0u);
  writeGroupSumAt(vec4(torque, 0.0), 1u);
  writeGroupSumAt(cells, 2u);
}
