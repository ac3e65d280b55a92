# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a Python that has bpy older than the manifest's blender_version_min (bpy 4.2.0, which
would unpack the wrong wheel): Blender must refuse to install the extension zip, naming the
version it needs, so no artist gets an add-on whose engine does not import.

    python bpy_refuses.py EXTENSION_ZIP WORK_DIR
"""

import os
import re
import sys
import zipfile

ZIP, WORK = (os.path.abspath(a) for a in sys.argv[1:3])
os.makedirs(WORK, exist_ok=False)
for name in ("CONFIG", "SCRIPTS", "EXTENSIONS", "DATAFILES"):  # read when bpy starts
    os.environ[f"BLENDER_USER_{name}"] = os.path.join(WORK, name.lower())
with zipfile.ZipFile(ZIP) as z:
    minimum = re.search(r'^blender_version_min = "([^"]+)"', z.read("blender_manifest.toml").decode(), re.M).group(1)

import io  # noqa: E402

import bpy  # noqa: E402


class Tee(io.TextIOBase):
    """Keeps what Blender's extension operator prints (its errors go to stdout) and shows it."""

    def __init__(self, out):
        self.out, self.text = out, []

    def write(self, s):
        self.text.append(s)
        return self.out.write(s)


tee = Tee(sys.stdout)
sys.stdout = tee
try:
    result = bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
except RuntimeError as exc:  # an error report
    result = None
    print(exc)
sys.stdout = tee.out
said = "".join(tee.text)
installed = os.path.isdir(os.path.join(os.environ["BLENDER_USER_EXTENSIONS"], "user_default", "hapticfluid"))
enabled = any(a.module.endswith(".hapticfluid") for a in bpy.context.preferences.addons)
ok = not installed and not enabled and f"minimum supported version ({minimum})" in said
print(f"bpy {bpy.app.version_string}: operator {result}, installed {installed}, enabled {enabled}", flush=True)
print(("PASS" if ok else "FAIL") + f": Blender {bpy.app.version_string} refuses the zip, naming {minimum}", flush=True)
os._exit(0 if ok else 1)  # bpy 4.2's exit handlers (bpy_check.py)
