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
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 0, u_pressure);
UIMAGE_RO(r8ui, 1, u_class);
UIMAGE_RO(r8ui, 2, u_nbmask);
IMAGE_RO(rgba32f, FACE_OPEN_UNIT, u_face_open);

UNIFORM(ivec3, u_origin);         // first cell of the box
UNIFORM(ivec3, u_extent);         // cells in the box
UNIFORM(float, u_face_area);      // h^2, m^2
UNIFORM(float, u_cell_size);      // h, m
UNIFORM(vec3, u_rho_g);           // fluid density times gravity, N/m^3
UNIFORM(int, u_cut_cells);        // 1: geometric face fractions; 0: binary (voxels)
UNIFORM(vec3, u_p0);              // grid-unit point the torque and centroid are summed about

bool unknownAt(ivec3 c) { return (imageLoad(u_nbmask, c).x & NB_SOLID) == 0u; }

void main() {
  ivec3 local = ivec3(gl_GlobalInvocationID);
  ivec3 c = u_origin + local;
  vec4 force = vec4(0.0f);
  vec3 torque = vec3(0.0f);
  vec4 cells = vec4(0.0f);
  bool inside = all(lessThan(local, u_extent)) && inGrid(c);
  uint cls = inside ? imageLoad(u_class, c).x : CELL_OUTSIDE;
  vec3 centre = vec3(c) + 0.5f;
  if (cls == CELL_BOUNDARY || cls == CELL_INSIDE) cells = vec4((centre - u_p0) * u_cell_size, 1.0f);
  if (inside) {
    bool here = unknownAt(c);
    float p_here = here ? imageLoad(u_pressure, c).x : 0.0f;
    UNROLL for (int a = 0; a < 3; ++a) {
      if (c[a] == 0) continue;  // a domain wall: no cell below
      float covered = 1.0f - imageLoad(u_face_open, c)[a];
      if (covered <= 0.0f) continue;
      ivec3 lo = c - unitAxis(a);
      bool below = unknownAt(lo);
      float p_lo = below ? imageLoad(u_pressure, lo).x : 0.0f;
      float hydro = (u_cut_cells == 0 && here != below) ? 0.5f : 1.0f;
      float dp = p_here - p_lo + hydro * u_rho_g[a] * u_cell_size;
      vec3 f = vec3(0.0f);
      f[a] = -covered * u_face_area * dp;
      vec3 face = centre;
      face[a] = float(c[a]);
      force += vec4(f, (here || below) ? 1.0f : 0.0f);
      torque += cross((face - u_p0) * u_cell_size, f);
    }
  }
  writeGroupSumAt(force, 0u);
  writeGroupSumAt(vec4(torque, 0.0f), 1u);
  writeGroupSumAt(cells, 2u);
}
