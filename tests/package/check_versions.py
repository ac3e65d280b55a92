# SPDX-License-Identifier: GPL-3.0-or-later
"""ctest package_versions: the project's one version, project(VERSION) in CMakeLists.txt, is the
version that pyproject.toml's regex reads for the wheel, hapticfluid.__version__, the add-on's
bl_info and blender_manifest.toml. Reads the files (no build needed).

    python3 check_versions.py SOURCE_DIR
"""

import ast
import pathlib
import re
import sys
import tomllib

root = pathlib.Path(sys.argv[1])
cmake = (root / "CMakeLists.txt").read_text(encoding="utf-8")
match = re.search(r"project\(\s*hapticfluid\s+VERSION\s+([0-9][0-9.]*)", cmake)
if match is None:
    sys.exit("FAIL: no project(hapticfluid VERSION x.y.z) in CMakeLists.txt")
version = match.group(1)

pyproject = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))
provider = pyproject["tool"]["scikit-build"]["metadata"]["version"]
wheel = re.search(provider["regex"], (root / provider["input"]).read_text(encoding="utf-8"))

init = ast.parse((root / "python/hapticfluid/__init__.py").read_text(encoding="utf-8"))
dunder = [n.value.value for n in init.body if isinstance(n, ast.Assign)
          and any(isinstance(t, ast.Name) and t.id == "__version__" for t in n.targets)]

addon = root / "addon/hapticfluid_blender"
tree = ast.parse((addon / "__init__.py").read_text(encoding="utf-8"))
bl_info = next(ast.literal_eval(n.value) for n in tree.body if isinstance(n, ast.Assign)
               and any(isinstance(t, ast.Name) and t.id == "bl_info" for t in n.targets))
manifest = tomllib.loads((addon / "blender_manifest.toml").read_text(encoding="utf-8"))

found = {
    "pyproject.toml regex (wheel metadata)": wheel.group("value") if wheel else None,
    "hapticfluid.__version__": dunder[0] if len(dunder) == 1 else dunder,
    "bl_info['version']": ".".join(str(v) for v in bl_info["version"]),
    "blender_manifest.toml version": manifest["version"],
}
bad = {k: v for k, v in found.items() if v != version}
for k, v in found.items():
    print(f"{'ok ' if v == version else 'BAD'} {k}: {v}")
if bad:
    sys.exit(f"FAIL: the project's version is {version} (CMakeLists.txt project()); these differ: {bad}")
print(f"all four carry the project's version {version}")
