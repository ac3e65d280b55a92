// SPDX-License-Identifier: GPL-3.0-or-later
// Included by a kernel file (cpu/kernels/) before the shaders it compiles, and undone by
// cpu/kernel_end.h after them: GLSL's declarations and built-ins as C++ (cpu/glsl.h).
#include "cpu/glsl.h"

// The declaration macros (see the top of this file; GLSL's definitions are in common.glsl).
// HF_IMAGE is the image type of the structs that follow: glsl::Image (bounds-tested, as GL), or
// glsl::UncheckedImage where a kernel file builds the variant its fast runner uses.
#define HF_IMAGE ::hf::cpu::glsl::Image
#define IMAGE_RW(fmt, unit, name) HF_IMAGE<::hf::cpu::glsl::fmt> name{this, unit, #name}
#define IMAGE_RO(fmt, unit, name) IMAGE_RW(fmt, unit, name)
#define IMAGE_WO(fmt, unit, name) IMAGE_RW(fmt, unit, name)
#define UIMAGE_RW(fmt, unit, name) IMAGE_RW(fmt, unit, name)
#define UIMAGE_RO(fmt, unit, name) IMAGE_RW(fmt, unit, name)
#define UIMAGE_WO(fmt, unit, name) IMAGE_RW(fmt, unit, name)
#define BUFFER_RW(block, type, binding, name) ::hf::cpu::glsl::Buffer<type> name{this, binding, #name}
#define BUFFER_RO(block, type, binding, name) BUFFER_RW(block, type, binding, name)
#define BUFFER_WO(block, type, binding, name) BUFFER_RW(block, type, binding, name)
#define UNIFORM(type, name) \
  type name{};              \
  ::hf::cpu::glsl::UniformSlot hf_uniform_##name { this, #name, &name }
#define LOCAL_SIZE(x, y, z) static_assert(true, "")
#define CONST static constexpr
#define UNROLL _Pragma("GCC unroll 8")
#define OUT(T) T&
#define INOUT(T) T&
#define INLINE __attribute__((always_inline))
// main() takes its invocation; the built-ins read from it.
#define main() hf_main(const ::hf::cpu::glsl::Invocation& hf_invocation)
#define gl_GlobalInvocationID (hf_invocation.global_id)
#define gl_LocalInvocationID (hf_invocation.local_id)
#define gl_WorkGroupID (hf_invocation.group_id)
#define gl_NumWorkGroups (hf_invocation.groups)
#define gl_LocalInvocationIndex (hf_invocation.local_index)
#define writeGroupSumAt(value, part) hf_invocation.group->add((value), (part))
#define writeGroupSum(value) writeGroupSumAt(value, 0u)
// A GLSL-only part of a shared file is wrapped in #ifndef HF_CPU.
#define HF_CPU 1
#define shared             // workgroup-shared arrays become members (their kernels run one workgroup at a time)
