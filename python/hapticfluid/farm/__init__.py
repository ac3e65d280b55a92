# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake on a farm: the bake as a job for Open Job Description (Deadline Cloud, ``openjd``) and
Flamenco, with the paths on shared storage.

A fluid bake is sequential in time, so a job bakes on a GPU worker, resumable per frame (a
re-queued task continues where the last one died), and renders chunks of the baked frames in
tasks that depend on the bake. The bake is one task, or with a bake chunk size a chain of
contiguous chunk tasks (frames 1-24, 25-48, ...), each continuing from the checkpoint the one
before left on the shared storage, with the render tasks of each chunk depending on that chunk
alone. The two job files ship in this package:

* ``openjd_bake_render.yaml``: an OpenJD ``jobtemplate-2023-09`` template (TASK_CHUNKING
  extension, a ``CHUNK[INT]`` task parameter for the render chunks);
* ``hapticfluid-bake-render.js``: a Flamenco job compiler script (a custom job type).

OpenJD has dependencies between steps only (the tasks of a step are independent), so a chained
bake is one Bake step and one Render step per chunk: :func:`chained_openjd_template` writes them
from the shipped template's two steps. Flamenco tasks have dependencies of their own: the job
type builds the chain itself from its ``bake_chunk_size`` setting.

:func:`write_openjd_job` and :func:`write_flamenco_job` write them for one scene into a folder,
with every path made relative to the farm's shared root; the worker-side commands are
``python3 -m hapticfluid.farm bake`` (:mod:`hapticfluid.farm.bake_step`) and Blender running the
add-on's ``render_main`` (BLENDER_RENDER_EXPR; its arguments: :mod:`hapticfluid.farm.chunks`). See docs/FARM.md.
"""

from __future__ import annotations

import json
import os
import re
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
# The add-on's command-line entry points, run inside Blender (--python-expr): the functions of its
# package that the farm's tasks call, so the package never names the add-on's modules. The job
# files (OPENJD_TEMPLATE, FLAMENCO_JOB_TYPE) spell the render one out (tests/python/test_farm.py
# checks they agree).
BLENDER_BAKE_EXPR = "import hapticfluid_blender as a; a.bake_main()"
BLENDER_RENDER_EXPR = "import hapticfluid_blender as a; a.render_main()"


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


def bake_chunks(first: int, last: int, bake_chunk_size: int) -> List[Tuple[int, int]]:
    """The bake's chunk tasks over frames first..last: one chunk when ``bake_chunk_size`` is 0
    (one bake task) or covers the range, else contiguous chunks of ``bake_chunk_size`` frames."""
    if bake_chunk_size < 0:
        raise ValueError(f"bake chunk size must be 0 (one bake task) or a number of frames >= 1, got {bake_chunk_size}")
    if bake_chunk_size == 0:
        return frame_chunks(first, last, last - first + 1)
    return frame_chunks(first, last, bake_chunk_size)


def _replace_once(text: str, old: str, new: str, where: str) -> str:
    if text.count(old) != 1:
        raise RuntimeError(f"the shipped OpenJD template ({OPENJD_TEMPLATE.name}) no longer has exactly one "
                           f"{old.strip()!r} in {where}: update hapticfluid.farm.chained_openjd_template with it")
    return text.replace(old, new)


def _yaml_quote(text: str) -> str:
    return json.dumps(text)  # a JSON string is a YAML double-quoted scalar


def chained_openjd_template(text: str, chunks: List[Tuple[int, int]], frames: str) -> str:
    """The OpenJD template of a chained bake, made from the shipped template's text: for each
    chunk (first, last), a step "Bake FIRST-LAST" (``--until LAST``, depending on the chunk
    before) and a step "Render FIRST-LAST" (its CHUNK[INT] range is that chunk, depending on that
    chunk's bake only). OpenJD dependencies are between steps, hence one step per chunk. The
    ``Frames`` parameter is left out: the steps fix the frames (write the job again to change
    them). Line edits, each checked to apply exactly once (RuntimeError if the shipped template
    changed shape), so the template stays the single source of the steps' commands and no YAML
    library is needed (Blender's Python has none)."""
    if len(chunks) < 2:
        raise ValueError(f"a chained bake needs at least 2 chunks, got {len(chunks)}: write the shipped template")
    head, sep, steps = text.partition("\nsteps:\n")
    if not sep:
        raise RuntimeError(f"the shipped OpenJD template ({OPENJD_TEMPLATE.name}) has no 'steps:' section")
    frames_param = re.search(r"^  - name: Frames\n(?:    .*\n)+", head, flags=re.M)
    if frames_param is None:
        raise RuntimeError(f"the shipped OpenJD template ({OPENJD_TEMPLATE.name}) has no Frames parameter")
    head = head[:frames_param.start()] + head[frames_param.end():]
    blocks = re.split(r"(?m)^(?=  - name: )", steps)
    if len(blocks) != 3 or blocks[0].strip() or not blocks[1].startswith("  - name: Bake\n") \
            or not blocks[2].startswith("  - name: Render\n"):
        raise RuntimeError(f"the shipped OpenJD template ({OPENJD_TEMPLATE.name}) must have the steps Bake, "
                           "then Render: update hapticfluid.farm.chained_openjd_template with it")
    bake, render = blocks[1], blocks[2]
    scene_arg = re.search(r'(?m)^( +)- "\{\{Param\.SceneFile\}\}"\n', bake)
    if scene_arg is None:
        raise RuntimeError(f"the shipped OpenJD template's Bake step ({OPENJD_TEMPLATE.name}) has no "
                           "SceneFile argument to add --until after")
    indent = scene_arg.group(1)
    out = [f"# Written by hapticfluid.farm from {OPENJD_TEMPLATE.name}: frames {frames} baked in {len(chunks)} "
           "chained chunks,\n# one Bake and one Render step per chunk (write the job again to change the "
           "frames or the chunks).\n", head, sep]
    previous = None
    for first, last in chunks:
        name = f"{first}-{last}"
        b = _replace_once(bake, "  - name: Bake\n", f"  - name: {_yaml_quote('Bake ' + name)}\n", "the Bake step")
        about = (f"Bakes frames {name} on a GPU worker" + (
            f", continuing from the checkpoint Bake {previous} left in the cache" if previous else
            " (and any frames of the scene before them)") + "; a re-queued task resumes from its latest checkpoint.")
        b = re.sub(r"(?m)^    description: .*\n", lambda _m: f"    description: {_yaml_quote(about)}\n", b, count=1)
        if previous is not None:
            b = b.replace("\n", f"\n    dependencies:\n      - dependsOn: {_yaml_quote('Bake ' + previous)}\n", 1)
        b = b.replace(scene_arg.group(0), scene_arg.group(0) + f'{indent}- "--until"\n{indent}- "{last}"\n', 1)
        r = _replace_once(render, "  - name: Render\n", f"  - name: {_yaml_quote('Render ' + name)}\n",
                          "the Render step")
        r = _replace_once(r, "- dependsOn: Bake\n", f"- dependsOn: {_yaml_quote('Bake ' + name)}\n", "the Render step")
        r = _replace_once(r, 'range: "{{Param.Frames}}"', f'range: "{name}"', "the Render step")
        out += [b, r]
        previous = name
    return "".join(out)


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
    bake_chunk_size: int = 0  # frames per bake task, chained; 0: one bake task
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
        self.bake_chunks()
        return {"scene_file": relative_to_root(self.scene_file, self.shared_root, "scene file"),
                "cache_dir": relative_to_root(self.cache_dir, self.shared_root, "cache folder"),
                "output_dir": relative_to_root(self.output_dir, self.shared_root, "output folder")}

    @property
    def frames(self) -> str:
        return f"{self.frame_start}-{self.frame_end}"

    def bake_chunks(self) -> List[Tuple[int, int]]:
        """The bake tasks' frame ranges: [(frame_start, frame_end)] for one bake task."""
        return bake_chunks(self.frame_start, self.frame_end, self.bake_chunk_size)

    @property
    def chained(self) -> bool:
        """True when the bake is more than one chunk task."""
        return len(self.bake_chunks()) > 1


def openjd_parameters(job: FarmJob) -> Dict[str, object]:
    """The OpenJD job parameter values (names as in OPENJD_TEMPLATE), SharedRoot left out: it is
    given where the job runs (``-p SharedRoot=...``), the other paths are relative to it. A
    chained bake's template has no Frames parameter (its steps fix the frames)."""
    rel = job.relative_paths()
    values: Dict[str, object] = {"SceneFile": rel["scene_file"], "CacheDir": rel["cache_dir"],
                                 "OutputDir": rel["output_dir"], "Resolution": job.resolution,
                                 "Frames": job.frames, "ChunkSize": job.chunk_size}
    if job.chained:
        del values["Frames"]
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
                                   "frames": job.frames, "chunk_size": job.chunk_size,
                                   "bake_chunk_size": job.bake_chunk_size}
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
    Deadline Cloud job bundle (template.yaml + parameter_values.json). The template is the
    shipped one, or for a chained bake :func:`chained_openjd_template` of it. Returns
    ``{"files": [...], "command": ..., "deadline_command": ...}``: the commands that run the job
    with openjd-cli and submit it to Deadline Cloud, from the shared root."""
    values = openjd_parameters(job)
    chunks = job.bake_chunks()
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    if len(chunks) > 1:
        text = chained_openjd_template(template_text(OPENJD_TEMPLATE), chunks, job.frames)
        template = out / OPENJD_TEMPLATE_FILE
        atomic_write(template, lambda f: f.write(text))
    else:
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
