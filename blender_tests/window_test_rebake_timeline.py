# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a Blender window under xvfb-run: the Timeline shows which baked frames a change has
invalidated. A probe keyed at frames 1, 10, 20 and 24 (linear) is baked with a checkpoint every
5 frames; its key at 20 is moved as a user would (the F-curve edited, no refresh called): the
add-on notices the edit, makes the re-bake plan once the edits pause, and the Timeline's bar
turns red over frames 11-24 and stays blue over 1-10 (screenshot timeline_partial_invalidation.png,
pixels checked); Resume re-bakes 11-24 and the bar is blue over 1-24 again
(timeline_rebaked.png)."""

import os
import tempfile

import bpy

from support import (area, check, clear_objects, close_splash, cube, drive, finish, ico_sphere, key_locations,
                     move_key, out_dir, png_rgb, redraw_all, region, remove_on_exit, screenshot, set_roles,
                     uv_sphere)

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.bake import cache_plan  # noqa: E402
from hapticfluid_blender.properties import roles  # noqa: E402
from hapticfluid_blender.ui import cache_bar  # noqa: E402

PATH = ((1, (0.3, 0.5, 0.55)), (10, (0.45, 0.5, 0.55)), (20, (0.6, 0.5, 0.5)), (24, (0.65, 0.5, 0.55)))
OUT = out_dir("addon")
TMP = remove_on_exit(tempfile.mkdtemp(prefix="hf_blender_rebake_window_"))
CACHE = os.path.join(TMP, "cache")
BLUE = lambda c: c[2] > 0.8 and c[2] - c[0] > 0.4  # noqa: E731
RED = lambda c: c[0] > 0.8 and c[0] - c[2] > 0.4  # noqa: E731
state = {"phase": "bake", "waits": 0}


def setup():
    hapticfluid_blender.register()
    scene = clear_objects()
    domain = cube(1.0, (0.5, 0.5, 0.5))
    probe = uv_sphere(0.12, PATH[0][1])
    key_locations(probe, PATH)
    source = ico_sphere(0.1, (0.5, 0.5, 0.2))
    source.hide_set(True)
    s = set_roles(scene, domain, probe, source)
    s.resolution, s.substeps, s.frame_start, s.frame_end, s.cache_dir = 16, 1, 1, 24, CACHE
    roles.domain_settings_of(scene).checkpoint_every = 5
    for fc in probe.animation_data.action.fcurves:
        for k in fc.keyframe_points:
            k.interpolation = "LINEAR"
    scene.frame_start, scene.frame_end = 0, 26
    close_splash()


def bar_share(rgb, dx, dy, reg, first, last, is_colour):
    """Share of the bar's pixels over frames first..last that have the colour."""
    x0, y0, x1, y1 = cache_bar.bar_rect(reg, first, last, bpy.context.preferences.system.ui_scale)
    rows = range(int(y0) + dy + 1, int(y1) + dy - 1)
    cells = [(x, y) for y in rows for x in range(int(x0) + dx + 3, int(x1) + dx - 3)]
    return sum(is_colour(rgb[y, x]) for x, y in cells) / max(1, len(cells)), len(cells)


def check_bar(name, spans):
    """Screenshot the Timeline; each (first, last, colour test, what) span must hold its colour."""
    timeline, reg = area("DOPESHEET_EDITOR"), region("DOPESHEET_EDITOR")
    path = screenshot(os.path.join(OUT, name), "DOPESHEET_EDITOR")
    rgb = png_rgb(path)
    dx, dy = reg.x - timeline.x, reg.y - timeline.y
    for first, last, is_colour, what in spans:
        share, n = bar_share(rgb, dx, dy, reg, first, last, is_colour)
        check(n > 50 and share > 0.9, f"{name}: frames {first}-{last} are {what} ({100 * share:.0f} % of {n} pixels)")


def settled():
    """False (after a redraw) for this phase's first few ticks: the window draws before a shot."""
    state["waits"] += 1
    if state["waits"] < 5:
        redraw_all()
        return False
    return True


def step():
    scene = bpy.context.scene
    s = roles.settings_of(scene)
    phase = state["phase"]
    if phase == "bake":
        area("VIEW_3D").ui_type = "TIMELINE"  # a large Timeline (the window's own is a few pixels high)
        check(bpy.ops.hapticfluid.bake() == {"FINISHED"}, f"bake 1-24: {s.status}")
        entry = cache_plan.get(scene)
        check(entry is not None and entry.kind == "complete", "the bake made the plan: every frame up to date")
        with bpy.context.temp_override(window=bpy.context.window_manager.windows[0], area=area("DOPESHEET_EDITOR"),
                                       region=region("DOPESHEET_EDITOR")):
            bpy.ops.action.view_all()
        state.update(phase="baked", waits=0)
    elif phase == "baked":
        if not settled():
            return 0.2
        check_bar("timeline_baked.png", [(1, 24, BLUE, "blue")])
        move_key(s.probe, 20, 0.05)  # x and z: the linear segments 10-20 and 20-24 change
        state.update(phase="edited", waits=0)
    elif phase == "edited":  # the depsgraph handler and the timer make the plan again
        entry = cache_plan.get(scene)
        state["waits"] += 1
        if entry is None or entry.kind != "inputs":
            check(state["waits"] < 50, f"the edit was noticed within 10 s (plan: {entry and entry.text!r})")
            return 0.2
        check(entry.text == "probe keys changed from frame 11: re-bake 11-24 from the checkpoint at 10",
              f"the plan: {entry.text!r}")
        state.update(phase="outdated", waits=0)
    elif phase == "outdated":
        if not settled():
            return 0.2
        check_bar("timeline_partial_invalidation.png",
                  [(1, 10, BLUE, "blue (kept)"), (11, 24, RED, "red (to re-bake)")])
        check(bpy.ops.hapticfluid.bake_resume() == {"FINISHED"} and "14 frame(s)" in s.status,
              f"Resume re-baked 11-24: {s.status}")
        state.update(phase="rebaked", waits=0)
    elif phase == "rebaked":
        if not settled():
            return 0.2
        check(cache_plan.get(scene).kind == "complete", "after Resume every frame is up to date")
        check_bar("timeline_rebaked.png", [(1, 24, BLUE, "blue")])
        hapticfluid_blender.unregister()
        finish(f"re-bake timeline test passed; screenshots in {OUT}")
        return None
    return 0.1


setup()
drive(step, 240, lambda: f"in phase {state['phase']}")
