// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "reduce": one workgroup sums u_count vec4 partials, from partials[u_first], into results[u_slot]
// (the second level of the parallel reductions of force and residual).
layout(local_size_x = REDUCE_SIZE) in;

layout(std430, binding = 0) readonly buffer Partials { vec4 partials[]; };
layout(std430, binding = 1) buffer Results { vec4 results[]; };

uniform uint u_count;
uniform uint u_slot;
uniform uint u_first;

shared vec4 s_sum[REDUCE_SIZE];

void main() {
  vec4 acc = vec4(0.0);
  for (uint i = gl_LocalInvocationIndex; i < u_count; i += uint(REDUCE_SIZE)) acc += partials[u_first + i];
  s_sum[gl_LocalInvocationIndex] = acc;
  barrier();
  for (uint stride = uint(REDUCE_SIZE) / 2u; stride > 0u; stride >>= 1u) {
    if (gl_LocalInvocationIndex < stride) {
      s_sum[gl_LocalInvocationIndex] += s_sum[gl_LocalInvocationIndex + stride];
    }
    barrier();
  }
  if (gl_LocalInvocationIndex == 0u) results[u_slot] = s_sum[0];
}
