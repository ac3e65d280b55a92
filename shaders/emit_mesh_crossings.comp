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
layout(local_size_x = WG_LINEAR) in;

layout(std430, binding = 0) readonly buffer Grid { vec4 grid_vertices[]; };
layout(std430, binding = 1) readonly buffer Triangles { uint indices[]; };
layout(std430, binding = 2) buffer Crossings { int crossings[]; };  // per cell: count, length

uniform uint u_count;    // triangles
uniform int u_subcell;   // lattice steps per cell, a multiple of 2 u_samples
uniform int u_samples;   // S, sub-columns per cell along x and y
uniform int u_limit;     // largest |lattice coordinate| (the host keeps vertices within it)

const float kLength = 65536.0;  // fixed-point units per cell of length

ivec2 snapXY(vec3 p) {
  return ivec2(clamp(round(p.xy * float(u_subcell)), vec2(-float(u_limit)), vec2(float(u_limit))));
}

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }  // b > 0

// The sub-column at q is on the inner (left) side of edge a -> b, ties broken by the (e, e^2) shift.
bool inside(ivec2 a, ivec2 b, ivec2 q, out double e) {
  ivec2 d = b - a;
  e = double(d.x) * double(q.y - a.y) - double(d.y) * double(q.x - a.x);
  return e > 0.0lf || (e == 0.0lf && (d.y < 0 || (d.y == 0 && d.x > 0)));
}

// Height of the unsnapped triangle above q (grid units), barycentric weights clamped to the
// triangle; the exact weights serve when the float area vanishes.
float hitHeight(vec3 pa, vec3 pb, vec3 pc, vec2 q, double ea, double eb, double ec, double area) {
  vec2 d1 = pb.xy - pa.xy, d2 = pc.xy - pa.xy, r = q - pa.xy;
  float a = d1.x * d2.y - d1.y * d2.x;
  if (a == 0.0) return float((ea * double(pa.z) + eb * double(pb.z) + ec * double(pc.z)) / area);
  vec2 w = max(vec2(r.x * d2.y - r.y * d2.x, d1.x * r.y - d1.y * r.x) / a, vec2(0.0));
  float s = w.x + w.y;
  if (s > 1.0) w /= s;
  return pa.z + w.x * (pb.z - pa.z) + w.y * (pc.z - pa.z);
}

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= u_count) return;
  vec3 pa = grid_vertices[indices[3u * t]].xyz;
  vec3 pb = grid_vertices[indices[3u * t + 1u]].xyz;
  vec3 pc = grid_vertices[indices[3u * t + 2u]].xyz;
  ivec2 a = snapXY(pa), b = snapXY(pb), c = snapXY(pc);
  double area = double(b.x - a.x) * double(c.y - a.y) - double(b.y - a.y) * double(c.x - a.x);
  if (area == 0.0lf) return;
  int sign = -1;  // counter-clockwise seen from +z: outward normal up, the +z ray leaves here
  if (area < 0.0lf) {
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
      float z = hitHeight(pa, pb, pc, (vec2(m, n) + 0.5) / float(u_samples), ea, eb, ec, area);
      if (z >= float(u_res.z)) continue;
      int k = 0;
      float above = 1.0;  // length of cell k above the hit
      if (z > 0.0) {
        k = min(int(floor(z)), u_res.z - 1);
        above = clamp(float(k + 1) - z, 0.0, 1.0);
      }
      int cell = m / u_samples + u_res.x * (n / u_samples + u_res.y * k);
      atomicAdd(crossings[2 * cell], sign);
      atomicAdd(crossings[2 * cell + 1], sign * int(round(above * kLength)));
    }
  }
}
