// Stage "force_faces": the first level of the force, torque and centroid reductions. Over a box
// of cells, every exposed face between a boundary cell and a fluid (surrounding) cell adds the
// fluid's pressure times the face area along the inward normal, F_f = -p n_out h^2 (N), and its
// moment (x_f - p0) x F_f (N m) about a point p0 near the body; every solid cell adds its centre
// relative to p0 (m). The pressure on a face is the surrounding cell's solved (dynamic) pressure
// plus the hydrostatic pressure at the face's centre. Each workgroup writes three sums:
// part 0 (force, faces), part 1 (torque, 0), part 2 (sum of x_c - p0, solid cells).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) readonly uniform image3D u_pressure;
layout(r8ui, binding = 1) readonly uniform uimage3D u_class;

uniform ivec3 u_origin;         // first cell of the box
uniform ivec3 u_extent;         // cells in the box
uniform float u_face_area;      // h^2, m^2
uniform float u_cell_size;      // h, m
uniform vec3 u_rho_g;           // fluid density times gravity, N/m^3
uniform vec3 u_reference;       // grid-unit point where the hydrostatic pressure is 0
uniform vec3 u_p0;              // grid-unit point the torque and centroid are summed about

void main() {
  ivec3 local = ivec3(gl_GlobalInvocationID);
  ivec3 c = u_origin + local;
  vec4 force = vec4(0.0);
  vec3 torque = vec3(0.0);
  vec4 cells = vec4(0.0);
  uint cls = (all(lessThan(local, u_extent)) && inGrid(c)) ? imageLoad(u_class, c).r : CELL_OUTSIDE;
  vec3 centre = vec3(c) + 0.5;
  if (cls == CELL_BOUNDARY || cls == CELL_INSIDE) cells = vec4((centre - u_p0) * u_cell_size, 1.0);
  if (cls == CELL_BOUNDARY) {
    for (int d = 0; d < 6; ++d) {
      ivec3 q = c + NEIGHBOUR[d];
      if (!inGrid(q)) continue;
      uint k = imageLoad(u_class, q).r;
      if (k != CELL_SURROUNDING && k != CELL_OUTSIDE) continue;
      vec3 n_out = vec3(NEIGHBOUR[d]);
      vec3 face = centre + 0.5 * n_out;
      float p = imageLoad(u_pressure, q).r + dot(u_rho_g, (face - u_reference) * u_cell_size);
      vec3 f = -p * u_face_area * n_out;
      force += vec4(f, 1.0);
      torque += cross((face - u_p0) * u_cell_size, f);
    }
  }
  writeGroupSumAt(force, 0u);
  writeGroupSumAt(vec4(torque, 0.0), 1u);
  writeGroupSumAt(cells, 2u);
}
