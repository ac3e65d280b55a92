"""Bake on a farm: the bake as a job for Open Job Description (Deadline Cloud, ``openjd``) and
Flamenco, with the paths on shared storage.

A fluid bake is sequential in time, so a job is one bake task (on a GPU worker; resumable per
frame, so a re-queued task continues where the last one died) and render tasks over chunks of
the baked frames that depend on it. The two job files ship in this package:

* ``openjd_bake_render.yaml``: an OpenJD ``jobtemplate-2023-09`` template (TASK_CHUNKING
  extension, a ``CHUNK[INT]`` task parameter for the render chunks);
* ``hapticfluid-bake-render.js``: a Flamenco job compiler script (a custom job type).

:func:`write_openjd_job` and :func:`write_flamenco_job` write them for one scene into a folder,
with every path made relative to the farm's shared root; the worker-side commands are
``python3 -m hapticfluid.farm bake`` (:mod:`hapticfluid.farm.bake_step`) and Blender running
:mod:`hapticfluid_blender.farm_render` (its arguments: :mod:`hapticfluid.farm.chunks`). See docs/FARM.md.
"""

from __future__ import annotations

import json
import os
import shlex
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Dict, List, Optional, Tuple

from hapticfluid.files import atomic_write

HERE = Path(__file__).resolve().parent
OPENJD_TEMPLATE = HERE / "openjd_bake_render.yaml"
FLAMENCO_JOB_TYPE_NAME = "hapticfluid-bake-render"  # Flamenco names a job type after its script file
FLAMENCO_JOB_TYPE = HERE / f"{FLAMENCO_JOB_TYPE_NAME}.js"
OPENJD_TEMPLATE_FILE = "template.yaml"  # the names a Deadline Cloud job bundle folder uses
OPENJD_PARAMETERS_FILE = "parameters.json"  # openjd run -p file://...: {name: value}
DEADLINE_PARAMETERS_FILE = "parameter_values.json"  # deadline bundle submit: {"parameterValues": [...]}
FLAMENCO_JOB_FILE = "flamenco_job.json"
SCENE_SUFFIXES = (".json", ".blend")


def template_text(path: Path) -> str:
    """The text of a shipped job file (OPENJD_TEMPLATE or FLAMENCO_JOB_TYPE)."""
    return path.read_text(encoding="utf-8")


def relative_to_root(path: "str | os.PathLike", root: "str | os.PathLike", what: str) -> str:
    """``path`` relative to the shared root, with forward slashes (the job files are read on
    other machines). ValueError naming ``what`` when the path is not under the root."""
    root_abs = Path(os.path.abspath(root))
    path_abs = Path(os.path.abspath(path))
    try:
        rel = path_abs.relative_to(root_abs)
    except ValueError:
        raise ValueError(f"move the {what} under the shared root '{root_abs}' (or choose a shared root that "
                         f"contains it): '{path_abs}' is not under it") from None
    text = PurePosixPath(*rel.parts).as_posix() if rel.parts else "."
    return text


def resolve(root: "str | os.PathLike", path: "str | os.PathLike") -> Path:
    """A job's path on this worker: relative paths start at the shared root, absolute ones stay."""
    p = Path(path)
    return p if p.is_absolute() else Path(root) / p


def parse_frames(text: str) -> List[int]:
    """Frames of an OpenJD-style range expression: ``"7"``, ``"1-48"``, ``"1-9:2"``, ``"1,3,5-8"``
    (ascending, each frame once). ValueError on anything else."""
    frames: List[int] = []
    for part in str(text).replace(" ", "").split(","):
        step = 1
        if ":" in part:
            part, step_text = part.split(":", 1)
            step = int(step_text)
        if "-" in part[1:]:
            cut = part.index("-", 1)
            first, last = int(part[:cut]), int(part[cut + 1:])
        else:
            first = last = int(part)
        if step < 1 or last < first:
            raise ValueError(f"frames '{text}': '{part}' must be FIRST-LAST with FIRST <= LAST and a step >= 1")
        frames.extend(range(first, last + 1, step))
    if sorted(set(frames)) != frames:
        raise ValueError(f"frames '{text}' must be ascending, each frame once")
    return frames


def frame_chunks(first: int, last: int, chunk_size: int) -> List[Tuple[int, int]]:
    """Contiguous (first, last) chunks of at most ``chunk_size`` frames covering first..last."""
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be >= 1, got {chunk_size}")
    if last < first:
        raise ValueError(f"frame range {first}..{last} is empty")
    return [(a, min(a + chunk_size - 1, last)) for a in range(first, last + 1, chunk_size)]


@dataclass(frozen=True)
class FarmJob:
    """One scene's bake-and-render job. Paths are as this machine sees them; the writers make them
    relative to ``shared_root``. None leaves a setting at the job file's default."""

    shared_root: str
    scene_file: str          # a hapticfluid scene .json or a .blend
    cache_dir: str           # the bake's cache folder (on the shared storage)
    output_dir: str          # rendered frames go here (on the shared storage)
    frame_start: int
    frame_end: int
    resolution: int          # cells along the domain's longest edge
    chunk_size: int = 8      # frames per render task
    render_samples: Optional[int] = None
    render_size: Optional[Tuple[int, int]] = None  # pixels
    python_path: Optional[str] = None  # PYTHONPATH on the workers (hapticfluid, hapticfluid_blender)
    python: Optional[str] = None       # the baking Python on the workers
    blender: Optional[str] = None      # the Blender on the workers
    name: str = ""

    def relative_paths(self) -> Dict[str, str]:
        """scene_file, cache_dir and output_dir relative to the shared root (ValueError if not under it)."""
        if not self.shared_root:
            raise ValueError("set the shared root (the folder every farm worker mounts): it is empty")
        if Path(self.scene_file).suffix.lower() not in SCENE_SUFFIXES:
            raise ValueError(f"scene file '{self.scene_file}' must be a hapticfluid scene .json or a .blend")
        if self.chunk_size < 1:
            raise ValueError(f"chunk size must be >= 1 frame, got {self.chunk_size}")
        frame_chunks(self.frame_start, self.frame_end, self.chunk_size)
        return {"scene_file": relative_to_root(self.scene_file, self.shared_root, "scene file"),
                "cache_dir": relative_to_root(self.cache_dir, self.shared_root, "cache folder"),
                "output_dir": relative_to_root(self.output_dir, self.shared_root, "output folder")}

    @property
    def frames(self) -> str:
        return f"{self.frame_start}-{self.frame_end}"


def openjd_parameters(job: FarmJob) -> Dict[str, object]:
    """The OpenJD job parameter values (names as in OPENJD_TEMPLATE), SharedRoot left out: it is
    given where the job runs (``-p SharedRoot=...``), the other paths are relative to it."""
    rel = job.relative_paths()
    values: Dict[str, object] = {"SceneFile": rel["scene_file"], "CacheDir": rel["cache_dir"],
                                 "OutputDir": rel["output_dir"], "Resolution": job.resolution,
                                 "Frames": job.frames, "ChunkSize": job.chunk_size}
    optional = {"RenderSamples": job.render_samples, "PythonPath": job.python_path, "Python": job.python,
                "Blender": job.blender}
    if job.render_size is not None:
        optional.update(RenderWidth=job.render_size[0], RenderHeight=job.render_size[1])
    values.update({k: v for k, v in optional.items() if v is not None})
    return values


def flamenco_settings(job: FarmJob) -> Dict[str, object]:
    """The Flamenco job settings (keys as in FLAMENCO_JOB_TYPE's JOB_TYPE.settings)."""
    rel = job.relative_paths()
    settings: Dict[str, object] = {"shared_root": str(Path(os.path.abspath(job.shared_root)).as_posix()),
                                   "scene_file": rel["scene_file"], "cache_dir": rel["cache_dir"],
                                   "output_dir": rel["output_dir"], "resolution": job.resolution,
                                   "frames": job.frames, "chunk_size": job.chunk_size}
    optional = {"render_samples": job.render_samples, "python_path": job.python_path, "python": job.python,
                "blender": job.blender}
    if job.render_size is not None:
        optional.update(render_width=job.render_size[0], render_height=job.render_size[1])
    settings.update({k: v for k, v in optional.items() if v is not None})
    return settings


def _write_json(path: Path, data: object) -> None:
    atomic_write(path, lambda f: (json.dump(data, f, indent=2, sort_keys=True), f.write("\n")))


def _copy(src: Path, folder: Path, name: Optional[str] = None) -> Path:
    dst = folder / (name or src.name)
    text = template_text(src)
    atomic_write(dst, lambda f: f.write(text))
    return dst


def write_openjd_job(job: FarmJob, folder: "str | os.PathLike") -> Dict[str, object]:
    """Write the OpenJD template and its parameter values into ``folder``, which is then also a
    Deadline Cloud job bundle (template.yaml + parameter_values.json). Returns
    ``{"files": [...], "command": ..., "deadline_command": ...}``: the commands that run the job
    with openjd-cli and submit it to Deadline Cloud, from the shared root."""
    values = openjd_parameters(job)
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    template = _copy(OPENJD_TEMPLATE, out, OPENJD_TEMPLATE_FILE)
    params = out / OPENJD_PARAMETERS_FILE
    _write_json(params, values)
    bundle_values = out / DEADLINE_PARAMETERS_FILE
    _write_json(bundle_values, {"parameterValues": [{"name": k, "value": v} for k, v in values.items()]})
    try:
        shown = Path(relative_to_root(out, job.shared_root, "job folder"))
    except ValueError:
        shown = Path(os.path.abspath(out))
    command = (f"cd {shlex.quote(str(Path(os.path.abspath(job.shared_root))))} && openjd run "
               f"{shlex.quote(str(shown / template.name))} "
               f"-p file://{shlex.quote(str(shown / params.name))} -p SharedRoot=\"$PWD\"")
    deadline = (f"cd {shlex.quote(str(Path(os.path.abspath(job.shared_root))))} && deadline bundle submit "
                f"{shlex.quote(str(shown))} -p SharedRoot=<the shared root as the workers mount it>")
    return {"files": [template, params, bundle_values], "command": command, "deadline_command": deadline}


def write_flamenco_job(job: FarmJob, folder: "str | os.PathLike", priority: int = 50,
                       worker_tag: Optional[str] = None) -> Dict[str, object]:
    """Write Flamenco's job compiler script and a job submission (the body of Flamenco Manager's
    ``POST /api/v3/jobs``) into ``folder``. Returns ``{"files": [...], "command": ...}``."""
    settings = flamenco_settings(job)
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    script = _copy(FLAMENCO_JOB_TYPE, out)
    submission: Dict[str, object] = {
        "name": job.name or f"hapticfluid {Path(job.scene_file).stem}",
        "type": FLAMENCO_JOB_TYPE_NAME,
        "priority": int(priority),
        "submitter_platform": "linux",
        "settings": settings,
        "metadata": {"project": "hapticfluid"},
    }
    if worker_tag:
        submission["worker_tag"] = worker_tag
    body = out / FLAMENCO_JOB_FILE
    _write_json(body, submission)
    command = (f"cp {shlex.quote(str(script))} <flamenco-manager folder>/scripts/{FLAMENCO_JOB_TYPE_NAME}.js "
               f"(once, then restart the Manager); curl -X POST -H 'Content-Type: application/json' "
               f"-d @{shlex.quote(str(body))} http://<manager>:8080/api/v3/jobs")
    return {"files": [script, body], "command": command}
