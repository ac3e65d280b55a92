// Stage "pcg_update": alpha = (r.z) / (s.q) from the reduction results, then p += alpha s and
// r -= alpha q on fluid cells (per-texel updates), and per workgroup (sum of the new r, fluid
// cells, r.r) into partials[] (x / y is the mean that a closed box removes).
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) uniform image3D u_pressure;
layout(r32f, binding = 1) uniform image3D u_r;
layout(r32f, binding = 2) readonly uniform image3D u_s;
layout(r32f, binding = 3) readonly uniform image3D u_q;
layout(r8ui, binding = 4) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 1) readonly buffer Results { vec4 results[]; };

uniform uint u_slot_rz;  // results[u_slot_rz].x = r.z
uniform uint u_slot_sq;  // results[u_slot_sq].x = s.q

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  vec4 mine = vec4(0.0);
  if (inGrid(c) && (imageLoad(u_nbmask, c).r & NB_SOLID) == 0u) {
    float sq = results[u_slot_sq].x;
    float alpha = sq > 0.0 ? results[u_slot_rz].x / sq : 0.0;
    imageStore(u_pressure, c, vec4(imageLoad(u_pressure, c).r + alpha * imageLoad(u_s, c).r));
    float r = imageLoad(u_r, c).r - alpha * imageLoad(u_q, c).r;
    imageStore(u_r, c, vec4(r));
    mine = vec4(r, 1.0, r * r, 0.0);
  }
  writeGroupSum(mine);
}
