// Stage "advect": semi-Lagrangian transport of one field (a velocity component or a scalar)
// through the velocity field, with a second-order (midpoint) back-trace.
// Also the forward and backward passes of MacCormack (u_dt_over_h < 0 for the backward one).
// Trilinear interpolation is done here from imageLoad()s rather than by texture(): on llvmpipe
// the eight loads and seven lerps cost less than one filtered texture().
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(r32f, binding = 2) readonly uniform image3D u_vel_x;
layout(r32f, binding = 3) readonly uniform image3D u_vel_y;
layout(r32f, binding = 4) readonly uniform image3D u_vel_z;
layout(r32f, binding = 5) readonly uniform image3D u_src;
layout(r8ui, binding = 1) readonly uniform uimage3D u_nbmask;
layout(r32f, binding = 0) uniform writeonly image3D u_dst;

uniform ivec3 u_field_size;   // texels of this field
uniform vec3 u_field_offset;  // grid-unit offset of texel (0,0,0)
uniform float u_dt_over_h;    // time step / cell size (s/m); negative traces forward
uniform float u_decay;        // multiplier applied to the result (dissipation), 1 for none
uniform int u_zero_in_solid;  // 1: cells covered by the solid get 0 (scalars only)

// Trilinear interpolation of image IMG (SIZE texels) at texel-space position t (texel centres
// at integer t), clamped to the edge: the value texture() gives with GL_LINEAR and
// GL_CLAMP_TO_EDGE. A macro, because an image passed as a function argument loses its format.
#define DEFINE_TRILINEAR(NAME, IMG)                                                        \
  float NAME(ivec3 size, vec3 t) {                                                         \
    t = clamp(t, vec3(0.0), vec3(size - 1));                                               \
    ivec3 i0 = ivec3(t);                                                                   \
    vec3 f = t - vec3(i0);                                                                 \
    ivec3 i1 = min(i0 + 1, size - 1);                                                      \
    float c00 = mix(imageLoad(IMG, i0).r, imageLoad(IMG, ivec3(i1.x, i0.y, i0.z)).r, f.x); \
    float c10 = mix(imageLoad(IMG, ivec3(i0.x, i1.y, i0.z)).r,                             \
                    imageLoad(IMG, ivec3(i1.x, i1.y, i0.z)).r, f.x);                       \
    float c01 = mix(imageLoad(IMG, ivec3(i0.x, i0.y, i1.z)).r,                             \
                    imageLoad(IMG, ivec3(i1.x, i0.y, i1.z)).r, f.x);                       \
    float c11 = mix(imageLoad(IMG, ivec3(i0.x, i1.y, i1.z)).r, imageLoad(IMG, i1).r, f.x); \
    return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);                               \
  }

DEFINE_TRILINEAR(sampleVx, u_vel_x)
DEFINE_TRILINEAR(sampleVy, u_vel_y)
DEFINE_TRILINEAR(sampleVz, u_vel_z)
DEFINE_TRILINEAR(sampleSrc, u_src)

// Velocity (m/s) at grid-unit position X; face fields sit at offsets (0,.5,.5), (.5,0,.5), (.5,.5,0).
vec3 velocityAt(vec3 X) {
  return vec3(sampleVx(u_res + ivec3(1, 0, 0), X - vec3(0.0, 0.5, 0.5)),
              sampleVy(u_res + ivec3(0, 1, 0), X - vec3(0.5, 0.0, 0.5)),
              sampleVz(u_res + ivec3(0, 0, 1), X - vec3(0.5, 0.5, 0.0)));
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(idx, u_field_size))) return;
  if (u_zero_in_solid != 0 && (imageLoad(u_nbmask, idx).r & NB_SOLID) != 0u) {
    imageStore(u_dst, idx, vec4(0.0));
    return;
  }
  vec3 X = vec3(idx) + u_field_offset;
  vec3 mid = X - 0.5 * u_dt_over_h * velocityAt(X);
  vec3 back = X - u_dt_over_h * velocityAt(mid);
  back = clamp(back, vec3(0.0), vec3(u_res));
  float value = sampleSrc(u_field_size, back - u_field_offset);
  imageStore(u_dst, idx, vec4(value * u_decay));
}
