# SPDX-License-Identifier: GPL-3.0-or-later
"""Which baked frames still hold what the scene would bake now: the package's re-bake plan
(``hapticfluid.bake.rebake_plan``) for the Blender scene, kept per scene for the panel and the
Timeline's cache bar.

The plan compares the probe's (and a moving source's) world matrix at every frame with what each
baked frame consumed, so making it reads the animation with ``frame_set`` on every frame of the
range (as the bake does): too slow for a panel's draw. It is made again after the scene changes
(a depsgraph update of the domain, the probe, the source or an Action), once the changes have
paused for REFRESH_DELAY_S, and after every bake; never while the timeline plays, a bake runs or
a live session runs (frame_set would move their frame), nor in background mode (no timers run
there: scripts and tests call refresh() themselves)."""

import logging

import bpy

from ..properties import roles

REFRESH_DELAY_S = 0.5
log = logging.getLogger(__name__)

_plans = {}  # scene name -> Entry
_pending = set()  # scene names whose plan is out of date
_refreshing = False  # frame_set inside refresh() updates the depsgraph: not a change to react to
_frames = {}  # scene name -> the frame of its last depsgraph update (playback is no edit)


class Entry:
    """A scene's plan as the UI shows it: the plan's line, its kind, and the Timeline's runs
    [(first, last, state)] with state 'baked', 'outdated' or 'missing'; or why there is none."""

    def __init__(self, text="", kind="", runs=(), problem=""):
        self.text, self.kind, self.runs, self.problem = text, kind, tuple(runs), problem


def get(scene):
    """The scene's last plan (an Entry), or None if none was made since it changed."""
    return _plans.get(scene.name) if scene is not None else None


def current(scene):
    """The scene's last plan while it still applies: None also when a bake setting changed since
    the bake (object_props.changed_cache_inputs, known at once, while the plan is made again only
    after the edits pause), since that outdates every frame, as the panel's warning says."""
    from ..properties import object_props

    entry = get(scene)
    if entry is None or object_props.changed_cache_inputs(scene, roles.settings_of(scene)):
        return None
    return entry


def refresh(scene):
    """Make the scene's plan now (main thread). Returns the Entry (also kept for get())."""
    global _refreshing
    _pending.discard(scene.name)
    settings = roles.settings_of(scene)
    if settings.domain is None:
        _plans.pop(scene.name, None)
        return None
    try:
        from hapticfluid.bake import rebake_plan, scene_from_dict
        from hapticfluid.bake.plan import frame_states

        from . import blender_scene

        _refreshing = True
        try:
            data = blender_scene.scene_dict(scene, settings)
        finally:
            _refreshing = False
        bake_scene = scene_from_dict(data)
        plan = rebake_plan(bake_scene, check_files=False)
        entry = Entry(plan.text, plan.kind, frame_states(bake_scene, plan))
    except Exception as exc:  # a scene the bake would refuse: the bake says it in full when pressed
        entry = Entry(problem=str(exc))
    _plans[scene.name] = entry
    _tag_redraw()
    return entry


def invalidate(scene):
    """Make the scene's plan again after REFRESH_DELAY_S (UI only); the old one shows meanwhile."""
    _pending.add(scene.name)
    if not bpy.app.background and not bpy.app.timers.is_registered(_on_timer):
        bpy.app.timers.register(_on_timer, first_interval=REFRESH_DELAY_S)


def _busy(scene):
    wm = bpy.context.window_manager
    playing = any(w.screen is not None and w.screen.is_animation_playing for w in (wm.windows if wm else ()))
    live = getattr(scene, "hapticfluid_live", None)
    return playing or roles.settings_of(scene).is_baking or bool(live and live.is_running)


def _on_timer():
    for name in list(_pending):
        scene = bpy.data.scenes.get(name)
        if scene is None:
            _pending.discard(name)
            continue
        if _busy(scene):
            return REFRESH_DELAY_S  # again when the timeline stops, the bake or the session ends
        refresh(scene)
    return None


def _watched(scene):
    s = roles.settings_of(scene)
    return {obj for obj in (s.domain, s.probe, s.source) if obj is not None}


@bpy.app.handlers.persistent
def on_depsgraph_update(scene, depsgraph):
    """depsgraph_update_post: an edit of the domain, probe, source or any Action outdates the plan;
    a new frame (playback, scrubbing) moves animated objects but changes nothing baked."""
    if _refreshing or scene is None or scene.name in _pending or scene.name not in _plans:
        return  # (no plan yet: one is made after a bake or on load; nothing to outdate before)
    frame, _frames[scene.name] = _frames.get(scene.name), scene.frame_current
    if frame is not None and frame != scene.frame_current:
        return
    watched = {obj.name for obj in _watched(scene)}
    if not watched:
        return
    for update in depsgraph.updates:
        target = update.id
        if isinstance(target, bpy.types.Action) or (isinstance(target, bpy.types.Object) and target.name in watched):
            invalidate(scene)
            return


@bpy.app.handlers.persistent
def on_load(_filepath=None):
    _plans.clear()
    _pending.clear()
    _frames.clear()
    for scene in bpy.data.scenes:
        if roles.settings_of(scene).domain is not None:
            invalidate(scene)


def _tag_redraw():
    wm = bpy.context.window_manager if bpy.context else None
    for window in wm.windows if wm else ():
        for area in window.screen.areas:
            if area.type in ("PROPERTIES", "DOPESHEET_EDITOR"):
                area.tag_redraw()


def attach():
    if on_depsgraph_update not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(on_depsgraph_update)
    if on_load not in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.append(on_load)


def detach():
    for handlers, fn in ((bpy.app.handlers.depsgraph_update_post, on_depsgraph_update),
                         (bpy.app.handlers.load_post, on_load)):
        if fn in handlers:
            handlers.remove(fn)
    if bpy.app.timers.is_registered(_on_timer):
        bpy.app.timers.unregister(_on_timer)
    _plans.clear()
    _pending.clear()
