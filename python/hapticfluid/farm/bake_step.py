"""The bake task of a farm job: ``python3 -m hapticfluid.farm bake --root ROOT SCENE --resolution N
--cache CACHE``.

Bakes a hapticfluid scene (.json) with ``python3 -m hapticfluid bake``, or a .blend with the
add-on's ``bake_blend.py`` in Blender, into CACHE. It resumes when CACHE holds a checkpoint and
starts from the first frame when it does not, so the same command serves the first run and every
re-queue: a worker that died, was preempted or lost the task continues after the last complete
frame. A checkpoint from other settings (resolution, scene) is refused with the bake's own error,
never deleted. A second worker given the same task is refused by the cache's lock (exit 1, the
message names the cache) while the first one bakes.
"""

from __future__ import annotations

import importlib.util
import logging
import os
import subprocess
from pathlib import Path
from typing import List

from hapticfluid.bake import cache as _cache
from hapticfluid.farm import resolve

log = logging.getLogger(__name__)


def should_resume(cache_dir: "str | os.PathLike") -> bool:
    """True when the cache holds a bake checkpoint to continue from."""
    return _cache.checkpoint_path(cache_dir).is_file()


def bake_command_json(scene: Path, resolution: int, cache: Path) -> List[str]:
    """Arguments of ``python3 -m hapticfluid`` that bake a scene .json into ``cache``."""
    args = ["bake", str(scene), "--resolution", str(resolution), "--cache", str(cache)]
    return args + (["--resume"] if should_resume(cache) else [])


def addon_folder() -> Path:
    """The folder of the hapticfluid_blender add-on importable here (PYTHONPATH), without
    importing it (it needs bpy)."""
    spec = importlib.util.find_spec("hapticfluid_blender")
    if spec is None or not spec.submodule_search_locations:
        raise FileNotFoundError("the hapticfluid_blender add-on is not importable: put the folder holding it "
                                "(the repository's addon/ folder) on the job's PythonPath to bake a .blend")
    return Path(list(spec.submodule_search_locations)[0])


def bake_command_blend(blender: str, scene: Path, resolution: int, cache: Path) -> List[str]:
    """The Blender command line that bakes a .blend's hapticfluid settings into ``cache``."""
    folder = addon_folder()
    setup = ("import sys, bpy; sys.path.insert(0, {parent!r}); import hapticfluid_blender as a; a.register(); "
             "a.properties.clear_stale_bake_state(); a.roles.settings_of(bpy.context.scene).cache_dir = {cache!r}"
             ).format(parent=str(folder.parent), cache=str(cache))
    args = [blender, "--background", str(scene), "--python-exit-code", "1", "--python-expr", setup,
            "--python", str(folder / "bake_blend.py"), "--", "--resolution", str(resolution)]
    return args + (["--resume"] if should_resume(cache) else [])


def run(root: str, scene: str, resolution: int, cache: str, blender: str = "blender") -> int:
    """Run the bake task; returns the process exit code (0 when the bake finished)."""
    scene_path, cache_path = resolve(root, scene), resolve(root, cache)
    if not scene_path.is_file():
        log.error("scene file '%s' does not exist on this worker (shared root '%s')", scene_path, root)
        return 2
    if not Path(root).is_dir():
        log.error("shared root '%s' is not a folder on this worker: mount the shared storage there or fix the "
                  "job's SharedRoot", root)
        return 2
    cache_path.parent.mkdir(parents=True, exist_ok=True)  # under the shared root: the job names it
    resume = should_resume(cache_path)
    log.info("%s %s into %s at resolution %d", "resuming" if resume else "baking", scene_path, cache_path,
             resolution)
    if scene_path.suffix.lower() == ".blend":
        try:
            command = bake_command_blend(blender, scene_path, resolution, cache_path)
        except FileNotFoundError as exc:
            log.error("%s", exc)
            return 2
        return subprocess.run(command, check=False).returncode
    from hapticfluid.cli import main as hapticfluid_main

    return hapticfluid_main(bake_command_json(scene_path, resolution, cache_path))
