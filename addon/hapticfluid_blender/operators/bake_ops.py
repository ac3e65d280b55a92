# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake, Resume and Free operators.

Bake/Resume read the Blender scene on the main thread (probe matrix per frame included), then
run ``hapticfluid.bake.bake`` on a worker thread that never touches bpy. Invoked from the UI
they are modal: a timer copies the worker's progress into the scene's status properties and the
window manager's progress bar, shows the Volume object from the first finished frame on and
extends it as frames land; Esc cancels between substeps (complete frames stay, Resume
continues). Run from a script or ``blender --background`` (execute), they wait for the worker.
Errors come back as ``self.report`` and in the status line. Disabling the add-on during a bake
cancels and joins the worker (``shutdown``) and shows what finished.
"""

import logging
import threading

import bpy

from . import modal_guard
from ..bake import blender_scene, cache_plan
from ..properties import roles
from ..render import volume

TIMER_S = 0.2
log = logging.getLogger(__name__)


class _BakeJob:
    """The worker thread and what it shares with the main thread (under a lock)."""

    def __init__(self, bake_scene, resume, scene_name):
        self.scene = bake_scene
        self.resume = resume
        self.scene_name = scene_name  # the Blender scene whose settings it reports into
        self.cancel = threading.Event()
        self.lock = threading.Lock()
        self.progress = None  # latest hapticfluid.bake.BakeProgress
        self.result = None
        self.error = None
        self.shown_last = None  # last frame the Volume object shows (main thread only)
        self.timer = None  # the modal operator's timer, removed by shutdown() if still there
        self.thread = threading.Thread(target=self._run, name="hapticfluid-bake", daemon=True)

    def _run(self):
        from hapticfluid.bake import bake

        try:
            result = bake(self.scene, resume=self.resume, progress=self._on_progress, cancel=self.cancel,
                          log=lambda line: log.info("bake: %s", line))
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

    def settings(self):
        scene = bpy.data.scenes.get(self.scene_name)
        return scene, (roles.settings_of(scene) if scene is not None else None)


_jobs = []  # running bakes (main thread only), so that disabling the add-on can end them


def _show_volume(scene, job, last_frame, collection=None):
    """Create or extend the Volume object to frames frame_start..last_frame; keep the domain's
    display as it was (restored by Free) and show it as a wire frame."""
    from hapticfluid.bake import frame_path

    settings = roles.settings_of(scene)
    bake_scene = job.scene
    first = str(frame_path(bake_scene.cache_dir, bake_scene.frame_start))
    if settings.cache_dir.startswith("//") and bpy.data.filepath:
        first = bpy.path.relpath(first)
    settings.volume_object = volume.show_sequence(
        scene, first, bake_scene.frame_start, last_frame - bake_scene.frame_start + 1,
        settings.density_scale, existing=settings.volume_object, collection=collection)
    job.shown_last = last_frame
    domain = settings.domain
    if domain is not None and not settings.domain_display_saved:  # the smoke shows the box now
        settings.domain_display_type = domain.display_type
        settings.domain_hide_render = domain.hide_render
        settings.domain_display_saved = True
        domain.display_type = "WIRE"
        domain.hide_render = True


def _finish_job(job, collection=None):
    """Main thread, after the worker ended: status, Volume, flags. Returns (level, text)."""
    if job in _jobs:
        _jobs.remove(job)
    scene, settings = job.settings()
    progress, result, error = job.snapshot()
    if settings is None:
        return "WARNING", "the scene of the bake was removed"
    settings.is_baking = False
    if error is not None:
        settings.status = f"bake failed: {error}"
        return "ERROR", settings.status
    if result.last_frame is not None and result.last_frame != job.shown_last:
        _show_volume(scene, job, result.last_frame, collection)
    per = f", {result.seconds_per_frame:.2f} s/frame" if result.frames_written else ""
    note = blender_scene.cache_note(settings)
    why = f" ({result.plan.text})" if job.resume and result.plan is not None else ""
    settings.status = (f"bake {result.status}: {result.frames_written} frame(s){per}; last complete frame "
                       f"{result.last_frame}{why}" + (f"; {note}" if note else ""))
    settings.progress = progress.fraction if progress is not None else settings.progress
    if not bpy.app.background:  # the panel's plan and the Timeline's bar (scripts call refresh themselves)
        cache_plan.refresh(scene)
    return ("WARNING" if result.status == "cancelled" else "INFO"), settings.status


# Disabling the add-on during a UI bake: its timer keeps ticking for modal_guard.DROP_S (Blender
# 4.3's crash in modal_handler_add; see modal_guard).
HANDLER_DROP_S = modal_guard.DROP_S


def shutdown():
    """The add-on is being disabled: cancel and join every running bake, end its progress, and
    show what finished (the complete frames; Resume continues after them). A modal bake's timer
    ends HANDLER_DROP_S later (modal_guard)."""
    wm = bpy.context.window_manager
    for job in list(_jobs):
        job.cancel.set()
        job.thread.join()
        if job.timer is not None and wm is not None:
            modal_guard.keep_ticking(job.timer)
            wm.progress_end()
            job.timer = None
        _finish_job(job)
        _scene, settings = job.settings()
        if settings is not None and job.error is None:
            settings.status = "the add-on was disabled during the bake: " + settings.status


class _IdleOnly:
    """poll for the bake operators: only while the scene has bake settings and no bake runs."""

    @classmethod
    def poll(cls, context):
        if context.scene is None or not hasattr(bpy.types.Object, "hapticfluid"):
            return False
        return not roles.settings_of(context.scene).is_baking


class _BakeBase(_IdleOnly):
    bl_options = {"REGISTER"}
    resume = False

    def _start(self, context):
        """Main thread: scene -> bake scene, then the worker. Returns the job or None (reported,
        and written to the status line so that it does not keep the previous bake's text)."""
        settings = roles.settings_of(context.scene)
        try:
            import hapticfluid  # noqa: F401  (a clear error if the package is missing)
            from hapticfluid.bake import scene_from_dict

            data = blender_scene.scene_dict(context.scene, settings)
            bake_scene = scene_from_dict(data)
        except ImportError as exc:
            return self._refuse(settings, f"install the hapticfluid Python package (see README) or add it to "
                                          f"PYTHONPATH (read by Blender 4.x only with --python-use-system-env): it is not "
                                          f"importable in Blender ({exc})")
        except (blender_scene.SceneError, ValueError) as exc:
            return self._refuse(settings, str(exc))
        job = _BakeJob(bake_scene, self.resume, context.scene.name)
        # what the cache is made from once this bake ends, for "cache out of date" (a Resume after a
        # changed setting re-bakes every frame with it)
        settings.baked_inputs = cache_plan.inputs_json(context.scene, settings)
        settings.is_baking = True
        settings.progress = 0.0
        note = blender_scene.cache_note(settings)
        settings.status = ("resuming..." if self.resume else "baking...") + (f" ({note})" if note else "")
        _jobs.append(job)
        job.thread.start()
        return job

    def _refuse(self, settings, message):
        if settings.domain is not None:  # else there is no domain to hold a status
            settings.status = f"bake not started: {message}"
        self.report({"ERROR"}, message)
        return None

    def _finish(self, job):
        level, text = _finish_job(job, self._collection)
        self.report({level}, text)
        return {"CANCELLED"} if level == "ERROR" else {"FINISHED"}

    # -- synchronous (scripts, --background) --------------------------------------------------
    def execute(self, context):
        self._collection = context.view_layer.active_layer_collection.collection
        job = self._start(context)
        if job is None:
            return {"CANCELLED"}
        try:
            job.thread.join()
        except KeyboardInterrupt:
            job.cancel.set()
            job.thread.join()
        return self._finish(job)

    # -- modal (UI) -----------------------------------------------------------------------------
    def invoke(self, context, _event):
        if modal_guard.pending():
            self._refuse(roles.settings_of(context.scene), modal_guard.REFUSAL.format(what="bake or live session"))
            return {"CANCELLED"}
        self._collection = context.view_layer.active_layer_collection.collection
        self._job = self._start(context)
        if self._job is None:
            return {"CANCELLED"}
        wm = context.window_manager
        self._job.timer = wm.event_timer_add(TIMER_S, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        job = self._job
        scene, settings = job.settings()
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel.set()
            if settings is not None:
                settings.status = "cancelling after this substep..."
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}  # the UI stays live while the worker bakes
        wm = context.window_manager
        progress, _result, _error = job.snapshot()
        if progress is not None and settings is not None:
            settings.progress = progress.fraction
            if not job.cancel.is_set():
                settings.status = progress.text()
            wm.progress_update(int(100 * progress.fraction))
            last = progress.frame_start + progress.frames_done - 1 if progress.frames_done else None
            if last is not None and last != job.shown_last:  # the frames show up as they land
                _show_volume(scene, job, last, self._collection)
        for area in context.screen.areas if context.screen else ():
            if area.type in ("PROPERTIES", "VIEW_3D", "DOPESHEET_EDITOR"):  # the last: the timeline's cache bar
                area.tag_redraw()
        if job.thread.is_alive():
            return {"RUNNING_MODAL"}
        wm.event_timer_remove(job.timer)
        job.timer = None
        wm.progress_end()
        return self._finish(job)


class HAPTICFLUID_OT_bake(_BakeBase, bpy.types.Operator):
    """Bake the probe's animation into an OpenVDB smoke cache (replaces the cache's frames)"""

    bl_idname = "hapticfluid.bake"
    bl_label = "Bake"


class HAPTICFLUID_OT_bake_resume(_BakeBase, bpy.types.Operator):
    """Bake what the cache lacks: keep every frame that still holds what the scene bakes and re-bake from the
    first missing, damaged or changed frame (the probe's keys), starting at the checkpoint before it; continues a
    cancelled bake, extends one after End was raised, and re-bakes every frame after a changed setting"""

    bl_idname = "hapticfluid.bake_resume"
    bl_label = "Resume"
    resume = True


class HAPTICFLUID_OT_bake_free(_IdleOnly, bpy.types.Operator):
    """Delete the bake's frames, checkpoint and manifest from the cache folder, remove the Volume
    object showing them and restore the domain's display"""

    bl_idname = "hapticfluid.bake_free"
    bl_label = "Free"
    bl_options = {"REGISTER"}

    def invoke(self, context, event):
        return context.window_manager.invoke_confirm(self, event)

    def execute(self, context):
        settings = roles.settings_of(context.scene)
        if settings.domain is None:
            self.report({"ERROR"}, f"Give a mesh the Domain role ({roles.PHYSICS_PATH}): Free deletes the cache of the "
                                   "scene's domain, and no object has that role")
            return {"CANCELLED"}
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
        volume.remove(settings.volume_object)
        settings.volume_object = None
        domain = settings.domain
        if domain is not None and settings.domain_display_saved:
            domain.display_type = settings.domain_display_type
            domain.hide_render = settings.domain_hide_render
        settings.domain_display_saved = False
        settings.baked_inputs = ""
        settings.progress = 0.0
        settings.status = f"freed {removed} file(s) in {folder}"
        self.report({"INFO"}, settings.status)
        return {"FINISHED"}
