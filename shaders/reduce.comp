// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "reduce": one workgroup sums u_count vec4 partials, from partials[u_first], into results[u_slot]
// (the second level of the parallel reductions of force and residual).
LOCAL_SIZE(REDUCE_SIZE, 1, 1);

BUFFER_RO(Partials, vec4, 0, partials);
BUFFER_RW(Results, vec4, 1, results);

UNIFORM(uint, u_count);
UNIFORM(uint, u_slot);
UNIFORM(uint, u_first);

shared vec4 s_sum[REDUCE_SIZE];

// Invocation `lane`'s share: every REDUCE_SIZE-th partial from its own.
vec4 laneSum(uint lane) {
  vec4 acc = vec4(0.0f);
  for (uint i = lane; i < u_count; i += uint(REDUCE_SIZE)) acc += partials[u_first + i];
  return acc;
}

// Then a tree over the lanes (the CPU's runner, cpu/kernels/reduce.cpp, adds in the same order).
void main() {
  s_sum[gl_LocalInvocationIndex] = laneSum(gl_LocalInvocationIndex);
  barrier();
  for (uint stride = uint(REDUCE_SIZE) / 2u; stride > 0u; stride >>= 1u) {
    if (gl_LocalInvocationIndex < stride) {
      s_sum[gl_LocalInvocationIndex] += s_sum[gl_LocalInvocationIndex + stride];
    }
    barrier();
  }
  if (gl_LocalInvocationIndex == 0u) results[u_slot] = s_sum[0];
}
