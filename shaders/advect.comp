// SPDX-License-Identifier: GPL-3.0-or-later
// Stage "advect": semi-Lagrangian transport through the velocity field, with a second-order
// (midpoint) back-trace. Also the forward and backward passes of MacCormack (u_dt_over_h < 0
// for the backward one).
// Variants (#defines): FIELD_AT 0, 1, 2 transports the velocity component on the faces of that
// axis; FIELD_AT 3 a scalar at cell centres; with PAIR, two scalars (smoke and heat) share one
// back-trace. The first velocity of the back-trace is taken at the field's own sample point,
// where it is an average of 1, 2 or 4 texels per component instead of a full trilinear lookup.
// Trilinear interpolation is done from imageLoad()s rather than by texture(): on llvmpipe the
// eight loads and seven lerps cost less than one filtered texture().
LOCAL_SIZE(WG_X, WG_Y, WG_Z);

IMAGE_RO(r32f, 2, u_vel_x);
IMAGE_RO(r32f, 3, u_vel_y);
IMAGE_RO(r32f, 4, u_vel_z);
IMAGE_RO(r32f, 5, u_src);
UIMAGE_RO(r8ui, 1, u_nbmask);
IMAGE_WO(r32f, 0, u_dst);
#ifdef PAIR
IMAGE_RO(r32f, 6, u_src2);
IMAGE_WO(r32f, 7, u_dst2);
UNIFORM(float, u_decay2);       // multiplier applied to the second result
#endif

UNIFORM(ivec3, u_field_size);   // texels of this field
UNIFORM(vec3, u_field_offset);  // grid-unit offset of texel (0,0,0)
UNIFORM(float, u_dt_over_h);    // time step / cell size (s/m); negative traces forward
UNIFORM(float, u_decay);        // multiplier applied to the result (dissipation), 1 for none
UNIFORM(int, u_zero_in_solid);  // 1: cells covered by the solid get 0 (scalars only)

DEFINE_VELOCITY_AT(u_vel_x, u_vel_y, u_vel_z)  // velocityAt(X), common.glsl
DEFINE_TRILINEAR(sampleSrc, u_src)
#ifdef PAIR
DEFINE_TRILINEAR(sampleSrc2, u_src2)
#endif

#if FIELD_AT == 3
// Velocity at the centre of cell idx: each component is the mean of the cell's two faces.
vec3 velocityHere(ivec3 idx) {
  return 0.5f * vec3(imageLoad(u_vel_x, idx).x + imageLoad(u_vel_x, idx + ivec3(1, 0, 0)).x,
                    imageLoad(u_vel_y, idx).x + imageLoad(u_vel_y, idx + ivec3(0, 1, 0)).x,
                    imageLoad(u_vel_z, idx).x + imageLoad(u_vel_z, idx + ivec3(0, 0, 1)).x);
}
#else
// Component B (on B-faces) at the point of A-face idx (A = FIELD_AT): the mean of the four
// B-faces around it, two along A (the cells either side of the face, clamped to the grid like
// the trilinear lookup) and two along B. Equal to velocityAt() there.
#define DEFINE_CROSS_MEAN(NAME, IMG, B)                                                    \
  float NAME(ivec3 idx) {                                                                  \
    ivec3 lo = idx;                                                                        \
    lo[FIELD_AT] = clampCellIndex(idx[FIELD_AT] - 1, FIELD_AT);                            \
    ivec3 hi = idx;                                                                        \
    hi[FIELD_AT] = clampCellIndex(idx[FIELD_AT], FIELD_AT);                                \
    ivec3 e = ivec3(0);                                                                    \
    e[B] = 1;                                                                              \
    return 0.25f * (imageLoad(IMG, lo).x + imageLoad(IMG, hi).x + imageLoad(IMG, lo + e).x + \
                   imageLoad(IMG, hi + e).x);                                              \
  }
#if FIELD_AT == 0
DEFINE_CROSS_MEAN(crossY, u_vel_y, 1)
DEFINE_CROSS_MEAN(crossZ, u_vel_z, 2)
vec3 velocityHere(ivec3 idx) { return vec3(imageLoad(u_vel_x, idx).x, crossY(idx), crossZ(idx)); }
#elif FIELD_AT == 1
DEFINE_CROSS_MEAN(crossX, u_vel_x, 0)
DEFINE_CROSS_MEAN(crossZ, u_vel_z, 2)
vec3 velocityHere(ivec3 idx) { return vec3(crossX(idx), imageLoad(u_vel_y, idx).x, crossZ(idx)); }
#else
DEFINE_CROSS_MEAN(crossX, u_vel_x, 0)
DEFINE_CROSS_MEAN(crossY, u_vel_y, 1)
vec3 velocityHere(ivec3 idx) { return vec3(crossX(idx), crossY(idx), imageLoad(u_vel_z, idx).x); }
#endif
#endif

// Texel idx's point in grid units.
vec3 fieldPoint(ivec3 idx) { return vec3(idx) + u_field_offset; }

// The back-trace in pieces, so that the CPU can run the lookups between them its own way
// (cpu/kernels/advect.cpp): its midpoint, half a step back along the velocity here; its foot,
// a step back along velocityAt(midpoint), in the field's texel space; the new value(s) from the
// field(s) sampled at the foot (.y: the second field's, with PAIR).
vec3 traceMid(ivec3 idx) { return fieldPoint(idx) - 0.5f * u_dt_over_h * velocityHere(idx); }

vec3 traceFootFrom(ivec3 idx, vec3 mid_velocity) {
  vec3 back = fieldPoint(idx) - u_dt_over_h * mid_velocity;
  back = clamp(back, vec3(0.0f), vec3(u_res));
  return back - u_field_offset;
}

// Times the decay; 0 in a solid cell where u_zero_in_solid.
vec2 finishedValues(ivec3 idx, vec2 sampled) {
  vec2 v = vec2(sampled.x * u_decay, 0.0f);
#ifdef PAIR
  v.y = sampled.y * u_decay2;
#endif
  bool solid = (imageLoad(u_nbmask, idx).x & NB_SOLID) != 0u;  // read always: no branch around a load
  return (u_zero_in_solid != 0 && solid) ? vec2(0.0f) : v;
}

// Texel idx's new value(s): the field(s) at the foot of its back-trace, finished. Branch-free, so
// the CPU's row loop vectorizes it.
vec2 advectedValues(ivec3 idx) {
  vec3 t = traceFootFrom(idx, velocityAt(traceMid(idx)));
  vec2 sampled = vec2(sampleSrc(u_field_size, t), 0.0f);
#ifdef PAIR
  sampled.y = sampleSrc2(u_field_size, t);
#endif
  return finishedValues(idx, sampled);
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, u_field_size))) return;
  vec2 v = advectedValues(idx);
  imageStore(u_dst, idx, vec4(v.x));
#ifdef PAIR
  imageStore(u_dst2, idx, vec4(v.y));
#endif
}
