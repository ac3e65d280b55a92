#!/usr/bin/env bash
# Builds the Blender 4.2+ extension zip into dist/: the add-on's code, its blender_manifest.toml
# and the hapticfluid wheel (native module and its libraries inside) under wheels/.
#
#   bash scripts/build_extension.sh [--out DIR] [--work DIR] [--wheel FILE]
#
# Without --wheel it first builds the wheel (scripts/build_wheel.sh, same --out and --work).
# The zip's manifest is addon/hapticfluid_blender/blender_manifest.toml with
# `wheels = ["./wheels/<the wheel>"]` appended; the manifest's version must be the wheel's.
# Validation: with `blender --command extension validate` when a Blender 4.2+ is on PATH, or
# with the same validator from a bpy module given as $HF_BPY_PYTHON (a python that imports
# bpy); tests/package/ validates it too and installs it into bpy.
# Exit status: 0 built; 77 the wheel cannot be built on this machine (reason printed); other:
# failed.
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$HF_ROOT/dist"
WORK="$HF_ROOT/build-wheel"
WHEEL=""
while [ $# -gt 0 ]; do
  case "$1" in
    --out) OUT="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --wheel) WHEEL="$2"; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "error: unknown argument '$1' (expected --out DIR, --work DIR, --wheel FILE)" >&2; exit 2 ;;
  esac
done
mkdir -p "$OUT" "$WORK"
OUT="$(cd "$OUT" && pwd)"

if [ -z "$WHEEL" ]; then
  bash "$HF_ROOT/scripts/build_wheel.sh" --out "$OUT" --work "$WORK"
  wheels=("$OUT"/hapticfluid-*.whl)
  WHEEL="${wheels[0]}"
fi
[ -f "$WHEEL" ] || { echo "error: --wheel '$WHEEL' is not a file" >&2; exit 2; }

ADDON="$HF_ROOT/addon/hapticfluid_blender"
PY="$(command -v python3)"
# Stage, check the version and write the zip (Python: zipfile and tomllib, no zip tool needed).
zip_path="$("$PY" - "$ADDON" "$WHEEL" "$OUT" <<'PY'
import pathlib, sys, tomllib, zipfile

addon, wheel, out = (pathlib.Path(a) for a in sys.argv[1:])
manifest_text = (addon / "blender_manifest.toml").read_text(encoding="utf-8")
manifest = tomllib.loads(manifest_text)
if "wheels" in manifest:
    sys.exit("error: blender_manifest.toml already lists wheels; this script adds the one it packs")
wheel_version = wheel.name.split("-")[1]
if manifest["version"] != wheel_version:
    sys.exit(f"error: blender_manifest.toml version {manifest['version']} is not the wheel's "
             f"{wheel_version}: set it to the project's version (CMakeLists.txt project())")
manifest_text += f'\nwheels = ["./wheels/{wheel.name}"]\n'
platform = manifest["platforms"][0].replace("-", "_")
zip_path = out / f"{manifest['id']}-{manifest['version']}-{platform}.zip"
sources = sorted(p for p in addon.rglob("*")
                 if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".pyc"
                 and p.name != "blender_manifest.toml")
with zipfile.ZipFile(zip_path, "w", zipfile.ZIP_DEFLATED) as z:
    z.writestr("blender_manifest.toml", manifest_text)
    for p in sources:
        z.write(p, p.relative_to(addon).as_posix())
    z.write(wheel, f"wheels/{wheel.name}", compress_type=zipfile.ZIP_STORED)  # already zipped
print(zip_path)
PY
)"
echo "== extension: $zip_path ($(du -h "$zip_path" | cut -f1))"

# Validate with Blender's own extension validator where one is at hand.
blender_version="$(blender --version 2>/dev/null | sed -n 's/^Blender \([0-9]*\.[0-9]*\).*/\1/p' | head -1)" || true
if [ -n "$blender_version" ] && [ "$(printf '%s\n4.2\n' "$blender_version" | sort -V | head -1)" = "4.2" ]; then
  blender --command extension validate "$zip_path"
elif [ -n "${HF_BPY_PYTHON:-}" ]; then
  "$HF_BPY_PYTHON" "$HF_ROOT/tests/package/validate_extension.py" "$zip_path"
else
  echo "   (not validated here: no Blender 4.2+ on PATH and no \$HF_BPY_PYTHON; tests/package validates it)"
fi
