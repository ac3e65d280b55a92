"""Bake, Resume and Free operators.

Bake/Resume read the Blender scene on the main thread (probe matrix per frame included), then
run ``hapticfluid.bake.bake`` on a worker thread that never touches bpy. Invoked from the UI
they are modal: a timer copies the worker's progress into the scene's status properties and the
window manager's progress bar, Esc cancels between substeps (complete frames stay, Resume
continues). Run from a script or ``blender --background`` (execute), they wait for the worker.
Errors come back as ``self.report``.
"""

import threading

import bpy

from . import blender_scene, volume

TIMER_S = 0.2


class _BakeJob:
    """The worker thread and what it shares with the main thread (under a lock)."""

    def __init__(self, bake_scene, resume):
        self.scene = bake_scene
        self.resume = resume
        self.cancel = threading.Event()
        self.lock = threading.Lock()
        self.progress = None  # latest hapticfluid.bake.BakeProgress
        self.result = None
        self.error = None
        self.thread = threading.Thread(target=self._run, name="hapticfluid-bake", daemon=True)

    def _run(self):
        from hapticfluid.bake import bake

        try:
            result = bake(self.scene, resume=self.resume, progress=self._on_progress, cancel=self.cancel,
                          log=lambda line: print("hapticfluid bake:", line, flush=True))
            with self.lock:
                self.result = result
        except Exception as exc:  # reported on the main thread
            with self.lock:
                self.error = f"{type(exc).__name__}: {exc}" if not str(exc) else str(exc)

    def _on_progress(self, p):
        with self.lock:
            self.progress = p

    def snapshot(self):
        with self.lock:
            return self.progress, self.result, self.error


class _IdleOnly:
    """poll for the bake operators: only while the scene has bake settings and no bake runs."""

    @classmethod
    def poll(cls, context):
        s = getattr(context.scene, "hapticfluid_bake", None)
        return s is not None and not s.is_baking


class _BakeBase(_IdleOnly):
    bl_options = {"REGISTER"}
    resume = False

    def _start(self, context):
        """Main thread: scene -> bake scene, then the worker. Returns the job or None (reported)."""
        settings = context.scene.hapticfluid_bake
        try:
            import hapticfluid  # noqa: F401  (a clear error if the package is missing)
            from hapticfluid.bake import scene_from_dict

            data = blender_scene.scene_dict(context.scene, settings)
            bake_scene = scene_from_dict(data)
        except ImportError as exc:
            self.report({"ERROR"}, f"the hapticfluid Python package is not importable in Blender ({exc}); "
                                   "install it (see README) or add it to PYTHONPATH")
            return None
        except (blender_scene.SceneError, ValueError) as exc:
            self.report({"ERROR"}, str(exc))
            return None
        job = _BakeJob(bake_scene, self.resume)
        settings.is_baking = True
        settings.progress = 0.0
        settings.status = "resuming..." if self.resume else "baking..."
        job.thread.start()
        return job

    def _finish(self, context, job):
        settings = context.scene.hapticfluid_bake
        settings.is_baking = False
        progress, result, error = job.snapshot()
        if error is not None:
            settings.status = f"bake failed: {error}"
            self.report({"ERROR"}, error)
            return {"CANCELLED"}
        if result.last_frame is not None:
            self._show_volume(context, job.scene, result.last_frame)
        per = f", {result.seconds_per_frame:.2f} s/frame" if result.frames_written else ""
        settings.status = (f"bake {result.status}: {result.frames_written} frame(s){per}; last complete frame "
                           f"{result.last_frame}")
        settings.progress = progress.fraction if progress is not None else settings.progress
        self.report({"WARNING"} if result.status == "cancelled" else {"INFO"}, settings.status)
        return {"FINISHED"}

    def _show_volume(self, context, bake_scene, last_frame):
        from hapticfluid.bake import frame_path

        settings = context.scene.hapticfluid_bake
        first = str(frame_path(bake_scene.cache_dir, bake_scene.frame_start))
        if settings.cache_dir.startswith("//") and bpy.data.filepath:
            first = bpy.path.relpath(first)
        settings.volume_object = volume.show_sequence(
            context.scene, first, bake_scene.frame_start, last_frame - bake_scene.frame_start + 1,
            settings.density_scale, existing=settings.volume_object)
        if settings.domain is not None:  # the smoke shows the box now: keep the mesh as a wire frame
            settings.domain.display_type = "WIRE"
            settings.domain.hide_render = True

    # -- synchronous (scripts, --background) --------------------------------------------------
    def execute(self, context):
        job = self._start(context)
        if job is None:
            return {"CANCELLED"}
        try:
            job.thread.join()
        except KeyboardInterrupt:
            job.cancel.set()
            job.thread.join()
        return self._finish(context, job)

    # -- modal (UI) -----------------------------------------------------------------------------
    def invoke(self, context, _event):
        self._job = self._start(context)
        if self._job is None:
            return {"CANCELLED"}
        wm = context.window_manager
        self._timer = wm.event_timer_add(TIMER_S, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            self._job.cancel.set()
            context.scene.hapticfluid_bake.status = "cancelling after this substep..."
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}  # the UI stays live while the worker bakes
        wm = context.window_manager
        progress, _result, _error = self._job.snapshot()
        settings = context.scene.hapticfluid_bake
        if progress is not None:
            settings.progress = progress.fraction
            if not self._job.cancel.is_set():
                settings.status = progress.text()
            wm.progress_update(int(100 * progress.fraction))
        for area in context.screen.areas if context.screen else ():
            if area.type in ("PROPERTIES", "VIEW_3D"):
                area.tag_redraw()
        if self._job.thread.is_alive():
            return {"RUNNING_MODAL"}
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        return self._finish(context, self._job)


class HAPTICFLUID_OT_bake(_BakeBase, bpy.types.Operator):
    """Bake the probe's animation into an OpenVDB smoke cache (replaces the cache's frames)"""

    bl_idname = "hapticfluid.bake"
    bl_label = "Bake"


class HAPTICFLUID_OT_bake_resume(_BakeBase, bpy.types.Operator):
    """Continue a cancelled or interrupted bake after its last complete frame"""

    bl_idname = "hapticfluid.bake_resume"
    bl_label = "Resume"
    resume = True


class HAPTICFLUID_OT_bake_free(_IdleOnly, bpy.types.Operator):
    """Delete the bake's frames, checkpoint and manifest from the cache folder"""

    bl_idname = "hapticfluid.bake_free"
    bl_label = "Free"
    bl_options = {"REGISTER"}

    def execute(self, context):
        settings = context.scene.hapticfluid_bake
        try:
            from hapticfluid.bake import BakeError, free_cache

            folder = blender_scene.cache_folder(settings)
        except (ImportError, blender_scene.SceneError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        try:
            removed = free_cache(folder)  # 0 if the folder does not exist
        except (BakeError, OSError) as exc:  # frames that are not ours, or a file we may not delete
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        settings.progress = 0.0
        settings.status = f"freed {removed} file(s) in {folder}"
        self.report({"INFO"}, settings.status)
        return {"FINISHED"}
