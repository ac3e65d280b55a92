// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "dispatch_floor" (benchmark only, gl/dispatch_floor.h): what a per-cell dispatch costs
// this device before a stage does any work. One invocation per cell of u_res, in the cell
// stages' workgroup shape. Without STORE the body stores nothing (its condition is never true,
// but the compiler cannot know it): the cost of launching the invocations. With STORE each
// cell's invocation writes one R32F texel: the cost of a stage's one mandatory output.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 0) writeonly uniform image3D u_out;

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
#ifdef STORE
  if (!inGrid(c)) return;
  imageStore(u_out, c, vec4(1.0));
#else
  if (c.x < 0) imageStore(u_out, c, vec4(1.0));
#endif
}
