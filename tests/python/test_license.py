# SPDX-License-Identifier: GPL-3.0-or-later
"""Every source file git tracks carries the project's SPDX license line (scripts/spdx.py adds
it), and the LICENSE file is the GPL version 3 the line names."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_every_source_file_names_its_license():
    if not (ROOT / ".git").exists():
        pytest.skip("not a git checkout: the file list comes from git ls-files")
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "spdx.py")], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_the_license_file_is_the_gpl_3():
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert "GNU GENERAL PUBLIC LICENSE" in text and "Version 3, 29 June 2007" in text
