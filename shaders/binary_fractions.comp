// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "binary_fractions": face fractions (common.glsl) of a voxelized body: a face is open (1)
// when no cell beside it is solid, else covered (0). Used for bodies without cut cells (the
// mesh probe) and for no body, so every stage reads one face-fraction image.
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

UIMAGE_RO(r8ui, 1, u_solid);
IMAGE_WO(rgba32f, 0, u_face_open);

UNIFORM(ivec3, u_origin);  // first face texel of the region dispatched (StepPipeline: the probe's move)

bool solidAt(ivec3 c) { return inGrid(c) && imageLoad(u_solid, c).x != 0u; }

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID) + u_origin;
  if (any(greaterThan(idx, u_res))) return;
  vec4 w = vec4(1.0f);
  UNROLL for (int a = 0; a < 3; ++a) {
    w[a] = (solidAt(idx) || solidAt(idx - unitAxis(a))) ? 0.0f : 1.0f;
  }
  imageStore(u_face_open, idx, w);
}
