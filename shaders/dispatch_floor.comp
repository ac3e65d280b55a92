// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "dispatch_floor" (benchmark only, gl/dispatch_floor.h): what a per-cell dispatch costs
// this device before a stage does any work. One invocation per cell of u_res, in the cell
// stages' workgroup shape. Without STORE the body stores nothing (its condition is never true,
// but the compiler cannot know it): the cost of launching the invocations. With STORE each
// cell's invocation writes one R32F texel: the cost of a stage's one mandatory output.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_WO(r32f, 0, u_out);

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
#ifdef STORE
  if (!inGrid(c)) return;
  imageStore(u_out, c, vec4(1.0f));
#else
  if (c.x < 0) imageStore(u_out, c, vec4(1.0f));
#endif
}
