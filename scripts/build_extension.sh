#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the Blender 4.2+ extension zip into dist/: the add-on's code, its blender_manifest.toml
# and two hapticfluid wheels (native module and its libraries inside) under wheels/: cp311 for
# Blender 4.2 to 5.0, cp313 for Blender 5.1 to 5.3 (and Debian 13's 4.3). Blender unpacks only
# the wheel whose tags match its own Python. Then a static extension repository beside it.
#
#   bash scripts/build_extension.sh [--out DIR] [--work DIR] [--wheel FILE]... [--repo DIR]
#
# Without --wheel it first builds both wheels (scripts/build_wheel.sh --python 3.11 and 3.13,
# same --out and --work; build_python.sh provides a CPython 3.13 where the system has none).
# The zip's manifest is addon/hapticfluid_blender/blender_manifest.toml with
# `wheels = ["./wheels/<cp311 wheel>", "./wheels/<cp313 wheel>"]` appended; the manifest's version
# must be the wheels'.
# Repository (--repo, default OUT/repository): the zip and the `index.json` that Blender's own
# `extension server-generate` writes for it; an artist adds the folder (or its URL on any static
# web server) once in Preferences > Get Extensions > Repositories, and later versions arrive as
# updates. Copy a newer zip into the folder and run this again (or server-generate) to publish.
# Blender's validator and index generator come from `blender` 4.2+ on PATH, else from a bpy module
# given as $HF_BPY_PYTHON (a python that imports bpy), else from the newest bpy the package tests
# cached in ~/.cache/hapticfluid: the same scripts; with none the zip is still built, and the
# repository step says it was left out. tests/package validates the zip,
# installs it into bpy, and adds the repository to bpy.
# Exit status: 0 built; 77 a wheel cannot be built on this machine (reason printed); other:
# failed.
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$HF_ROOT/dist"
WORK="$HF_ROOT/build-wheel"
WHEELS=()
REPO=""
while [ $# -gt 0 ]; do
  case "$1" in
    --out) OUT="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --wheel) WHEELS+=("$2"); shift 2 ;;
    --repo) REPO="$2"; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "error: unknown argument '$1' (expected --out DIR, --work DIR, --wheel FILE, --repo DIR)" >&2; exit 2 ;;
  esac
done
mkdir -p "$OUT" "$WORK"
OUT="$(cd "$OUT" && pwd)"

REPO="${REPO:-$OUT/repository}"

if [ ${#WHEELS[@]} -eq 0 ]; then
  for v in 3.11 3.13; do
    bash "$HF_ROOT/scripts/build_wheel.sh" --python "$v" --out "$OUT" --work "$WORK"
    built=("$OUT"/hapticfluid-*-cp${v/./}-*.whl)
    WHEELS+=("${built[0]}")
  done
fi
for w in "${WHEELS[@]}"; do [ -f "$w" ] || { echo "error: --wheel '$w' is not a file" >&2; exit 2; }; done

ADDON="$HF_ROOT/addon/hapticfluid_blender"
PY="$(command -v python3)"
# Stage, check the version and write the zip (Python: zipfile and tomllib, no zip tool needed).
zip_path="$("$PY" - "$ADDON" "$OUT" "${WHEELS[@]}" <<'PY'
import pathlib, sys, tomllib, zipfile

addon, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
wheels = sorted(pathlib.Path(a) for a in sys.argv[3:])
manifest_text = (addon / "blender_manifest.toml").read_text(encoding="utf-8")
manifest = tomllib.loads(manifest_text)
if "wheels" in manifest:
    sys.exit("error: blender_manifest.toml already lists wheels; this script adds the one it packs")
tags = [w.name.split("-")[2] for w in wheels]
if len(set(tags)) != len(tags):
    sys.exit(f"error: two wheels for one Python ({tags}): give one wheel per Python")
for wheel in wheels:
    if manifest["version"] != wheel.name.split("-")[1]:
        sys.exit(f"error: blender_manifest.toml version {manifest['version']} is not {wheel.name}'s: "
                 f"set it to the project's version (CMakeLists.txt project())")
manifest_text += "\nwheels = [" + ", ".join(f'"./wheels/{w.name}"' for w in wheels) + "]\n"
platform = manifest["platforms"][0].replace("-", "_")
zip_path = out / f"{manifest['id']}-{manifest['version']}-{platform}.zip"
sources = sorted(p for p in addon.rglob("*")
                 if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".pyc"
                 and p.name != "blender_manifest.toml")
with zipfile.ZipFile(zip_path, "w", zipfile.ZIP_DEFLATED) as z:
    z.writestr("blender_manifest.toml", manifest_text)
    for p in sources:
        z.write(p, p.relative_to(addon).as_posix())
    for wheel in wheels:
        z.write(wheel, f"wheels/{wheel.name}", compress_type=zipfile.ZIP_STORED)  # already zipped
print(zip_path)
PY
)"
echo "== extension: $zip_path ($(du -h "$zip_path" | cut -f1)), wheels: $(printf '%s ' "${WHEELS[@]##*/}")"

# Blender's extension command line: `blender --command extension ...` from a Blender 4.2+ on
# PATH, else the same script (bl_pkg's cli/blender_ext.py) from $HF_BPY_PYTHON's bpy module.
blender_version="$(blender --version 2>/dev/null | sed -n 's/^Blender \([0-9]*\.[0-9]*\).*/\1/p' | head -1)" || true
if [ -n "$blender_version" ] && [ "$(printf '%s\n4.2\n' "$blender_version" | sort -V | head -1)" = "4.2" ]; then
  extension_cli() { blender --factory-startup --command extension "$@"; }
elif [ -n "${HF_BPY_PYTHON:-}" ]; then
  extension_cli() { "$HF_BPY_PYTHON" "$HF_ROOT/tests/package/extension_cli.py" "$@"; }
elif cached="$(ls -d "${HF_BPY_CACHE:-$HOME/.cache/hapticfluid}"/bpy-*/.hf-ok 2>/dev/null | sort -V | tail -1)" \
     && [ -n "$cached" ]; then  # a bpy the package tests installed (tests/package/bpy_venv.sh)
  HF_BPY_PYTHON="$(dirname "$cached")/bin/python"
  extension_cli() { "$HF_BPY_PYTHON" "$HF_ROOT/tests/package/extension_cli.py" "$@"; }
else
  extension_cli() { return 77; }
fi

set +e; extension_cli validate "$zip_path"; rc=$?; set -e
case $rc in
  0) ;;
  77) echo "   (not validated here: no Blender 4.2+ on PATH, no \$HF_BPY_PYTHON, no cached bpy; tests/package validates it)" ;;
  *) echo "error: Blender's validator rejects $zip_path" >&2; exit 1 ;;
esac

# The static repository: the zip, replacing an older hapticfluid zip there (an index lists one
# package per id and platform), and index.json.
mkdir -p "$REPO"
zip_name="$(basename "$zip_path")"
find "$REPO" -maxdepth 1 -name "${zip_name%%-*}-*.zip" -delete
cp "$zip_path" "$REPO/"
set +e; extension_cli server-generate --repo-dir "$REPO"; rc=$?; set -e
case $rc in
  0) echo "== repository: $REPO ($(ls "$REPO" | grep -c '\.zip$') zip(s) + index.json): add it in Blender once" \
          "(Preferences > Get Extensions > Repositories > + > Add Remote Repository, URL file://$REPO/index.json" \
          "or its address on a web server)" ;;
  77) echo "   (repository index not written: no Blender 4.2+ on PATH, no \$HF_BPY_PYTHON, no cached bpy to run server-generate;" \
           "the zip is in $REPO)" ;;
  *) echo "error: Blender's server-generate failed for $REPO" >&2; exit 1 ;;
esac
