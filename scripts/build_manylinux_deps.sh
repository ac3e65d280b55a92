#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Provides the toolchain and static libraries that build the wheels for glibc 2.28
# (manylinux_2_28, blender.org's floor), once per machine, and prints the folder that holds them.
#
#   bash scripts/build_manylinux_deps.sh        # prints PREFIX; builds it first if needed
#
# The compiler is zig's clang (the `ziglang` wheel from PyPI, in a venv of its own) targeting
# x86_64-linux-gnu.2.28: it links against glibc 2.28's symbol versions whatever the host's glibc,
# and links LLVM's libc++ statically, so the module needs no newer libstdc++ either. The
# libraries the engine links (OpenVDB 10.0.1 core, oneTBB 2021.8, Imath 3.1.6, c-blosc 1.21.3
# with lz4 1.9.4 and zlib 1.2.13, libusb 1.0.26) are built from the same Debian 12 source
# packages that Debian's own binaries come from, as static archives with hidden symbols, into
# PREFIX (~/.cache/hapticfluid/manylinux_2_28-<key>): the wheel's `_core` then carries them
# inside itself and exports nothing but PyInit__core (share/module.map), so no copy of TBB or
# OpenVDB in it can meet Blender's own. Header-only pieces come from the host's Debian packages
# (Boost's uuid headers, GLM, EGL/GL/KHR), each linked or copied into PREFIX/include alone: the
# host's /usr/include (glibc 2.36's headers) never reaches the compiler. libglvnd
# (libEGL.so.1, libOpenGL.so.0) stays the user system's, as before.
# OpenVDB is built without explicit template instantiation (only what the engine uses is
# compiled, in its one .cpp) and without delayed loading (no Boost iostreams).
#
# Time: about 5 minutes on 2 cores the first time (nice 19; OpenVDB 2.5 of them), then nothing.
# Exit status: 0 ready; 77 this machine cannot build it (the reason is printed: not x86_64 Linux,
# PyPI or Debian's source archive unreachable, a header package missing); else a build failed
# (log: PREFIX.log).
set -eEuo pipefail
{
ZIG_VERSION=0.14.1
TARGET=x86_64-linux-gnu.2.28
SOURCES=(zlib lz4 c-blosc imath onetbb openvdb libusb-1.0)  # Debian 12 (bookworm) source packages
KEY="zig$ZIG_VERSION-v1"   # bump when a library, an option or this recipe changes
PREFIX="${HF_MANYLINUX_CACHE:-$HOME/.cache/hapticfluid}/manylinux_2_28-$KEY"
LOG="$PREFIX.log"
say() { echo "$*" >&2; }
cannot() { say "SKIP: cannot build the manylinux_2_28 toolchain here: $*"; exit 77; }
source "$(dirname "${BASH_SOURCE[0]}")/package_common.sh"  # hf_pip_offline

if [ -f "$PREFIX/.hf-ok" ]; then echo "$PREFIX"; exit 0; fi
[ "$(uname -s)-$(uname -m)" = Linux-x86_64 ] || cannot "this is $(uname -s)-$(uname -m), not Linux-x86_64"
command -v apt-get >/dev/null || cannot "no apt-get to fetch Debian's source packages"
for h in /usr/include/boost/uuid/uuid.hpp /usr/include/glm/glm.hpp /usr/include/EGL/egl.h /usr/include/GL/gl.h; do
  [ -f "$h" ] || cannot "$h is missing (scripts/common.sh installs libboost-dev, libglm-dev, libegl-dev, libgl-dev)"
done
for l in libEGL.so.1 libOpenGL.so.0; do
  [ -e "/usr/lib/x86_64-linux-gnu/$l" ] || cannot "/usr/lib/x86_64-linux-gnu/$l is missing (libegl1, libopengl0)"
done

t0=$SECONDS
WORK="$PREFIX.work"
# A build that stopped keeps its work folder; HF_MANYLINUX_RESUME=1 goes on from the last library
# built (after a fix to this script), otherwise everything starts again.
if [ "${HF_MANYLINUX_RESUME:-0}" != 1 ] || [ ! -f "$WORK/.sources-ok" ]; then rm -rf "$PREFIX" "$WORK"; fi
mkdir -p "$PREFIX"/{bin,include,lib/cmake/glm,share} "$WORK"
[ -f "$WORK/.sources-ok" ] || : >"$LOG"
say "== manylinux_2_28: zig $ZIG_VERSION and static libraries into $PREFIX (log: $LOG)"

# ---- the compiler ----
if [ ! -x "$PREFIX/zig-venv/bin/python" ]; then
  # scripts/common.sh installs python3-venv: a venv that fails is a failure, not a skip.
  /usr/bin/python3 -m venv "$PREFIX/zig-venv" >>"$LOG" 2>&1 || { say "error: /usr/bin/python3 -m venv failed (log: $LOG)"; exit 1; }
  if ! "$PREFIX/zig-venv/bin/python" -m pip install -q "ziglang==$ZIG_VERSION" >"$LOG.pip" 2>&1; then
    cat "$LOG.pip" >>"$LOG"
    rm -rf "$PREFIX/zig-venv"
    hf_pip_offline "$LOG.pip" && cannot "pip could not reach its package index for ziglang==$ZIG_VERSION (no network)"
    say "error: pip could not install ziglang==$ZIG_VERSION with its index reachable (log: $LOG)"
    exit 1
  fi
fi
ZIG="$("$PREFIX/zig-venv/bin/python" -c 'import ziglang, os; print(os.path.join(os.path.dirname(ziglang.__file__), "zig"))')"
[ -x "$ZIG" ] || { say "error: no zig binary in the ziglang wheel ($ZIG)"; exit 1; }
for tool in cc c++; do
  printf '#!/bin/sh\nexport ZIG_GLOBAL_CACHE_DIR="${ZIG_GLOBAL_CACHE_DIR:-%s}"\nexec "%s" %s -target %s "$@"\n' \
    "$PREFIX/zig-cache" "$ZIG" "$tool" "$TARGET" >"$PREFIX/bin/$tool"
done
for tool in ar ranlib; do printf '#!/bin/sh\nexec "%s" %s "$@"\n' "$ZIG" "$tool" >"$PREFIX/bin/$tool"; done
chmod +x "$PREFIX"/bin/*
# The extension module exports its init function only: every static library inside stays private.
printf '{\n  global: PyInit_*;\n  local: *;\n};\n' >"$PREFIX/share/module.map"
# zig keeps its compiled libc++ and glibc stubs in a cache: the wrappers above use PREFIX's own.

cat >"$PREFIX/share/toolchain.cmake" <<EOF
# CMake toolchain: zig's clang for glibc 2.28 ($TARGET), libraries from $PREFIX only.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(CMAKE_C_COMPILER "$PREFIX/bin/cc")
set(CMAKE_CXX_COMPILER "$PREFIX/bin/c++")
set(CMAKE_AR "$PREFIX/bin/ar" CACHE FILEPATH "")
set(CMAKE_RANLIB "$PREFIX/bin/ranlib" CACHE FILEPATH "")
set(CMAKE_PREFIX_PATH "$PREFIX" \${CMAKE_PREFIX_PATH})
set(CMAKE_FIND_USE_CMAKE_SYSTEM_PATH FALSE)   # never the host's /usr: its glibc headers are 2.36's
set(CMAKE_FIND_USE_SYSTEM_ENVIRONMENT_PATH FALSE)
# Boost 1.74 and OpenVDB 10 predate clang 19 and libc++ 19: their enum casts in constant
# expressions and "template" keywords without argument lists are errors there by default, and
# Boost's hash still derives from std::unary_function (removed from C++17 in libc++ 19).
set(CMAKE_CXX_FLAGS_INIT "-Wno-enum-constexpr-conversion -Wno-missing-template-arg-list-after-template-kw -D_LIBCPP_ENABLE_CXX17_REMOVED_UNARY_BINARY_FUNCTION")
set(CMAKE_INTERPROCEDURAL_OPTIMIZATION OFF)   # pybind11 adds no LTO of its own then
set(PKG_CONFIG_EXECUTABLE /usr/bin/pkg-config CACHE FILEPATH "")  # programs are the host's
set(CMAKE_STRIP /usr/bin/strip CACHE FILEPATH "")
set(BUILD_SHARED_LIBS OFF CACHE BOOL "")
set(ENV{PKG_CONFIG_LIBDIR} "$PREFIX/lib/pkgconfig")
set(CMAKE_MODULE_LINKER_FLAGS_INIT "-Wl,--version-script=$PREFIX/share/module.map")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-Wl,--version-script=$PREFIX/share/module.map")
set(OpenGL_GL_PREFERENCE GLVND)
set(OPENGL_INCLUDE_DIR "$PREFIX/include" CACHE PATH "")
set(OPENGL_EGL_INCLUDE_DIR "$PREFIX/include" CACHE PATH "")
set(OPENGL_opengl_LIBRARY "$PREFIX/lib/libOpenGL.so" CACHE FILEPATH "")
set(OPENGL_egl_LIBRARY "$PREFIX/lib/libEGL.so" CACHE FILEPATH "")
set(HF_OPENVDB_MODULE_DIR "$PREFIX/lib/cmake/OpenVDB" CACHE PATH "")
set(OPENVDB_USE_STATIC_LIBS ON CACHE BOOL "")
set(USE_STATIC_DEPENDENCIES ON CACHE BOOL "")
set(TBB_USE_STATIC_LIBS ON CACHE BOOL "")
set(Blosc_USE_STATIC_LIBS ON CACHE BOOL "")
set(ZLIB_USE_STATIC_LIBS ON CACHE BOOL "")
EOF

# ---- header-only pieces from the host, each alone ----
ln -sfn /usr/include/boost "$PREFIX/include/boost"
rm -rf "$PREFIX/include/glm" && cp -r /usr/include/glm "$PREFIX/include/glm"
for d in EGL GL KHR; do ln -sfn "/usr/include/$d" "$PREFIX/include/$d"; done
ln -sf /usr/lib/x86_64-linux-gnu/libEGL.so.1 "$PREFIX/lib/libEGL.so"
ln -sf /usr/lib/x86_64-linux-gnu/libOpenGL.so.0 "$PREFIX/lib/libOpenGL.so"
cat >"$PREFIX/lib/cmake/glm/glmConfig.cmake" <<EOF
if(NOT TARGET glm::glm)
  add_library(glm::glm INTERFACE IMPORTED)
  set_target_properties(glm::glm PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "$PREFIX/include")
endif()
set(glm_FOUND TRUE)
EOF

# ---- the sources: Debian 12's source packages (the .orig tarballs) ----
mkdir -p "$WORK/apt/lists/partial" "$WORK/apt/cache/archives/partial" "$WORK/src"
echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian bookworm main" >"$WORK/apt/sources.list"
apt_opts=(-q -o Dir::Etc::SourceList="$WORK/apt/sources.list" -o Dir::Etc::SourceParts=/dev/null
          -o Dir::State::Lists="$WORK/apt/lists" -o Dir::Cache="$WORK/apt/cache" -o APT::Sandbox::User=root)
[ -f "$WORK/.sources-ok" ] || { ( cd "$WORK/src" && apt-get "${apt_opts[@]}" update ) >>"$LOG" 2>&1 \
  || cannot "Debian's source archive is unreachable (see $LOG)"; }
for s in "${SOURCES[@]}"; do
  [ -f "$WORK/.sources-ok" ] && break
  # Only the upstream tarball is used; a missing Debian patch tarball does not matter.
  ( cd "$WORK/src" && apt-get "${apt_opts[@]}" source --download-only "$s" ) >>"$LOG" 2>&1 || true
  orig=("$WORK"/src/"$s"_*.orig.tar.*)
  case "${orig[0]}" in *.asc) orig=("${orig[@]:1}") ;; esac
  [ -f "${orig[0]}" ] || cannot "no upstream tarball of Debian's '$s' source package came (see $LOG)"
  mkdir -p "$WORK/$s" && tar -C "$WORK/$s" --strip-components=1 -xf "${orig[0]}"
done
touch "$WORK/.sources-ok"

# ---- the libraries ----
export PATH="$PREFIX/bin:$PATH" CC="$PREFIX/bin/cc" CXX="$PREFIX/bin/c++" AR="$PREFIX/bin/ar" RANLIB="$PREFIX/bin/ranlib"
export CFLAGS="-O2 -fPIC -fvisibility=hidden" CXXFLAGS="-O2 -fPIC -fvisibility=hidden"
JOBS="$(nproc)"
# Debian's CMake (3.25): the libraries' old cmake_minimum_required() calls stop CMake 4 (pip's).
CMAKE=/usr/bin/cmake
[ -x "$CMAKE" ] || CMAKE="$(command -v cmake)"
done_before() {  # done_before NAME: true (and says so) when NAME was built by an earlier, resumed run
  if [ -f "$WORK/.done-$1" ]; then say "   $1: built before"; return 0; fi
  say "   $1 ($((SECONDS - t0)) s)"; return 1
}
cmake_lib() {  # cmake_lib NAME SOURCE_SUBDIR [cmake args...]
  local name="$1" src="$WORK/$2"; shift 2
  done_before "$name" && return 0
  rm -rf "$WORK/build-$name"
  nice -n 19 "$CMAKE" -S "$src" -B "$WORK/build-$name" -G "Unix Makefiles" -DCMAKE_MAKE_PROGRAM="$(command -v make)" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_TOOLCHAIN_FILE="$PREFIX/share/toolchain.cmake" -DCMAKE_INSTALL_PREFIX="$PREFIX" \
    -DCMAKE_INSTALL_LIBDIR=lib -DCMAKE_POSITION_INDEPENDENT_CODE=ON "$@" >>"$LOG" 2>&1
  nice -n 19 "$CMAKE" --build "$WORK/build-$name" -j "$JOBS" >>"$LOG" 2>&1
  nice -n 19 "$CMAKE" --install "$WORK/build-$name" >>"$LOG" 2>&1
  touch "$WORK/.done-$name"
}
build() {
  if ! done_before zlib; then  # its configure: Debian's tarball lacks the CMake build's win32/ files
    ( cd "$WORK/zlib" && nice -n 19 ./configure --static --prefix="$PREFIX" --libdir="$PREFIX/lib" \
        && nice -n 19 make -j "$JOBS" libz.a && make install ) >>"$LOG" 2>&1
    touch "$WORK/.done-zlib"
  fi
  if ! done_before lz4; then
    nice -n 19 make -C "$WORK/lz4/lib" -j "$JOBS" liblz4.a CC="$CC" AR="$AR" CFLAGS="$CFLAGS" >>"$LOG" 2>&1
    cp "$WORK/lz4/lib/liblz4.a" "$PREFIX/lib/"
    cp "$WORK"/lz4/lib/{lz4.h,lz4hc.h,lz4frame.h} "$PREFIX/include/"
    touch "$WORK/.done-lz4"
  fi
  cmake_lib blosc c-blosc -DBUILD_SHARED=OFF -DBUILD_STATIC=ON -DBUILD_TESTS=OFF -DBUILD_FUZZERS=OFF \
    -DBUILD_BENCHMARKS=OFF -DDEACTIVATE_SNAPPY=ON -DDEACTIVATE_ZSTD=ON -DPREFER_EXTERNAL_LZ4=ON \
    -DPREFER_EXTERNAL_ZLIB=ON -DLZ4_INCLUDE_DIR="$PREFIX/include" -DLZ4_LIBRARY="$PREFIX/lib/liblz4.a"
  cmake_lib imath imath -DBUILD_TESTING=OFF -DPYTHON=OFF
  cmake_lib tbb onetbb -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBBMALLOC_BUILD=OFF -DTBB_STRICT=OFF
  cmake_lib openvdb openvdb -DOPENVDB_BUILD_CORE=ON -DOPENVDB_CORE_SHARED=OFF -DOPENVDB_CORE_STATIC=ON \
    -DOPENVDB_BUILD_BINARIES=OFF -DOPENVDB_BUILD_PYTHON_MODULE=OFF -DOPENVDB_USE_DELAYED_LOADING=OFF \
    -DUSE_EXPLICIT_INSTANTIATION=OFF -DUSE_CCACHE=OFF -DUSE_LOG4CPLUS=OFF -DUSE_EXR=OFF -DUSE_PKGCONFIG=OFF \
    -DOPENVDB_ENABLE_UNINSTALL=OFF -DBlosc_ROOT="$PREFIX" -DTBB_ROOT="$PREFIX" -DZLIB_ROOT="$PREFIX" \
    -DBoost_INCLUDE_DIR="$PREFIX/include" -DDISABLE_DEPENDENCY_VERSION_CHECKS=ON
  # OpenVDB 10's installed find module asks for Boost iostreams whatever the build: this one has
  # no delayed loading, so it needs none (its Boost headers are in PREFIX/include).
  sed -i 's/^find_package(Boost REQUIRED COMPONENTS iostreams)$/# (no Boost iostreams: built without delayed loading)/' \
    "$PREFIX/lib/cmake/OpenVDB/FindOpenVDB.cmake"
  ! grep -q "COMPONENTS iostreams)$" "$PREFIX/lib/cmake/OpenVDB/FindOpenVDB.cmake"
  if ! done_before libusb; then
    ( cd "$WORK/libusb-1.0" && nice -n 19 ./configure --host=x86_64-linux-gnu --prefix="$PREFIX" \
        --libdir="$PREFIX/lib" --disable-udev --enable-static --disable-shared \
        && nice -n 19 make -j "$JOBS" && make install ) >>"$LOG" 2>&1
    touch "$WORK/.done-libusb"
  fi
}
# errexit holds inside build() (it is not called in a condition); the trap says where it stopped.
trap 'tail -n 30 "$LOG" >&2; say "error: building the manylinux_2_28 libraries failed (log: $LOG; work folder kept: $WORK)"' ERR
build
trap - ERR
# What the engine's module links with: OpenVDB's find module (10.0.1) links a static OpenVDB
# without its blosc and zlib, and blosc's static archive needs lz4 and zlib after it.
cat >"$PREFIX/share/module-toolchain.cmake" <<EOF
include("$PREFIX/share/toolchain.cmake")
set(CMAKE_CXX_STANDARD_LIBRARIES "$PREFIX/lib/libblosc.a $PREFIX/lib/liblz4.a $PREFIX/lib/libz.a" CACHE STRING "")
EOF
rm -rf "$WORK"
touch "$PREFIX/.hf-ok"
say "   ready in $((SECONDS - t0)) s: $(du -sh "$PREFIX" | cut -f1)"
echo "$PREFIX"
}
