"""Validates an extension zip with Blender's own validator, from a Python that has `bpy`.

    python validate_extension.py EXTENSION_ZIP

`blender --command extension validate` runs bl_pkg's cli/blender_ext.py with the tag list Blender
ships; the bpy module from PyPI carries both files but not the command line, so this runs the
same script with the same tag list (without importing bpy: it only finds bpy's folder).
Exit status: the validator's (0 valid).
"""

import importlib.util
import pathlib
import subprocess
import sys

spec = importlib.util.find_spec("bpy")
if spec is None or spec.origin is None:
    sys.exit("error: this Python has no bpy module")
bpy_dir = pathlib.Path(spec.origin).parent
validators = sorted(bpy_dir.glob("*/scripts/addons_core/bl_pkg/cli/blender_ext.py"))
tags = sorted(bpy_dir.glob("*/scripts/modules/_bpy_internal/extensions/tags.py"))
if len(validators) != 1 or len(tags) != 1:
    sys.exit(f"error: expected one blender_ext.py and one tags.py under {bpy_dir}: {validators} {tags}")
print(f"validating {sys.argv[1]} with {validators[0]}", flush=True)
sys.exit(subprocess.call([sys.executable, str(validators[0]), "validate", sys.argv[1],
                          "--valid-tags", str(tags[0])]))
