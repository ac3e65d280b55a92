// Stage "pcg_apply": q = A s (the operator of pcg_init.comp) and, per workgroup, s.q into
// partials[]. 0 in solid cells.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 1) readonly uniform image3D u_s;
layout(r8ui, binding = 3) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 0) uniform writeonly image3D u_q;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  vec4 mine = vec4(0.0);
  if (inGrid(c)) {
    uint m = imageLoad(u_nbmask, c).r;
    float q = 0.0;
    if ((m & NB_SOLID) == 0u) {
      float s = imageLoad(u_s, c).r;
      q = (m & NB_OPEN_TOP) != 0u ? s : 0.0;
      for (int d = 0; d < 6; ++d) {
        if (((m >> uint(d)) & 1u) != 0u) q += s - imageLoad(u_s, c + NEIGHBOUR[d]).r;
      }
      mine = vec4(s * q, 0.0, 0.0, 0.0);
    }
    imageStore(u_q, c, vec4(q));
  }
  writeGroupSum(mine);
}
