# SPDX-License-Identifier: GPL-3.0-or-later
"""Write Farm Job: the current scene's bake as a farm job (OpenJD and/or Flamenco), on shared storage.

The operator exports the scene as a hapticfluid scene .json into the job folder (the bake task
then needs no Blender, only Python and the hapticfluid package on a GPU worker), writes the job
files next to it with every path relative to the shared root the user sets, and reports the
command a farm user runs to submit it. Its settings live on the scene as
``scene.hapticfluid_farm``; this module registers them itself (the operator's register()), so the
add-on lists only the operator.
"""

import json
import os

import bpy
from bpy.props import EnumProperty, IntProperty, PointerProperty, StringProperty

from ..bake import blender_scene
from ..properties import roles

SCENE_FILE = "hapticfluid_scene.json"


class HapticFluidFarmSettings(bpy.types.PropertyGroup):
    shared_root: StringProperty(
        name="Shared Root", subtype="DIR_PATH", default="",
        description="Folder of the shared storage that every farm worker mounts; the job's paths are "
                    "written relative to it (the cache, job and output folders must lie under it)")
    job_dir: StringProperty(
        name="Job Folder", subtype="DIR_PATH", default="//farm_job",
        description="Where the job files and the exported scene go (under the shared root); // is the "
                    ".blend's folder")
    output_dir: StringProperty(
        name="Render Output", subtype="DIR_PATH", default="//farm_renders",
        description="Folder of the rendered frames, frame_####.png (under the shared root)")
    chunk_size: IntProperty(name="Chunk Size", default=8, min=1, max=150,
                            description="Frames rendered by one render task (OpenJD allows at most 150)")
    bake_chunk_size: IntProperty(
        name="Bake Chunk", default=0, min=0, max=100000,
        description="Frames per bake task: the bake becomes a chain of tasks (frames 1-24, 25-48, ...), each "
                    "continuing from the checkpoint the one before left in the cache, so a preempted worker loses "
                    "at most one chunk and a chunk's renders start as soon as it is baked. 0: one bake task")
    job_kind: EnumProperty(
        name="Farm", default="BOTH",
        items=(("OPENJD", "OpenJD", "Open Job Description template + parameters (openjd run, Deadline Cloud)"),
               ("FLAMENCO", "Flamenco", "Flamenco job type script + job submission"),
               ("BOTH", "Both", "Write the OpenJD and the Flamenco job files")),
        description="Which farm's job files to write")
    python_path: StringProperty(
        name="Worker PYTHONPATH", default="",
        description="PYTHONPATH on the workers: folders holding the hapticfluid package and the add-on "
                    "(empty when both are installed there)")
    submit_command: StringProperty(name="Submit", default="",
                                   description="The command that submits the last job written")


def _folder(path: str, what: str) -> str:
    if path.startswith("//") and not bpy.data.filepath:
        raise ValueError(f"Save the .blend first or make the {what} absolute: '{path}' is relative to the .blend")
    return os.path.normpath(bpy.path.abspath(path))


def _under(path: str, root: str, what: str, prop: str) -> None:
    from hapticfluid.farm import relative_to_root

    try:
        relative_to_root(path, root, what)
    except ValueError:
        raise ValueError(f"Choose a {prop} under the shared root '{root}': the {what} '{path}' is outside it, "
                         "so the workers could not reach it") from None


def write_job(scene) -> dict:
    """Write the job for ``scene``; returns {"files": [...], "commands": [...]}. ValueError or
    blender_scene.SceneError with the fix first on bad input."""
    from hapticfluid.farm import FarmJob, write_flamenco_job, write_openjd_job
    from hapticfluid.files import atomic_write

    settings, farm = roles.settings_of(scene), scene.hapticfluid_farm
    if not farm.shared_root.strip():
        raise ValueError("Set the Shared Root (the folder every farm worker mounts) in the Farm box: it is empty")
    root = _folder(farm.shared_root, "shared root")
    if not os.path.isdir(root):
        raise ValueError(f"Choose an existing folder as the Shared Root: '{root}' does not exist")
    data = blender_scene.scene_dict(scene, settings)
    cache = data["cache"]["directory"]
    job_dir = _folder(farm.job_dir, "job folder")
    output = _folder(farm.output_dir, "render output folder")
    _under(cache, root, "cache folder", "Cache Folder")
    _under(job_dir, root, "job folder", "Job Folder")
    _under(output, root, "render output folder", "Render Output folder")

    for folder in (job_dir, cache, output):  # on the shared storage, ready for the workers
        os.makedirs(folder, exist_ok=True)
    data["cache"]["directory"] = os.path.relpath(cache, job_dir)  # valid wherever the storage is mounted
    scene_file = os.path.join(job_dir, SCENE_FILE)
    atomic_write(scene_file, lambda f: json.dump(data, f, indent=1))
    job = FarmJob(shared_root=root, scene_file=scene_file, cache_dir=cache, output_dir=output,
                  frame_start=settings.frame_start, frame_end=settings.frame_end, resolution=settings.resolution,
                  chunk_size=farm.chunk_size, bake_chunk_size=farm.bake_chunk_size, python_path=farm.python_path or None,
                  name=f"hapticfluid {os.path.splitext(os.path.basename(bpy.data.filepath))[0] or scene.name}")
    files, commands = [scene_file], []
    if farm.job_kind in ("OPENJD", "BOTH"):
        written = write_openjd_job(job, job_dir)
        files += written["files"]
        commands += [written["command"], written["deadline_command"]]
    if farm.job_kind in ("FLAMENCO", "BOTH"):
        written = write_flamenco_job(job, job_dir)
        files += written["files"]
        commands.append(written["command"])
    return {"files": [str(f) for f in files], "commands": commands}


class HAPTICFLUID_OT_write_farm_job(bpy.types.Operator):
    """Write the bake (then chunked renders) as a farm job: OpenJD template + parameters and/or a
    Flamenco job, paths relative to the shared root; reports the command that submits it"""

    bl_idname = "hapticfluid.write_farm_job"
    bl_label = "Write Farm Job"
    bl_options = {"REGISTER"}

    @classmethod
    def register(cls):  # called by bpy.utils.register_class: the settings come with the operator
        bpy.utils.register_class(HapticFluidFarmSettings)
        bpy.types.Scene.hapticfluid_farm = PointerProperty(type=HapticFluidFarmSettings)

    @classmethod
    def unregister(cls):
        del bpy.types.Scene.hapticfluid_farm
        bpy.utils.unregister_class(HapticFluidFarmSettings)

    def execute(self, context):
        try:
            import hapticfluid.farm  # noqa: F401  (a clear error if the package is missing)
        except ImportError as exc:
            self.report({"ERROR"}, f"Install the hapticfluid Python package where Blender finds it: {exc}")
            return {"CANCELLED"}
        try:
            result = write_job(context.scene)
        except (ValueError, blender_scene.SceneError, OSError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        context.scene.hapticfluid_farm.submit_command = result["commands"][0]
        self.report({"INFO"}, f"wrote {len(result['files'])} job files; submit with: " + " | ".join(result["commands"]))
        return {"FINISHED"}


def draw(layout, context):
    """The Farm box of the bake panel."""
    farm = getattr(context.scene, "hapticfluid_farm", None)
    if farm is None:
        return
    box = layout.box()
    box.label(text="Farm", icon="NETWORK_DRIVE")
    col = box.column()
    for name in ("shared_root", "job_dir", "output_dir", "chunk_size", "bake_chunk_size", "job_kind", "python_path"):
        col.prop(farm, name)
    col.operator(HAPTICFLUID_OT_write_farm_job.bl_idname, icon="EXPORT")
    if farm.submit_command:
        col.label(text=farm.submit_command)
