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
    the bake (changed_inputs, known at once, while the plan is made again only after the edits
    pause), since that outdates every frame, as the panel's warning says."""
    entry = get(scene)
    if entry is None or changed_inputs(scene, roles.settings_of(scene)):
        return None
    return entry


def inputs(scene, settings):
    """What the cache is made from, cheap enough for a panel's draw, as the package lists it
    (hapticfluid.bake.scene.CACHE_INPUTS, the fingerprint's entries): the settings, gravity and
    frame rate as the bake reads them (blender_scene.settings_dict), the domain's world box, and
    the probe and the smoke source by their objects' names and settings (their animation and
    meshes are read with frame_set on every frame, too slow for a draw: the plan compares those).
    Floats rounded to 9 decimals, as JSON stores them. ``settings`` is ``roles.settings_of(scene)``."""
    from hapticfluid.bake.scene import cache_inputs

    from . import blender_scene, source_mesh

    data = blender_scene.settings_dict(scene, settings)
    if settings.domain is not None:
        lo, hi = blender_scene.world_box(settings.domain)
        data["domain"] = {"origin": lo, "size": [hi[i] - lo[i] for i in range(3)]}
    if settings.probe is not None:
        data["probe"] = {"object": settings.probe.name, "shape": settings.probe_shape}
    if settings.source is not None:
        data["source"] = {"object": settings.source.name, **source_mesh.values(settings)}
    return _rounded(cache_inputs(data))


def _rounded(value):
    if isinstance(value, float):
        return round(value, 9)
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_rounded(v) for v in value]
    return value


def inputs_json(scene, settings) -> str:
    import json

    return json.dumps(inputs(scene, settings), sort_keys=True)


def changed_inputs(scene, settings):
    """What changed since the bake, as the re-bake plan names it ('fluid.vorticity',
    'domain_size'): [] if nothing, or no bake recorded. A record made before the package's list
    (keyed by the fields' names) is no answer: the plan, made from the cache itself, says then."""
    import json

    if not settings.baked_inputs:
        return []
    try:
        baked = json.loads(settings.baked_inputs)
        from hapticfluid.bake.cache import settings_differences
    except ValueError:
        return ["(unreadable record)"]
    except ImportError:  # no package: no bake either, and the panel says why
        return []
    now = json.loads(inputs_json(scene, settings))  # the same rounding and JSON types
    if not isinstance(baked, dict) or not set(baked) & set(now):
        return []
    return settings_differences(baked, now)


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
