#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The extension zip in a Blender binary (not the bpy module): Blender's own validator, then
# bpy_check.py run inside `blender --background --factory-startup` (bpy first: install, roles,
# bake, Volume, live session on the simulated Falcon, Record, disable), user folders in a new
# work folder. For Blenders that no bpy module stands for: Debian 13's 4.3 (run it in the chroot:
#   sudo bash scripts/debian13_check.sh --root DIR -- bash tests/package/test_blender.sh ZIP
# with ZIP copied into DIR first), or blender.org's tarballs.
#   bash test_blender.sh EXTENSION_ZIP [BLENDER]        (BLENDER: default `blender` on PATH)
# Exit 0 all checks passed; 77 no Blender 4.2+ here (reason printed); other: a check failed.
set -euo pipefail
ZIP="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"
BLENDER="${2:-blender}"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
version="$("$BLENDER" --version 2>/dev/null | sed -n 's/^Blender \([0-9]*\.[0-9]*\.[0-9]*\).*/\1/p' | head -1)" || true
[ -n "$version" ] || { echo "SKIP: no Blender at '$BLENDER'"; exit 77; }
[ "$(printf '%s\n4.2.0\n' "$version" | sort -V | head -1)" = 4.2.0 ] \
  || { echo "SKIP: Blender $version has no extensions (4.2+ needed)"; exit 77; }
work="$(mktemp -d)/blender-$version"
echo "== Blender $version ($(command -v "$BLENDER")), $ZIP"
"$BLENDER" --factory-startup --command extension validate "$ZIP"
env BLENDER_USER_CONFIG="$work/config" BLENDER_USER_SCRIPTS="$work/scripts" \
    BLENDER_USER_EXTENSIONS="$work/extensions" BLENDER_USER_DATAFILES="$work/datafiles" \
  "$BLENDER" --background --factory-startup --python-exit-code 1 --python "$HERE/bpy_check.py" \
  -- bpy-first "$ZIP" "$work"
rm -rf "$(dirname "$work")"
