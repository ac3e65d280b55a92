// Stage "apply_forces": adds dt times the body acceleration, averaged from the two cells that
// share each face, to all three velocity components in one pass (per-texel read-modify-write).
// One invocation per point of the (nx+1, ny+1, nz+1) lattice updates the x, y and z faces with
// that index where they exist; the cell at the index (clamped) is the high side of all three,
// so its force is loaded once. The same sums as one pass per component: identical results.
layout(local_size_x = WG_X, local_size_y = WG_Y, local_size_z = WG_Z) in;

layout(rgba32f, binding = 1) readonly uniform image3D u_force;
layout(r32f, binding = 0) uniform image3D u_vel_x;
layout(r32f, binding = 2) uniform image3D u_vel_y;
layout(r32f, binding = 3) uniform image3D u_vel_z;

uniform float u_dt;    // s

bool isFace(ivec3 idx, int axis) { return all(lessThan(idx, faceSize(axis))); }

float faceAccel(ivec3 idx, int axis, vec4 f_hi) {
  return 0.5 * (imageLoad(u_force, clampCell(idx - unitAxis(axis)))[axis] + f_hi[axis]);
}

void main() {
  ivec3 idx = ivec3(gl_GlobalInvocationID);
  bool fx = isFace(idx, 0), fy = isFace(idx, 1), fz = isFace(idx, 2);
  if (!(fx || fy || fz)) return;
  vec4 f_hi = imageLoad(u_force, clampCell(idx));
  if (fx) imageStore(u_vel_x, idx, vec4(imageLoad(u_vel_x, idx).r + u_dt * faceAccel(idx, 0, f_hi)));
  if (fy) imageStore(u_vel_y, idx, vec4(imageLoad(u_vel_y, idx).r + u_dt * faceAccel(idx, 1, f_hi)));
  if (fz) imageStore(u_vel_z, idx, vec4(imageLoad(u_vel_z, idx).r + u_dt * faceAccel(idx, 2, f_hi)));
}
