#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Prints the python of a venv that has bpy BPY_VERSION (Blender as a Python module, from PyPI),
# installing it once into ${HF_BPY_CACHE:-~/.cache/hapticfluid}/bpy-<version> (~0.4 GB; later
# runs reuse it). The venv's CPython is the one that release's wheels are built for (3.11 for
# Blender 4.2 to 5.0, 3.13 for 5.1+: scripts/build_python.sh provides it, built once from
# Debian's source where the system lacks it).
#   bash bpy_venv.sh BPY_VERSION        # stdout: the venv's python; progress on stderr
# Exit 0; 77 where PyPI has no bpy wheel for this platform (not Linux x86_64 with glibc 2.28+)
# or no such CPython can be had (reason on stderr); 1 where it should install and does not.
set -euo pipefail
VERSION="$1"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$HERE/../../scripts/package_common.sh"
CACHE="${HF_BPY_CACHE:-$HOME/.cache/hapticfluid}/bpy-$VERSION"
if [ -f "$CACHE/.hf-ok" ]; then echo "$CACHE/bin/python"; exit 0; fi

not_here() {  # a skip where bpy cannot exist, a failure where it should install
  if hf_bpy_platform; then echo "error: $*" >&2; exit 1; fi
  echo "SKIP: $* (PyPI's bpy wheels are for Linux x86_64 with glibc 2.28+, macOS and Windows;" \
       "this is $(uname -s) $(uname -m))" >&2
  exit 77
}
PYVER="$(hf_bpy_python "$VERSION")"
set +e; PY="$(hf_python "$PYVER")"; rc=$?; set -e
[ $rc -eq 0 ] || { [ $rc -eq 77 ] && exit 77; not_here "no CPython $PYVER for bpy $VERSION (scripts/build_python.sh $PYVER failed above)"; }
echo "== installing bpy==$VERSION for CPython $PYVER into $CACHE (once; about 0.4 GB)" >&2
t0=$SECONDS
rm -rf "$CACHE"
mkdir -p "$(dirname "$CACHE")"
"$PY" -m venv "$CACHE"
if ! "$CACHE/bin/python" -m pip install -q "bpy==$VERSION" >"$CACHE.log" 2>&1; then
  reason="$(hf_pip_quiet <"$CACHE.log" | tail -3)"
  rm -rf "$CACHE"
  not_here "bpy==$VERSION cannot be installed: $reason (is PyPI reachable?)"
fi
if ! err="$("$CACHE/bin/python" -c 'import bpy' 2>&1)"; then
  rm -rf "$CACHE"
  not_here "bpy==$VERSION installs but does not import: $(echo "$err" | tail -2)"
fi
touch "$CACHE/.hf-ok"
echo "   installed in $((SECONDS - t0)) s" >&2
echo "$CACHE/bin/python"
