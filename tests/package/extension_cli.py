# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender's `extension` command line (validate, server-generate, ...) from a Python that has bpy.

    python extension_cli.py validate EXTENSION_ZIP
    python extension_cli.py server-generate --repo-dir DIR

`blender --command extension ...` runs bl_pkg's cli/blender_ext.py (for `validate`, with the tag
list Blender ships); the bpy module from PyPI carries both files but not the command line, so this
runs the same script the same way (without importing bpy: it only finds bpy's folder).
Exit status: the script's (0 done, validate: 0 valid).
"""

import importlib.util
import pathlib
import subprocess
import sys

spec = importlib.util.find_spec("bpy")
if spec is None or spec.origin is None:
    sys.exit("error: this Python has no bpy module")
bpy_dir = pathlib.Path(spec.origin).parent
scripts = sorted(bpy_dir.glob("*/scripts/addons_core/bl_pkg/cli/blender_ext.py"))
tags = sorted(bpy_dir.glob("*/scripts/modules/_bpy_internal/extensions/tags.py"))
if len(scripts) != 1 or len(tags) != 1:
    sys.exit(f"error: expected one blender_ext.py and one tags.py under {bpy_dir}: {scripts} {tags}")
args = sys.argv[1:]
if args[:1] == ["validate"]:
    args += ["--valid-tags", str(tags[0])]
print(f"extension {' '.join(sys.argv[1:])} ({scripts[0]})", flush=True)
sys.exit(subprocess.call([sys.executable, str(scripts[0]), *args]))
