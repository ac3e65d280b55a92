# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake task of a farm job: ``python3 -m hapticfluid.farm bake --root ROOT SCENE --resolution N
--cache CACHE [--until LAST]``.

Bakes a hapticfluid scene (.json) with ``python3 -m hapticfluid bake --resume``, or a .blend in
Blender with the add-on's entry point (``bake_main``, given ``--cache CACHE --resume``), into CACHE.
``--resume`` is the bake's lazy cache: on an empty cache it starts from the first frame; otherwise
it keeps every sound frame and bakes from the latest kept checkpoint before the first frame that
is missing, damaged or whose inputs changed. So one command serves the first run, every re-queue
(a worker that died, was preempted or lost the task continues from the latest checkpoint) and
every chunk of a chained bake: ``--until LAST`` stops after frame LAST, leaving the checkpoint the
next chunk starts from. A checkpoint from other settings (resolution, scene) is refused with the
bake's own error, never deleted. A second worker given the same task (or a chunk run beside the
one before it) is refused by the cache's lock (exit 1, the message names the cache) while the
first one bakes.
"""

from __future__ import annotations

import importlib.util
import logging
import os
import subprocess
from pathlib import Path
from typing import List, Optional

from hapticfluid.farm import BLENDER_BAKE_EXPR, resolve

log = logging.getLogger(__name__)


def _until_args(until: Optional[int]) -> List[str]:
    return [] if until is None else ["--until", str(until)]


def bake_command_json(scene: Path, resolution: int, cache: Path, until: Optional[int] = None) -> List[str]:
    """Arguments of ``python3 -m hapticfluid`` that bake a scene .json into ``cache`` (up to
    frame ``until``, or its last frame)."""
    return ["bake", str(scene), "--resolution", str(resolution), "--cache", str(cache), "--resume"] + \
        _until_args(until)


def addon_folder() -> Path:
    """The folder of the hapticfluid_blender add-on importable here (PYTHONPATH), without
    importing it (it needs bpy)."""
    spec = importlib.util.find_spec("hapticfluid_blender")
    if spec is None or not spec.submodule_search_locations:
        raise FileNotFoundError("the hapticfluid_blender add-on is not importable: put the folder holding it "
                                "(the repository's addon/ folder) on the job's PythonPath to bake a .blend")
    return Path(list(spec.submodule_search_locations)[0])


def bake_command_blend(blender: str, scene: Path, resolution: int, cache: Path,
                       until: Optional[int] = None) -> List[str]:
    """The Blender command line that bakes a .blend's hapticfluid settings into ``cache``: the
    add-on's entry point (BLENDER_BAKE_EXPR), with the add-on's folder put on Blender's path."""
    setup = f"import sys; sys.path.insert(0, {str(addon_folder().parent)!r}); {BLENDER_BAKE_EXPR}"
    # --python-use-system-env: Blender 4.x reads PYTHONPATH (where hapticfluid may be) only with it.
    args = [blender, "--background", str(scene), "--python-use-system-env", "--python-exit-code", "1", "--python-expr", setup,
            "--", "--resolution", str(resolution), "--cache", str(cache), "--resume"]
    return args + _until_args(until)


def run(root: str, scene: str, resolution: int, cache: str, blender: str = "blender",
        until: Optional[int] = None) -> int:
    """Run the bake task (up to frame ``until``, or the scene's last); returns the process exit
    code (0 when the bake finished or reached ``until``)."""
    scene_path, cache_path = resolve(root, scene), resolve(root, cache)
    if not scene_path.is_file():
        log.error("scene file '%s' does not exist on this worker (shared root '%s')", scene_path, root)
        return 2
    if not Path(root).is_dir():
        log.error("shared root '%s' is not a folder on this worker: mount the shared storage there or fix the "
                  "job's SharedRoot", root)
        return 2
    cache_path.parent.mkdir(parents=True, exist_ok=True)  # under the shared root: the job names it
    log.info("bake task: %s into %s at resolution %d, %s; frames the cache holds sound are kept", scene_path,
             cache_path, resolution, "to the last frame" if until is None else f"until frame {until}")
    if scene_path.suffix.lower() == ".blend":
        try:
            command = bake_command_blend(blender, scene_path, resolution, cache_path, until)
        except FileNotFoundError as exc:
            log.error("%s", exc)
            return 2
        return subprocess.run(command, check=False).returncode
    from hapticfluid.cli import main as hapticfluid_main

    return hapticfluid_main(bake_command_json(scene_path, resolution, cache_path, until))
