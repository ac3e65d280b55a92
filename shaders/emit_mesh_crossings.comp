// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "emit_mesh_crossings" (emitter/mesh_emitter.h): each triangle of the smoke source visits
// the sub-columns whose line (x, y) = ((m + 1/2) / S, (n + 1/2) / S) passes through it, S =
// u_samples sub-columns per cell along x and y. At the hit height z it adds, in the cell (m / S,
// n / S, floor z) holding the hit, its signed crossing (+1 where the +z ray enters the body:
// outward normal down, -1 where it leaves) and the signed length of that cell above the hit,
// sign x (floor z + 1 - z), in fixed point (kLength per cell). A hit below the grid counts in
// cell 0 with the whole cell above it; one above the grid adds nothing. The column test is
// exact as in voxelize_mesh_crossings.comp: xy snapped to a lattice of u_subcell steps per
// cell, integer coordinates, edge functions in double (exact for these magnitudes, so a source
// may reach out of the grid), and a sub-column on an edge or vertex is decided as if moved by
// (e, e^2), so triangles sharing an edge never both count it nor both miss it.
LOCAL_SIZE(WG_LINEAR, 1, 1);

BUFFER_RO(Grid, vec4, 0, grid_vertices);
BUFFER_RO(Triangles, uint, 1, indices);
BUFFER_RW(Crossings, int, 2, crossings);  // per cell: count, length

UNIFORM(uint, u_count);    // triangles
UNIFORM(int, u_subcell);   // lattice steps per cell, a multiple of 2 u_samples
UNIFORM(int, u_samples);   // S, sub-columns per cell along x and y
UNIFORM(int, u_limit);     // largest |lattice coordinate| (the host keeps vertices within it)

CONST float kLength = 65536.0f;  // fixed-point units per cell of length

ivec2 snapXY(vec3 p) {
  return ivec2(clamp(round(vec2(p) * float(u_subcell)), vec2(-float(u_limit)), vec2(float(u_limit))));
}

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }  // b > 0

// The sub-column at q is on the inner (left) side of edge a -> b, ties broken by the (e, e^2) shift.
bool inside(ivec2 a, ivec2 b, ivec2 q, OUT(double) e) {
  ivec2 d = b - a;
  e = double(d.x) * double(q.y - a.y) - double(d.y) * double(q.x - a.x);
  return e > double(0) || (e == double(0) && (d.y < 0 || (d.y == 0 && d.x > 0)));
}

// Height of the unsnapped triangle above q (grid units), barycentric weights clamped to the
// triangle; the exact weights serve when the float area vanishes.
float hitHeight(vec3 pa, vec3 pb, vec3 pc, vec2 q, double ea, double eb, double ec, double area) {
  vec2 d1 = vec2(pb) - vec2(pa), d2 = vec2(pc) - vec2(pa), r = q - vec2(pa);
  float a = d1.x * d2.y - d1.y * d2.x;
  if (a == 0.0f) return float((ea * double(pa.z) + eb * double(pb.z) + ec * double(pc.z)) / area);
  vec2 w = max(vec2(r.x * d2.y - r.y * d2.x, d1.x * r.y - d1.y * r.x) / a, vec2(0.0f));
  float s = w.x + w.y;
  if (s > 1.0f) w /= s;
  return pa.z + w.x * (pb.z - pa.z) + w.y * (pc.z - pa.z);
}

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= u_count) return;
  vec3 pa = vec3(grid_vertices[indices[3u * t]]);
  vec3 pb = vec3(grid_vertices[indices[3u * t + 1u]]);
  vec3 pc = vec3(grid_vertices[indices[3u * t + 2u]]);
  ivec2 a = snapXY(pa), b = snapXY(pb), c = snapXY(pc);
  double area = double(b.x - a.x) * double(c.y - a.y) - double(b.y - a.y) * double(c.x - a.x);
  if (area == double(0)) return;
  int sign = -1;  // counter-clockwise seen from +z: outward normal up, the +z ray leaves here
  if (area < double(0)) {
    ivec2 ti = b; b = c; c = ti;
    vec3 tp = pb; pb = pc; pc = tp;
    area = -area;
    sign = 1;
  }
  int step = u_subcell / u_samples;  // lattice steps between sub-columns (even)
  ivec2 lo = min(a, min(b, c)), hi = max(a, max(b, c));
  // Sub-columns m whose centre m * step + step / 2 lies in [lo, hi], within the grid.
  ivec2 first, last;
  for (int ax = 0; ax < 2; ++ax) {
    first[ax] = max(-floorDiv(-(lo[ax] - step / 2), step), 0);
    last[ax] = min(floorDiv(hi[ax] - step / 2, step), u_res[ax] * u_samples - 1);
  }
  for (int n = first.y; n <= last.y; ++n) {
    for (int m = first.x; m <= last.x; ++m) {
      ivec2 q = ivec2(m, n) * step + step / 2;
      double ea, eb, ec;  // edge functions opposite a, b, c
      if (!inside(b, c, q, ea) || !inside(c, a, q, eb) || !inside(a, b, q, ec)) continue;
      float z = hitHeight(pa, pb, pc, (vec2(m, n) + 0.5f) / float(u_samples), ea, eb, ec, area);
      if (z >= float(u_res.z)) continue;
      int k = 0;
      float above = 1.0f;  // length of cell k above the hit
      if (z > 0.0f) {
        k = min(int(floor(z)), u_res.z - 1);
        above = clamp(float(k + 1) - z, 0.0f, 1.0f);
      }
      int cell = m / u_samples + u_res.x * (n / u_samples + u_res.y * k);
      atomicAdd(crossings[2 * cell], sign);
      atomicAdd(crossings[2 * cell + 1], sign * int(round(above * kLength)));
    }
  }
}
