#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The project's SPDX license line in every source file git tracks.

    python3 scripts/spdx.py           list the files without it (exit 1 if any)
    python3 scripts/spdx.py --add     add it where it is missing (after a #! line)

Source files are C++, GLSL, Python, shell, CMake, JavaScript and YAML; the line is the first
(the second after a ``#!`` line), in the file's comment syntax. Vendored code keeps its own
license and is not listed here (the project vendors none today). tests/python/test_license.py
runs the check.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

LICENSE = "GPL-3.0-or-later"
TAG = "SPDX-License-Identifier:"
COMMENT = {".h": "//", ".cpp": "//", ".glsl": "//", ".comp": "//", ".js": "//",
           ".py": "#", ".sh": "#", ".cmake": "#", ".yaml": "#", ".yml": "#"}
SKIP_PARTS = ("corpus", "seeds")  # fuzz inputs: data, not source


def comment_of(path: Path) -> str | None:
    if path.name == "CMakeLists.txt":
        return "#"
    return COMMENT.get(path.suffix)


def source_files(root: Path) -> list[Path]:
    names = subprocess.run(["git", "ls-files"], cwd=root, capture_output=True, text=True, check=True).stdout.split()
    return [root / n for n in names
            if comment_of(Path(n)) and not any(part in SKIP_PARTS for part in Path(n).parts)]


def has_line(path: Path) -> bool:
    head = path.read_text(encoding="utf-8", errors="replace").splitlines()[:3]
    return any(TAG in line for line in head)


def add_line(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    line = f"{comment_of(path)} {TAG} {LICENSE}\n"
    if text.startswith("#!"):
        first, _, rest = text.partition("\n")
        path.write_text(f"{first}\n{line}{rest}", encoding="utf-8")
    else:
        path.write_text(line + text, encoding="utf-8")


def main(argv: list[str]) -> int:
    root = Path(__file__).resolve().parent.parent
    missing = [p for p in source_files(root) if not has_line(p)]
    if "--add" in argv:
        for p in missing:
            add_line(p)
        print(f"added the SPDX line to {len(missing)} file(s)")
        return 0
    for p in missing:
        print(p.relative_to(root))
    print(f"{len(missing)} source file(s) without '{TAG} {LICENSE}'")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
