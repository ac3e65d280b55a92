// SPDX-License-Identifier: GPL-3.0-or-later
// Undoes cpu/kernel_begin.h after a kernel file's shaders.
#undef HF_IMAGE
#undef IMAGE_RW
#undef IMAGE_RO
#undef IMAGE_WO
#undef UIMAGE_RW
#undef UIMAGE_RO
#undef UIMAGE_WO
#undef BUFFER_RW
#undef BUFFER_RO
#undef BUFFER_WO
#undef UNIFORM
#undef LOCAL_SIZE
#undef CONST
#undef UNROLL
#undef OUT
#undef INOUT
#undef main
#undef gl_GlobalInvocationID
#undef gl_LocalInvocationID
#undef gl_WorkGroupID
#undef gl_NumWorkGroups
#undef gl_LocalInvocationIndex
#undef writeGroupSumAt
#undef writeGroupSum
#undef shared
#undef HF_CPU
