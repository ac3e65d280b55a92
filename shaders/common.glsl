// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by every stage; prepended after the #version line and the stage's #defines, and
// included by the C++ kernels (cpu/glsl.h, which defines HF_CPU and its own versions of the
// declaration macros below: the GLSL/C++ common subset is described there).
// Grid units: cell (i,j,k) spans [i,i+1]x[j,j+1]x[k,k+1]; its centre is at (i,j,k)+0.5.
// Staggered (MAC) velocity: u lives on x-faces, (nx+1,ny,nz) texels at offset (0,.5,.5);
// v on y-faces, offset (.5,0,.5); w on z-faces, offset (.5,.5,0). Scalars sit at (.5,.5,.5).

#ifndef HF_CPU
// The declaration macros of the GLSL/C++ common subset (cpu/glsl.h defines the C++ side): images
// by format and access, std430 storage buffers, uniforms and the workgroup shape.
#define IMAGE_RW(fmt, unit, name) layout(fmt, binding = unit) uniform image3D name
#define IMAGE_RO(fmt, unit, name) layout(fmt, binding = unit) readonly uniform image3D name
#define IMAGE_WO(fmt, unit, name) layout(fmt, binding = unit) writeonly uniform image3D name
#define UIMAGE_RW(fmt, unit, name) layout(fmt, binding = unit) uniform uimage3D name
#define UIMAGE_RO(fmt, unit, name) layout(fmt, binding = unit) readonly uniform uimage3D name
#define UIMAGE_WO(fmt, unit, name) layout(fmt, binding = unit) writeonly uniform uimage3D name
#define BUFFER_RW(block, type, binding_, name) layout(std430, binding = binding_) buffer block { type name[]; }
#define BUFFER_RO(block, type, binding_, name) layout(std430, binding = binding_) readonly buffer block { type name[]; }
#define BUFFER_WO(block, type, binding_, name) layout(std430, binding = binding_) writeonly buffer block { type name[]; }
#define UNIFORM(type, name) uniform type name
#define LOCAL_SIZE(x, y, z) layout(local_size_x = x, local_size_y = y, local_size_z = z) in
#define CONST const  // a constant at file scope (C++: static constexpr)
#define UNROLL       // a short loop of constant count (C++: unrolled, so its index folds)
#define OUT(T) out T  // an out parameter (C++: a reference)
#define INOUT(T) inout T  // an in-out parameter (C++: a reference)
#define INLINE  // a small function a C++ row loop calls from several places (C++: always inlined)
#endif

// Cell classes of the seed paper (values shared with cpp/obstacle/cell_class.h).
CONST uint CELL_OUTSIDE = 0u;      // fluid, no solid neighbour
CONST uint CELL_SURROUNDING = 1u;  // fluid next to a boundary cell
CONST uint CELL_BOUNDARY = 2u;     // solid with at least one fluid neighbour
CONST uint CELL_INSIDE = 3u;       // solid, all neighbours solid

// Bits of the per-cell neighbour mask written by classify.comp.
// Bit d (0..5, order -x,+x,-y,+y,-z,+z): that neighbour is a fluid cell inside the grid.
// Bit 6: the +z neighbour is the open top (a Dirichlet ghost with pressure 0).
// Bit 7: this cell is solid.
CONST uint NB_OPEN_TOP = 64u;
CONST uint NB_SOLID = 128u;

// Cut cells (Batty, Bertails & Bridson 2007): the open (fluid) fraction of every MAC face, 1 =
// fluid, 0 = covered by a solid, in an RGBA32F image of (nx+1, ny+1, nz+1) texels: texel (i,j,k)
// holds in .x/.y/.z the fraction of the x-, y- and z-face with index (i,j,k). Stages that use
// it bind it at image unit FACE_OPEN_UNIT.
#define FACE_OPEN_UNIT 6
// Open fraction of face d (NEIGHBOUR order) of cell c, read from the face-fraction image `img`.
#define FACE_OPEN(img, c, d) imageLoad(img, ((d) & 1) != 0 ? (c) + unitAxis((d) >> 1) : (c))[(d) >> 1]
// All six of cell c's open fractions (NEIGHBOUR order) into float w[6], from the four texels that
// hold them: six FACE_OPENs load six texels, three of them the same (the pressure stages' loops).
#define FACE_OPEN_ALL(img, c, w)                   \
  {                                                \
    vec4 low_ = imageLoad(img, c);                 \
    w[0] = low_.x;                                 \
    w[1] = imageLoad(img, (c) + ivec3(1, 0, 0)).x; \
    w[2] = low_.y;                                 \
    w[3] = imageLoad(img, (c) + ivec3(0, 1, 0)).y; \
    w[4] = low_.z;                                 \
    w[5] = imageLoad(img, (c) + ivec3(0, 0, 1)).z; \
  }

// A computed open fraction with fractions under `min_open` taken to 0 continuously: w for
// w >= 2 min_open, 2 (w - min_open) between, 0 below (a nearly covered face would make its cell's
// pressure row nearly singular; a hard cut-off would make the fraction jump as the body moves).
float cutOffOpen(float w, float min_open) {
  if (w >= 2.0f * min_open) return min(w, 1.0f);
  return max(2.0f * (w - min_open), 0.0f);
}

CONST ivec3 NEIGHBOUR[6] = {ivec3(-1, 0, 0), ivec3(1, 0, 0), ivec3(0, -1, 0),
                            ivec3(0, 1, 0), ivec3(0, 0, -1), ivec3(0, 0, 1)};

UNIFORM(ivec3, u_res);  // cells per axis

bool inGrid(ivec3 c) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, u_res)); }

// Cell c clamped into the grid. A CPU kernel file may also build a stage with HF_CLAMP_FREE for
// the cells whose every neighbour is in the grid, where the clamp changes nothing: its loads are
// then contiguous along a row (cpu/kernel.h, InteriorSimdRowRunner).
#ifdef HF_CLAMP_FREE
ivec3 clampCell(ivec3 c) { return c; }
int clampCellIndex(int i, int /*axis*/) { return i; }
#else
ivec3 clampCell(ivec3 c) { return clamp(c, ivec3(0), u_res - 1); }
// Cell index i on one axis clamped into the grid (clampCell for one component).
int clampCellIndex(int i, int axis) { return clamp(i, 0, u_res[axis] - 1); }
#endif

// Cell c's open fractions as two vectors (the branch-free stages' FACE_OPEN_ALL): W_LO of its
// -x, -y, -z faces, W_HI of its +x, +y, +z faces, declared here.
#define FACE_OPEN_LO_HI(img, c, W_LO, W_HI)                                                \
  vec3 W_LO = vec3(imageLoad(img, c));                                                     \
  vec3 W_HI = vec3(imageLoad(img, (c) + ivec3(1, 0, 0)).x, imageLoad(img, (c) + ivec3(0, 1, 0)).y, \
                   imageLoad(img, (c) + ivec3(0, 0, 1)).z)
// Cell c's six neighbours' values in image img: LO across its -x, -y, -z faces, HI across its +x,
// +y, +z faces, declared here.
#define NEIGHBOURS_LO_HI(img, c, LO, HI)                                                              \
  vec3 LO = vec3(imageLoad(img, (c) - ivec3(1, 0, 0)).x, imageLoad(img, (c) - ivec3(0, 1, 0)).x,       \
                 imageLoad(img, (c) - ivec3(0, 0, 1)).x);                                              \
  vec3 HI = vec3(imageLoad(img, (c) + ivec3(1, 0, 0)).x, imageLoad(img, (c) + ivec3(0, 1, 0)).x,       \
                 imageLoad(img, (c) + ivec3(0, 0, 1)).x)

// A face's part of a sum: v where mask m links face d, else 0.
float linkedPart(uint m, int d, float v) { return ((m >> uint(d)) & 1u) != 0u ? v : 0.0f; }

// The pressure operator at one cell, (A x)_c: the open top's w x plus, over the linked faces in
// NEIGHBOUR order, w (x - x_nb) (differences, not n x - sum: exact near 0); w a face's open
// fraction. From the cell's loaded neighbourhood: m its mask, w_lo and w_hi its faces' fractions
// (FACE_OPEN_LO_HI), x its value, x_lo and x_hi its neighbours' (NEIGHBOURS_LO_HI; any value
// where m has no link: it is not used). Branch-free, so the CPU's row loops vectorize it (the
// same arithmetic as skipping the unlinked faces: adding 0 is exact).
float operatorAt(uint m, vec3 w_lo, vec3 w_hi, float x, vec3 x_lo, vec3 x_hi) {
  float ax = (m & NB_OPEN_TOP) != 0u ? w_hi.z * x : 0.0f;
  ax += linkedPart(m, 0, w_lo.x * (x - x_lo.x));
  ax += linkedPart(m, 1, w_hi.x * (x - x_hi.x));
  ax += linkedPart(m, 2, w_lo.y * (x - x_lo.y));
  ax += linkedPart(m, 3, w_hi.y * (x - x_hi.y));
  ax += linkedPart(m, 4, w_lo.z * (x - x_lo.z));
  ax += linkedPart(m, 5, w_hi.z * (x - x_hi.z));
  return ax;
}

// b - A x at one cell (operatorAt), 0 in a solid cell.
float residualAt(uint m, vec3 w_lo, vec3 w_hi, float x, vec3 x_lo, vec3 x_hi, float b) {
  return (m & NB_SOLID) != 0u ? 0.0f : b - operatorAt(m, w_lo, w_hi, x, x_lo, x_hi);
}

// Trilinear interpolation of image IMG (SIZE texels) at texel-space position t (texel centres
// at integer t), clamped to the edge: the value texture() gives with GL_LINEAR and
// GL_CLAMP_TO_EDGE, but with full-precision weights (hardware filtering uses 8-bit ones), so
// every back-trace (advect.comp, maccormack.comp) gives the same point on every device.
// In three pieces, so that the CPU can fetch the eight corners its own way (cpu/kernels/
// advect.cpp: a block of texels from one window of rows) around the same arithmetic: the corner
// below t (i0), t's fractions past it (f), and the blend of the corners c<x><y><z> (0: at i0,
// 1: at i0 + 1, clamped to the edge).
INLINE ivec3 trilinearCorner(ivec3 size, vec3 t) { return ivec3(clamp(t, vec3(0.0f), vec3(size - 1))); }
INLINE vec3 trilinearFraction(ivec3 size, vec3 t) {
  vec3 c = clamp(t, vec3(0.0f), vec3(size - 1));
  return c - vec3(ivec3(c));
}
INLINE float trilinearBlend(float c000, float c100, float c010, float c110, float c001, float c101, float c011,
                            float c111, vec3 f) {
  return mix(mix(mix(c000, c100, f.x), mix(c010, c110, f.x), f.y), mix(mix(c001, c101, f.x), mix(c011, c111, f.x), f.y),
             f.z);
}
// A macro, because an image passed as a function argument loses its format.
#define DEFINE_TRILINEAR(NAME, IMG)                                                                 \
  INLINE float NAME(ivec3 size, vec3 t) {                                                                  \
    ivec3 i0 = trilinearCorner(size, t);                                                            \
    ivec3 i1 = min(i0 + 1, size - 1);                                                               \
    return trilinearBlend(imageLoad(IMG, i0).x, imageLoad(IMG, ivec3(i1.x, i0.y, i0.z)).x,          \
                          imageLoad(IMG, ivec3(i0.x, i1.y, i0.z)).x, imageLoad(IMG, ivec3(i1.x, i1.y, i0.z)).x, \
                          imageLoad(IMG, ivec3(i0.x, i0.y, i1.z)).x, imageLoad(IMG, ivec3(i1.x, i0.y, i1.z)).x, \
                          imageLoad(IMG, ivec3(i0.x, i1.y, i1.z)).x, imageLoad(IMG, i1).x,                      \
                          trilinearFraction(size, t));                                              \
  }

// Defines velocityAt(vec3 X): the trilinear velocity (m/s) at grid-unit position X from the
// staggered images VX, VY, VZ (face fields of faceSize(axis) texels at faceOffset(axis)).
#define DEFINE_VELOCITY_AT(VX, VY, VZ)                                                     \
  DEFINE_TRILINEAR(sampleVx, VX)                                                          \
  DEFINE_TRILINEAR(sampleVy, VY)                                                          \
  DEFINE_TRILINEAR(sampleVz, VZ)                                                          \
  vec3 velocityAt(vec3 X) {                                                               \
    return vec3(sampleVx(faceSize(0), X - faceOffset(0)), sampleVy(faceSize(1), X - faceOffset(1)), \
                sampleVz(faceSize(2), X - faceOffset(2)));                                \
  }

// Texel offset of face component `axis` (0=u, 1=v, 2=w).
// Branch-free (selects, no indexing by a variable), so the CPU's row loops vectorize around them.
ivec3 unitAxis(int axis) { return ivec3(axis == 0 ? 1 : 0, axis == 1 ? 1 : 0, axis == 2 ? 1 : 0); }

// Component `axis` (0..2) of a vector.
float component(vec4 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }
int component(ivec3 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

vec3 faceOffset(int axis) { return vec3(0.5f) - 0.5f * vec3(unitAxis(axis)); }

ivec3 faceSize(int axis) { return u_res + unitAxis(axis); }

// The pressure's row stages (pcg_init, pcg_apply, pcg_dot, pcg_update, pcg_predict,
// pressure_sum) sum their row's cells in ROW_PARTS interleaved parts: cell i into part
// i % ROW_PARTS, each part in the row's order, then the parts in a fixed tree (rowPartsTotal). Both
// backends add in this order; the CPU, which has the cells' terms in row buffers there, adds a
// block of ROW_PARTS cells with one vector add where a sum in the row's order was a chain of
// dependent adds, one a cell (cpu/kernels/pressure_row.h, addRowParts).
CONST int ROW_PARTS = 8;

vec4 rowPartsTotal(vec4 p[ROW_PARTS]) {
  return ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
}

// The mean over the fluid cells of a reduced (sum, fluid cells, ...) result (pressure_sum's,
// pcg_init's), 0 with no fluid cell: what a closed box's mean removal takes away (pressure_shift,
// and pcg_predict for the starting residual: the same bits either way).
float meanOverFluid(vec4 sums) { return sums.y > 0.0f ? sums.x / sums.y : 0.0f; }

#if defined(GROUP_SUM) && !defined(HF_CPU)  // C++: cpu/glsl.h sums a workgroup in order
// First level of a parallel reduction: every invocation of a workgroup calls writeGroupSum with
// its value; the workgroup's sum lands in partials[workgroup index] for reduce.comp.
layout(std430, binding = 0) writeonly buffer Partials { vec4 partials[]; };
CONST uint GROUP = uint(WG_X * WG_Y * WG_Z);  // a power of two
shared vec4 s_sum[GROUP];

// Stages that reduce several vec4s call writeGroupSumAt(value, part) once per part, in the same
// order in every invocation; part p of the workgroup lands in partials[p * groups + group].
void writeGroupSumAt(vec4 mine, uint part) {
  barrier();  // the previous part's s_sum[0] has been read
  s_sum[gl_LocalInvocationIndex] = mine;
  barrier();
  for (uint stride = GROUP / 2u; stride > 0u; stride >>= 1u) {
    if (gl_LocalInvocationIndex < stride) s_sum[gl_LocalInvocationIndex] += s_sum[gl_LocalInvocationIndex + stride];
    barrier();
  }
  if (gl_LocalInvocationIndex == 0u) {
    uint group = gl_WorkGroupID.x + gl_NumWorkGroups.x * (gl_WorkGroupID.y + gl_NumWorkGroups.y * gl_WorkGroupID.z);
    uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y * gl_NumWorkGroups.z;
    partials[part * groups + group] = s_sum[0];
  }
}

void writeGroupSum(vec4 mine) { writeGroupSumAt(mine, 0u); }
#endif
