# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by build_wheel.sh, build_extension.sh and tests/package/*.sh.
# hf_python VERSION: prints a CPython VERSION (3.11: Blender 4.2 to 5.0; 3.13: Blender 5.1 to 5.3
# and Debian 13's 4.3) with venv and ensurepip: the system's, else one built once from Debian's
# source package into ~/.cache/hapticfluid (scripts/build_python.sh, which says how). Returns 1,
# with the reason on stderr, when there is none.
hf_python() {
  bash "$(dirname "${BASH_SOURCE[0]}")/build_python.sh" "$1"
}
hf_python311() { hf_python 3.11; }

# hf_wheel_python VERSION: prints the CPython to build the VERSION wheel with: $HF_WHEEL_PYTHON
# when set (it must be a CPython VERSION with venv and ensurepip), else hf_python's choice.
# Returns 1, with the reason on stderr, when there is none.
hf_wheel_python() {
  local v="$1" c="${HF_WHEEL_PYTHON:-}"
  if [ -z "$c" ]; then hf_python "$v"; return; fi
  command -v "$c" >/dev/null 2>&1 || { echo "HF_WHEEL_PYTHON='$c' is not a program" >&2; return 1; }
  if ! "$c" -c "import sys, venv, ensurepip; sys.exit('%d.%d' % sys.version_info[:2] != '$v')" 2>/dev/null; then
    echo "HF_WHEEL_PYTHON='$c' is not a CPython $v with venv and ensurepip (Debian: python3-venv)" >&2; return 1
  fi
  "$c" -c 'import sys; print(sys.executable)'
}

# hf_bpy_python BPY_VERSION: the Python version (3.11 or 3.13) that bpy BPY_VERSION's wheels are
# built for: Blender 4.2 to 5.0 embed CPython 3.11, 5.1 and later 3.13.
hf_bpy_python() {
  case "$1" in
    4.*|5.0|5.0.*) echo 3.11 ;;
    *) echo 3.13 ;;
  esac
}

# hf_bpy_platform: true where bpy wheels exist (PyPI has them for Linux x86_64 with glibc 2.28+
# among others; this project's packaging targets Linux x86_64 only). Where it is true, a bpy that
# cannot be installed is a failure, not a skip.
hf_bpy_platform() {
  [ "$(uname -s)-$(uname -m)" = Linux-x86_64 ] || return 1
  local glibc; glibc="$(getconf GNU_LIBC_VERSION 2>/dev/null | awk '{print $2}')"
  [ -n "$glibc" ] && [ "$(printf '%s\n2.28\n' "$glibc" | sort -V | head -1)" = 2.28 ]
}

# pip's output without the "Location ... is ignored" lines that a pip.conf naming missing
# local indexes adds to every look-up.
hf_pip_quiet() { grep -v '^WARNING: Location ' || true; }

# hf_pip_offline LOG: true when pip's output in LOG shows that it could not reach its package
# index (no network, no name resolution, a proxy or timeout on the connection). A pip failure
# with the index reachable (a version conflict, a missing wheel, a broken build) is not that:
# the package scripts skip (exit 77) on the first and fail on the second.
hf_pip_offline() {
  grep -Eq 'NewConnectionError|Failed to establish a new connection|Temporary failure in name resolution|Name or service not known|Network is unreachable|ConnectTimeoutError|Connection timed out|ProxyError|Max retries exceeded|ReadTimeoutError|connection broken by' "$1"
}
