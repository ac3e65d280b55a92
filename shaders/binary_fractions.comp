// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "binary_fractions": face fractions (common.glsl) of a voxelized body: a face is open (1)
// when no cell beside it is solid, else covered (0). Used for bodies without cut cells (the
// mesh probe) and for no body, so every stage reads one face-fraction image.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r8ui, binding = 1) readonly uniform uimage3D u_solid;
layout(rgba32f, binding = 0) uniform writeonly image3D u_face_open;

uniform ivec3 u_origin;  // first face texel of the region dispatched (StepPipeline: the probe's move)

bool solidAt(ivec3 c) { return inGrid(c) && imageLoad(u_solid, c).r != 0u; }

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID) + u_origin;
  if (any(greaterThan(idx, u_res))) return;
  vec4 w = vec4(1.0);
  for (int a = 0; a < 3; ++a) {
    w[a] = (solidAt(idx) || solidAt(idx - unitAxis(a))) ? 0.0 : 1.0;
  }
  imageStore(u_face_open, idx, w);
}
