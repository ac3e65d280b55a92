// Stage "pcg_cold_start": a warm start must never start worse than a cold one. If the previous
// pressure's residual is larger than the right-hand side (results[u_slot]: z = r.r, w = b.b from
// pcg_init), as after an impulsive start or stop, the solve starts from p = 0 instead: p = 0 and
// r = b = -rhs in every fluid cell. Otherwise nothing changes. Per-texel; decided on the GPU so
// the fixed-count mode needs no read-back.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) uniform writeonly image3D u_pressure;
layout(r32f, binding = 1) uniform writeonly image3D u_r;
layout(r32f, binding = 2) readonly uniform image3D u_rhs;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(std430, binding = 1) readonly buffer Results { vec4 results[]; };

uniform uint u_slot;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  vec4 start = results[u_slot];
  if (!(start.z > start.w)) return;  // the warm start is no worse than p = 0
  if ((imageLoad(u_nbmask, c).r & NB_SOLID) != 0u) return;
  imageStore(u_pressure, c, vec4(0.0));
  imageStore(u_r, c, vec4(-imageLoad(u_rhs, c).r));
}
