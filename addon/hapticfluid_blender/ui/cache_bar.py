# SPDX-License-Identifier: GPL-3.0-or-later
"""The baked range on the Timeline, as Mantaflow's cache bar: a bar along the bottom of the
Timeline's frame area, blue over the frames that hold what the scene bakes now, red over baked
frames a change has invalidated (the re-bake plan, cache_plan.py: "keys changed from frame 80"
turns 80 on red, a changed setting all of them), orange over the range while baking. Before a
plan is made (just after opening a file), the frames the domain's Volume object shows are drawn
blue, or red when a setting changed since the bake.

Blender's own cache bars (point caches) are drawn in C and have no Python hook, so this is a
``POST_PIXEL`` draw handler on the Dope Sheet/Timeline editor's frame region, drawn only in its
Timeline mode, with the ``gpu`` module. The scene's preview range was the other way: it shows a
range with no drawing code, but it changes what playback loops over, which is the artist's
setting, not ours. No handler is added in background mode (nothing is drawn there, and ``gpu``
cannot draw). Each baked frame gets a one-frame-wide cell centred on its frame number."""

import bpy

from ..bake import cache_plan
from ..properties import roles

BAR_BOTTOM_PX = 18  # above the region's lower edge (clear of the horizontal scroll bar), at UI scale 1
BAR_HEIGHT_PX = 6
COLOURS = {  # RGBA
    "baked": (0.25, 0.55, 1.0, 0.95),
    "baking": (1.0, 0.6, 0.1, 0.95),
    "outdated": (0.95, 0.25, 0.2, 0.95),
}

_handle = None


def runs(scene):
    """[(first frame, last frame, state)] to draw: the plan's baked and outdated runs, or the
    baked_range as one run (while baking, before a plan is made, or when a setting changed since
    the bake: that outdates every frame, known at once); [] for nothing."""
    s = roles.settings_of(scene)
    entry = cache_plan.current(scene)
    if s.domain is not None and not s.is_baking and entry is not None and entry.runs:
        return [r for r in entry.runs if r[2] in COLOURS]
    found = baked_range(scene)
    return [found] if found is not None else []


def baked_range(scene):
    """(first frame, last frame, state) of the cache the domain shows, or None: state is
    'baking', 'outdated' or 'baked' (a key of COLOURS)."""
    s = roles.settings_of(scene)
    if s.domain is None:
        return None
    vol = s.volume_object
    if vol is None or vol.type != "VOLUME" or not vol.data.is_sequence or vol.data.frame_duration < 1:
        return None
    first = vol.data.frame_start
    last = first + vol.data.frame_duration - 1
    if s.is_baking:
        state = "baking"
    else:
        state = "outdated" if cache_plan.changed_inputs(scene, s) else "baked"
    return first, last, state


def bar_rect(region, first, last, ui_scale=1.0):
    """The bar's (x0, y0, x1, y1) in the region's pixels: frames first - 0.5 .. last + 0.5."""
    x0, _ = region.view2d.view_to_region(first - 0.5, 0.0, clip=False)
    x1, _ = region.view2d.view_to_region(last + 0.5, 0.0, clip=False)
    y0 = BAR_BOTTOM_PX * ui_scale
    return float(x0), y0, float(max(x1, x0 + 2)), y0 + BAR_HEIGHT_PX * ui_scale


def _shader():
    import gpu

    for name in ("UNIFORM_COLOR", "2D_UNIFORM_COLOR"):  # Blender 4.0 dropped the '2D_' prefix
        try:
            return gpu.shader.from_builtin(name)
        except (ValueError, TypeError):
            continue
    raise RuntimeError("no uniform-colour built-in shader in this Blender")


def draw():
    """The draw handler (Timeline mode only)."""
    context = bpy.context
    space, region = context.space_data, context.region
    if space is None or getattr(space, "mode", None) != "TIMELINE" or region is None or context.scene is None:
        return
    if not hasattr(bpy.types.Object, "hapticfluid"):
        return
    found = runs(context.scene)
    if not found:
        return
    import gpu
    from gpu_extras.batch import batch_for_shader

    shader = _shader()
    blend = gpu.state.blend_get()
    gpu.state.blend_set("ALPHA")
    shader.bind()
    for first, last, state in found:
        x0, y0, x1, y1 = bar_rect(region, first, last, context.preferences.system.ui_scale)
        x0, x1 = max(x0, 0.0), min(x1, float(region.width))
        if x1 <= x0:
            continue
        batch = batch_for_shader(shader, "TRIS", {"pos": ((x0, y0), (x1, y0), (x1, y1), (x0, y1))},
                                 indices=((0, 1, 2), (0, 2, 3)))
        shader.uniform_float("color", COLOURS[state])
        batch.draw(shader)
    gpu.state.blend_set(blend)


def attach():
    global _handle
    if _handle is None and not bpy.app.background:
        _handle = bpy.types.SpaceDopeSheetEditor.draw_handler_add(draw, (), "WINDOW", "POST_PIXEL")


def detach():
    global _handle
    if _handle is not None:
        bpy.types.SpaceDopeSheetEditor.draw_handler_remove(_handle, "WINDOW")
        _handle = None
