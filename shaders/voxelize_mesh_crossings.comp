// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "voxelize_mesh_crossings": each triangle adds its signed crossing to every cell column
// (i, j) whose centre line (x, y) = (i + 0.5, j + 0.5) passes through it: +1 where the +z ray
// enters the body (outward normal pointing down), -1 where it leaves, added atomically at the
// first cell whose centre lies above the hit. The column-in-triangle test is exact: xy are
// snapped to a fixed-point lattice of u_subcell steps per cell and the edge functions are
// integers. A column on an edge or vertex is decided as if it were moved by (e, e^2) for a tiny
// e > 0, so triangles sharing that edge never both count it nor both miss it; a closed mesh then
// gives every column crossings that sum to its winding number. Zero-area projections add
// nothing. Every loop is bounded by the triangle's box clamped to the grid.
LOCAL_SIZE(WG_LINEAR, 1, 1);

BUFFER_RO(Grid, vec4, 0, grid_vertices);
BUFFER_RO(Triangles, uint, 1, indices);
BUFFER_RW(Crossings, int, 2, crossings);

UNIFORM(uint, u_count);    // triangles
UNIFORM(int, u_subcell);   // fixed-point steps per cell (even)

ivec2 snapXY(vec3 p) {
  vec2 limit = vec2(ivec2(u_res) * u_subcell);
  return ivec2(clamp(round(vec2(p) * float(u_subcell)), vec2(0.0f), limit));
}

// The column at q is on the inner (left) side of edge a -> b, ties broken by the (e, e^2) shift.
bool inside(ivec2 a, ivec2 b, ivec2 q, OUT(int) e) {
  ivec2 d = b - a;
  e = d.x * (q.y - a.y) - d.y * (q.x - a.x);
  return e > 0 || (e == 0 && (d.y < 0 || (d.y == 0 && d.x > 0)));
}

// Height of the triangle above column centre q. The snapped triangle decided that q is in; the
// height comes from the unsnapped one (snapping a steep triangle tilts it a lot), with the
// barycentric weights clamped to the triangle so a column that snapping moved just inside
// takes the nearest edge's height. Integer weights serve when the float area vanishes.
float hitHeight(vec3 pa, vec3 pb, vec3 pc, vec2 q, int ea, int eb, int ec, int area) {
  vec2 d1 = vec2(pb) - vec2(pa), d2 = vec2(pc) - vec2(pa), r = q - vec2(pa);
  float a = d1.x * d2.y - d1.y * d2.x;
  if (a == 0.0f) return (float(ea) * pa.z + float(eb) * pb.z + float(ec) * pc.z) / float(area);
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
  int area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (area == 0) return;
  // Counter-clockwise seen from +z: outward normal up, so the +z ray leaves the body here.
  int sign = -1;
  if (area < 0) {  // make it counter-clockwise; the ray enters here
    ivec2 ti = b; b = c; c = ti;
    vec3 tp = pb; pb = pc; pc = tp;
    area = -area;
    sign = 1;
  }
  ivec2 lo = min(a, min(b, c)), hi = max(a, max(b, c));
  // Columns whose centre (i + 0.5) * s lies in [lo, hi].
  ivec2 first = max((lo - u_subcell / 2 + u_subcell - 1) / u_subcell, ivec2(0));
  ivec2 last = min((hi - u_subcell / 2) / u_subcell, ivec2(u_res) - 1);
  // lo - s/2 may be negative: integer division rounds towards zero, so fix the first column.
  for (int ax = 0; ax < 2; ++ax) {
    if (lo[ax] < u_subcell / 2) first[ax] = 0;
  }
  for (int j = first.y; j <= last.y; ++j) {
    for (int i = first.x; i <= last.x; ++i) {
      ivec2 q = ivec2(i, j) * u_subcell + u_subcell / 2;
      int ea, eb, ec;  // edge functions opposite a, b, c
      if (!inside(b, c, q, ea) || !inside(c, a, q, eb) || !inside(a, b, q, ec)) continue;
      float z = hitHeight(pa, pb, pc, vec2(i, j) + 0.5f, ea, eb, ec, area);
      int k = int(floor(z + 0.5f));  // first cell whose centre k + 0.5 is above z
      k = clamp(k, 0, u_res.z);
      if (k == u_res.z) continue;
      atomicAdd(crossings[i + u_res.x * (j + u_res.y * k)], sign);
    }
  }
}
