// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "pcg_direction": the next search direction s = z + beta s, beta = (r.z)_new / (r.z)_old
// from the reduction results; per-texel update, 0 in solids. (The first direction is z itself:
// PressureMultigrid swaps the two textures instead of copying.)
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RW(r32f, 0, u_s);
IMAGE_RO(r32f, 1, u_z);
UIMAGE_RO(r8ui, 2, u_nbmask);
BUFFER_RO(Results, vec4, 1, results);

UNIFORM(uint, u_slot_new);  // results[u_slot_new].x = r.z of this iteration
UNIFORM(uint, u_slot_old);  // results[u_slot_old].x = r.z of the previous one

// beta from the reduction results: 0 where the old r.z is not positive.
float directionBeta() {
  float old_rz = results[u_slot_old].x;
  return old_rz <= 0.0f ? 0.0f : results[u_slot_new].x / old_rz;
}

// A cell's new direction z + beta s from its mask m, z and s: 0 in a solid cell. Branch-free (the
// mask selects), so the CPU's row loop vectorizes it (with beta taken once a row).
float newDirection(uint m, float z, float s, float beta) { return (m & NB_SOLID) != 0u ? 0.0f : z + beta * s; }

void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  float s = newDirection(imageLoad(u_nbmask, c).x, imageLoad(u_z, c).x, imageLoad(u_s, c).x, directionBeta());
  imageStore(u_s, c, vec4(s));
}
