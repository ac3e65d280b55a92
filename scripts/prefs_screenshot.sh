#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Makes the README's screenshots of the extension in Blender's Preferences: a Blender 4.2+ in a
# window under Xvfb, fresh user folders, adds the extension repository, installs and enables
# hapticfluid from it as an artist does, then captures Preferences > Add-ons and Get Extensions
# with the entry expanded (scripts/prefs_screenshot.py does the Blender side and says how).
#
#   bash scripts/prefs_screenshot.sh [--home DIR] REPO_DIR OUT_DIR [BLENDER]
#
# REPO_DIR: the repository build_extension.sh writes (`bash scripts/build_extension.sh --out D`
# gives D/repository). Writes OUT_DIR/prefs_addons.png and OUT_DIR/prefs_get_extensions.png
# (the Preferences window alone, 1000x460, on a 1280x800 screen; optipng'd when optipng is
# present) and OUT_DIR/prefs_screenshot.log, which also holds the "engine:" lines: hapticfluid
# imported inside that Blender, from the wheel it unpacked, stepping an 8^3 simulation.
# BLENDER: default `blender` on PATH. --home: the HOME Blender runs with, so its user folders
# (config, extensions) are DIR/.config/blender/<version>, shown as the add-on's path in both
# pictures; DIR must not exist, and is removed afterwards (default: a mktemp folder; the README's
# pictures used /home/artist).
# Needs xvfb-run (xvfb, xauth), xwd (x11-apps), convert (imagemagick), xdotool, and an OpenGL
# 4.3 that Blender accepts (Mesa's llvmpipe will do). The README's picture is Debian 13's
# Blender 4.3.2, made in a trixie chroot from a Debian host, as root (scripts/debian13_check.sh):
#   bash scripts/build_extension.sh --out /var/tmp/ext
#   sudo bash scripts/debian13_check.sh --root /var/tmp/hf-trixie -- 'apt-get update && apt-get
#     install -y --no-install-recommends blender python3-numpy libegl1 libopengl0 libegl-mesa0
#     libgl1-mesa-dri xvfb xauth x11-apps imagemagick xdotool optipng'
#   cp -r /var/tmp/ext/repository /var/tmp/hf-trixie/root/
#   sudo bash scripts/debian13_check.sh --root /var/tmp/hf-trixie --reuse -- \
#     bash scripts/prefs_screenshot.sh --home /home/artist /root/repository /root/shots
# then the PNGs are in /var/tmp/hf-trixie/root/shots (docs/ has the README's). About 1 minute on
# the project's loaded 2-core machine. Exit 0: both PNGs written; 77: no Blender 4.2+ or a tool
# missing (reason printed); other: a step failed (the log says which).
set -euo pipefail
HOME_DIR=""
if [ "${1:-}" = --home ]; then HOME_DIR="$2"; shift 2; fi
[ $# -ge 2 ] || { echo "usage: bash scripts/prefs_screenshot.sh [--home DIR] REPO_DIR OUT_DIR [BLENDER]" >&2; exit 2; }
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
REPO="$(cd "$1" && pwd)"
mkdir -p "$2"
OUT="$(cd "$2" && pwd)"
BLENDER="${3:-blender}"
[ -f "$REPO/index.json" ] || { echo "error: $REPO has no index.json (build_extension.sh writes it)" >&2; exit 2; }
for tool in xvfb-run xauth xwd convert xdotool; do
  command -v "$tool" >/dev/null 2>&1 || { echo "SKIP: $tool is missing"; exit 77; }
done
version="$("$BLENDER" --version 2>/dev/null | sed -n 's/^Blender \([0-9]*\.[0-9]*\.[0-9]*\).*/\1/p' | head -1)" || true
[ -n "$version" ] || { echo "SKIP: no Blender at '$BLENDER'"; exit 77; }
[ "$(printf '%s\n4.2.0\n' "$version" | sort -V | head -1)" = 4.2.0 ] \
  || { echo "SKIP: Blender $version has no extensions (4.2+ needed)"; exit 77; }

if [ -n "$HOME_DIR" ]; then
  [ ! -e "$HOME_DIR" ] || { echo "error: --home $HOME_DIR exists (it must be new: it is removed afterwards)" >&2; exit 2; }
  mkdir -p "$HOME_DIR"
  work="$(cd "$HOME_DIR" && pwd)"
else
  work="$(mktemp -d)"
fi
trap 'rm -rf "$work"' EXIT
rm -f "$OUT/prefs_addons.png" "$OUT/prefs_get_extensions.png"
echo "== Blender $version ($(command -v "$BLENDER")), repository $REPO -> $OUT"
# HOME: Blender's user folders (config, extensions) in $work/.config/blender, none of the caller's.
# No --factory-startup: the first-run state an artist has (with the splash turned off).
set +e
env -u BLENDER_USER_RESOURCES -u BLENDER_USER_CONFIG -u BLENDER_USER_SCRIPTS -u BLENDER_USER_EXTENSIONS \
    -u BLENDER_USER_DATAFILES -u XDG_CONFIG_HOME HOME="$work" \
  xvfb-run -a -s "-screen 0 1280x800x24" \
  "$BLENDER" --window-geometry 0 0 1280 800 --python-exit-code 1 \
    --python "$HERE/prefs_screenshot.py" -- "$REPO" "$OUT" >"$OUT/prefs_screenshot.log" 2>&1
rc=$?
set -e
grep '^prefs_screenshot:' "$OUT/prefs_screenshot.log" || true
[ "$rc" -eq 0 ] && [ -f "$OUT/prefs_addons.png" ] && [ -f "$OUT/prefs_get_extensions.png" ] \
  || { echo "FAILED (exit $rc): last lines of $OUT/prefs_screenshot.log:" >&2; tail -n 30 "$OUT/prefs_screenshot.log" >&2; exit 1; }
if command -v optipng >/dev/null 2>&1; then
  optipng -quiet -o2 "$OUT/prefs_addons.png" "$OUT/prefs_get_extensions.png"
fi
ls -l "$OUT"/prefs_*.png
