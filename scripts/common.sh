# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by the README's commands: installs what is missing, then builds.
# Debian packages, the same names on Debian 12 (bookworm) and 13 (trixie); Python is Debian's
# /usr/bin/python3 (3.11 on 12, 3.13 on 13), the interpreter Debian's Blender (3.4 on 12, 4.3 on
# 13) embeds (a pyenv python3 may come first on PATH: it is never used for the module).
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
HF_BUILD="${HF_BUILD:-$HF_ROOT/build}"

HF_PACKAGES=(
  cmake g++ make ccache
  python3 python3-dev python3-venv pybind11-dev python3-numpy python3-pytest python3-hypothesis python3-matplotlib python3-yaml
  libglm-dev libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  libgtest-dev
  libusb-1.0-0-dev pkg-config clang libclang-rt-dev
  blender xvfb xauth
  nodejs  # runs the Flamenco job compiler in tests/farm (18 on Debian 12, 20 on 13)
  mmdebstrap  # builds the trixie tree whose Blender 4.3 the package tests install the zip into
  libopenvdb-dev python3-openvdb libopenvdb-tools libboost-iostreams-dev
)

hf_install_missing() {
  local missing=()
  for pkg in "${HF_PACKAGES[@]}"; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
  done
  if [ ${#missing[@]} -eq 0 ]; then
    echo "== dependencies: all ${#HF_PACKAGES[@]} Debian packages present"
    return 0
  fi
  echo "== dependencies: installing ${missing[*]}"
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then sudo=(sudo); else
      echo "error: these packages are missing and this user cannot install them: ${missing[*]}" >&2
      echo "       run as root: apt-get install -y --no-install-recommends ${missing[*]}" >&2
      return 1
    fi
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -q
  "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
}

hf_build() {
  echo "== build: $HF_BUILD"
  # ccache (a Debian package) keeps compiled objects between builds: a warm machine, a fresh
  # clone in another folder (CCACHE_BASEDIR makes paths relative to the clone) and the wheel's
  # second compile of the engine (CMake reads the launcher from the environment) reuse them.
  if command -v ccache >/dev/null 2>&1; then
    export CMAKE_CXX_COMPILER_LAUNCHER="${CMAKE_CXX_COMPILER_LAUNCHER:-ccache}"
    export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$HF_ROOT}"
  fi
  cmake -S "$HF_ROOT" -B "$HF_BUILD" -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=/usr/bin/python3 >/dev/null
  cmake --build "$HF_BUILD" -j "$(nproc)" "$@"
}
