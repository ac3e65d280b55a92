# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a windowed Blender under xvfb-run (--enable-event-simulate): a bake invoked from the UI
makes its Volume object at the first finished frame, in the active collection, and extends it
as frames land; disabling the add-on in the middle of the bake cancels and joins the worker
and shows the finished frames; enabling it again clears is_baking; Resume finishes the bake.
Then the Properties editor (Scene tab, then the Physics tab with the Domain's sub-panels), the
3D viewport in Solid mode and in Material Preview, and the Timeline are screenshotted: the PNGs go
to $HAPTICFLUID_OUT_DIR, else <HAPTICFLUID_SOURCE_DIR>/out/addon; the smoke must cover a region
of the viewport (pixels that change when the Volume is hidden) and stand out there with the
add-on's defaults (Solid: the plume's mean luminance at least 3 times darker or brighter than the
same pixels without it; Material Preview, a scene without lights: 0.08 brighter or darker; both
fail on the grey smoke of the add-on's defaults before), the Timeline's cache bar must cover the baked frames'
span in red while a setting differs from the bake's, in blue once it is set back (and nothing
past its end), and every open sub-panel of the Domain must have been drawn.
Exits 0 when every check passed, 1 otherwise (os._exit: a timer cannot raise out)."""

import os
import tempfile
import threading
import time

import bpy

from support import (BakePacer, area as area_of, check, clear_objects, close_splash, cube, drive, fail, finish,
                     frames_on_disk as frames_in, ico_sphere, invoke, key_locations, out_dir, png_rgb, redraw_all,
                     region as region_of, remove_on_exit, screenshot as screenshot_to, set_roles, settings,
                     uv_sphere, window)

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.operators import bake_ops  # noqa: E402
from hapticfluid_blender.ui import cache_bar, physics_panels  # noqa: E402

FRAMES = 48
OUT = out_dir("addon")
TMP = remove_on_exit(tempfile.mkdtemp(prefix="hf_blender_display_"))
CACHE = os.path.join(TMP, "cache")
state = {"phase": "start", "t0": time.time(), "durations": [], "waits": 0, "drawn": set()}


def setup():
    record_panel_draws()
    hapticfluid_blender.register()
    scene = clear_objects()
    fx = bpy.data.collections.new("FX")
    scene.collection.children.link(fx)
    bpy.context.view_layer.active_layer_collection = bpy.context.view_layer.layer_collection.children["FX"]
    domain = cube(1.0, (0.5, 0.5, 0.5))
    probe = uv_sphere(0.1, (0.3, 0.5, 0.6))
    key_locations(probe, ((0, (0.3, 0.5, 0.6)), (FRAMES, (0.7, 0.5, 0.6))))
    source = ico_sphere(0.14, (0.5, 0.5, 0.22))
    source.hide_set(True)  # the screenshots show the smoke, not the emitter
    s = set_roles(scene, domain, probe, source)
    s.resolution, s.frame_start, s.frame_end, s.substeps = 24, 1, FRAMES, 2
    s.heat_buoyancy, s.source_temperature, s.source_density = 2.0, 10.0, 1.0
    s.cache_dir = CACHE
    close_splash()


def frames_on_disk():
    return frames_in(CACHE)


def bake_threads():
    return [t for t in threading.enumerate() if t.name == "hapticfluid-bake" and t.is_alive()]


def screenshot(kind, name):
    return screenshot_to(os.path.join(OUT, name), kind)


def pixels(path):
    rgb = png_rgb(path)
    return rgb, rgb.shape[1], rgb.shape[0]


def frame_viewport():
    from mathutils import Euler, Vector

    space = area_of("VIEW_3D").spaces.active
    space.shading.type = "SOLID"
    space.overlay.show_overlays = False  # no grid or outlines: only the scene
    r3d = space.region_3d
    r3d.view_perspective = "PERSP"
    r3d.view_location = Vector((0.5, 0.5, 0.5))
    r3d.view_rotation = Euler((1.25, 0.0, 0.5)).to_quaternion()
    r3d.view_distance = 2.6
    props = area_of("PROPERTIES").spaces.active
    props.context = "SCENE"


def check_cache_bar(name, kind, is_bar_colour):
    """Screenshot the Timeline; the bar must cover frames 1..FRAMES at its height, and the
    pixels just past its end must not have its colour."""
    scene = bpy.context.scene
    check(cache_bar.baked_range(scene) == (1, FRAMES, kind), f"the cache bar's range: "
                                                            f"{cache_bar.baked_range(scene)}")
    timeline = area_of("DOPESHEET_EDITOR")
    region = region_of("DOPESHEET_EDITOR")
    rgb, w, h = pixels(screenshot("DOPESHEET_EDITOR", name))
    check((w, h) == (timeline.width, timeline.height), f"the Timeline screenshot is its area ({w} x {h})")
    x0, y0, x1, y1 = cache_bar.bar_rect(region, 1, FRAMES, bpy.context.preferences.system.ui_scale)
    dx, dy = region.x - timeline.x, region.y - timeline.y  # the region inside the area's image
    rows = range(int(y0) + dy + 1, int(y1) + dy - 1)
    inside = [(x, y) for y in rows for x in range(int(x0) + dx + 2, int(x1) + dx - 2)]
    past = [(x, y) for y in rows for x in range(int(x1) + dx + 6, min(int(x1) + dx + 60, w))]
    share = sum(is_bar_colour(rgb[y, x]) for x, y in inside) / max(1, len(inside))
    stray = sum(is_bar_colour(rgb[y, x]) for x, y in past)
    check(len(inside) > 100 and share > 0.9,
          f"the {kind} bar covers frames 1..{FRAMES} (x {x0:.0f}..{x1:.0f} px): {100 * share:.0f} % of "
          f"{len(inside)} pixels have its colour")
    check(past and stray == 0, f"nothing of the bar's colour past frame {FRAMES} ({stray} of {len(past)} pixels)")


def record_panel_draws():
    """Wrap the Physics tab panels' draw to note which ones Blender drew (before registering:
    a registered class's draw must not be replaced)."""
    def recording(draw, label):
        def recorded(self, context):
            state["drawn"].add(label)
            draw(self, context)
        return recorded

    for cls in physics_panels.classes[1:]:
        cls.draw = recording(cls.draw, cls.bl_label)


def show_physics_tab():
    """The domain active in the Physics tab."""
    bpy.context.view_layer.objects.active = settings().domain
    area_of("PROPERTIES").spaces.active.context = "PHYSICS"
    redraw_all()


def plume_contrast(with_volume, without_volume):
    """(mean display luminance of the plume's pixels, of the same pixels without the Volume, the
    plume's share of the image): the plume's pixels are those the Volume changes by more than 0.08
    in some channel."""
    import numpy as np

    a, w, h = pixels(with_volume)
    b, w2, h2 = pixels(without_volume)
    check((w, h) == (w2, h2), "both viewport screenshots have one size")
    plume = np.abs(a - b).max(axis=2) > 0.08
    if not plume.any():
        return 0.0, 0.0, 0.0
    luminance = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)  # Rec. 709 weights
    return float((a[plume] @ luminance).mean()), float((b[plume] @ luminance).mean()), float(plume.mean())


def next_phase(name):
    state.update(phase=name, waits=0)


def settling(ticks):
    """Counts this phase's ticks: True (after a redraw) for the first ticks - 1 of them, so the
    window has redrawn before the phase acts."""
    state["waits"] += 1
    if state["waits"] < ticks:
        redraw_all()
        return True
    return False


def step():
    phase = state["phase"]
    scene = bpy.context.scene
    if phase == "start":
        check(invoke(bpy.ops.hapticfluid.bake) == {"RUNNING_MODAL"}, "Bake invoked from the UI runs modal")
        state["phase"] = "baking"
    elif phase == "baking":
        pacer.tick()  # the bake's next frame may start (support.BakePacer)
        s = settings(scene)
        if not s.is_baking:
            fail(f"the bake ended before the add-on could be disabled: {s.status}")
        vol = s.volume_object
        if vol is not None:
            duration = vol.data.frame_duration
            if not state["durations"]:
                check(duration < FRAMES and vol.name in bpy.data.collections["FX"].objects,
                      f"the Volume appears during the bake ({duration} frame(s)), in the active collection")
            if not state["durations"] or state["durations"][-1] != duration:
                state["durations"].append(duration)
        if len(state["durations"]) >= 2:  # it followed at least one more frame: disable now
            check(state["durations"] == sorted(state["durations"]),
                  f"the Volume follows the frames as they land: {state['durations']}")
            hapticfluid_blender.unregister()
            pacer.release()  # Resume, later, bakes at its own pace
            check(not bake_threads(), "disabling the add-on joined the bake's worker")
            done = len(frames_on_disk())
            check(0 < done < FRAMES, f"the bake was cancelled with {done} complete frame(s)")
            vol = bpy.data.objects.get("hapticfluid Smoke")
            check(vol is not None and vol.data.frame_duration == done,
                  f"the Volume shows the {done} finished frame(s)")
            domain = bpy.data.objects["Cube"]  # its settings, read as stored (the add-on is off)
            check(not domain["hapticfluid"]["domain_settings"].get("is_baking", False),
                  "is_baking is cleared in the saved settings")
            hapticfluid_blender.register()
            s = settings(scene)
            check(not s.is_baking and "disabled" in s.status, f"enabled again: not baking, status {s.status!r}")
            try:  # Blender 4.3 crashed here: the ended bake's modal handler was still listed
                refused = invoke(bpy.ops.hapticfluid.bake_resume) == {"CANCELLED"}
            except RuntimeError as exc:  # the operator's error report
                refused = "Try again in a moment" in str(exc)
            check(refused, "Resume right after enabling again is refused until Blender dropped the ended bake")
            state.update(phase="resume_later", refused_at=time.time())
            return bake_ops.HANDLER_DROP_S + 0.1
    elif phase == "resume_later":
        try:
            result = invoke(bpy.ops.hapticfluid.bake_resume)
        except RuntimeError as exc:  # Blender's timers may run a little early: a few more tries
            if "Try again in a moment" in str(exc) and time.time() - state["refused_at"] < 4 * bake_ops.HANDLER_DROP_S:
                return 0.2
            raise
        check(result == {"RUNNING_MODAL"}, f"Resume runs modal {time.time() - state['refused_at']:.1f} s later")
        state["phase"] = "resuming"
    elif phase == "resuming":
        s = settings(scene)
        if not s.is_baking:
            check("finished" in s.status, f"Resume finished the bake: '{s.status}'")
            check(len(frames_on_disk()) == FRAMES and s.volume_object.data.frame_duration == FRAMES,
                  f"all {FRAMES} frames on disk and in the Volume")
            scene.frame_set(FRAMES)
            frame_viewport()
            redraw_all()
            next_phase("shoot")
    elif phase == "shoot":
        if settling(5):
            return 0.2
        state["with_smoke"] = screenshot("VIEW_3D", "viewport_solid.png")
        screenshot_to(os.path.join(OUT, "window.png"))
        settings(scene).volume_object.hide_viewport = True
        redraw_all()
        next_phase("shoot_without")
    elif phase == "shoot_without":
        if settling(5):
            return 0.2
        without = screenshot("VIEW_3D", "viewport_solid_no_volume.png")
        plume, background, share = plume_contrast(state["with_smoke"], without)
        check(share > 0.01, f"the smoke covers a visible region of the Solid viewport ({100 * share:.1f} % of it)")
        ratio = max(plume, background) / max(min(plume, background), 1e-3)
        check(ratio >= 3.0, f"the plume stands out in Solid mode: mean luminance {plume:.3f} on the plume's pixels, "
                            f"{background:.3f} there without it (x {ratio:.1f}, at least x 3)")
        area_of("VIEW_3D").spaces.active.shading.type = "MATERIAL"
        next_phase("material_without")
    elif phase == "material_without":
        if settling(30):  # EEVEE compiles its shaders and accumulates samples first (llvmpipe: seconds)
            return 0.3
        state["material_without"] = screenshot("VIEW_3D", "viewport_material_no_volume.png")
        settings(scene).volume_object.hide_viewport = False
        next_phase("material")
    elif phase == "material":
        if settling(30):
            return 0.3
        shot = screenshot("VIEW_3D", "viewport_material.png")
        plume, background, share = plume_contrast(shot, state["material_without"])
        # Blender 3.4's EEVEE shows the material's emission (brighter); 4.3's EEVEE Next, under Xvfb,
        # its absorption (darker): either way the plume must differ by 0.08 over 1 % of the view.
        check(share > 0.01 and abs(plume - background) >= 0.08,
              f"the plume stands out in Material Preview (a scene without lights): it covers {100 * share:.1f} % of "
              f"the viewport, mean luminance {plume:.3f} on its pixels, {background:.3f} without it")
        # The panel, large: the 3D view becomes a Properties editor on the Scene tab, scrolled
        # down to the add-on's panel; a changed setting shows "cache out of date".
        settings(scene).vorticity = 0.9
        big = area_of("VIEW_3D")
        big.type = "PROPERTIES"  # its tabs exist after its first draw: the Scene tab is chosen then
        redraw_all()
        next_phase("scroll")
    elif phase == "scroll":
        state["waits"] += 1
        big = area_of("PROPERTIES")
        region = next(r for r in big.regions if r.type == "WINDOW")
        if state["waits"] == 2:
            big.spaces.active.context = "SCENE"
        if 2 <= state["waits"] < 10:
            with bpy.context.temp_override(window=window(), area=big, region=region):
                bpy.ops.view2d.scroll_down(deltay=60)
        if state["waits"] < 12:
            redraw_all()
            return 0.2
        screenshot("PROPERTIES", "panel_scene_tab.png")
        show_physics_tab()
        next_phase("physics")
    elif phase == "physics":
        state["waits"] += 1
        big = area_of("PROPERTIES")
        if state["waits"] == 2:
            big.spaces.active.context = "PHYSICS"
        if state["waits"] < 8:
            redraw_all()
            return 0.2
        screenshot("PROPERTIES", "panel_physics_tab.png")
        want = {"hapticfluid", "Resolution", "Fluid", "Cache", "Display"}  # Pressure Solver starts closed
        check(want <= state["drawn"], f"the Physics tab drew the Domain's panels: {sorted(state['drawn'])}")
        big.ui_type = "TIMELINE"  # the window's own Timeline is a few pixels high at 1024 x 768
        next_phase("timeline")
    elif phase == "timeline":
        if settling(6):
            return 0.2
        if "outdated" not in state:  # vorticity was changed for the Scene tab's shot
            check_cache_bar("timeline_out_of_date.png", "outdated", lambda c: c[0] > 0.8 and c[0] - c[2] > 0.4)
            state["outdated"] = True
            settings(scene).vorticity = 0.4  # set back: up to date again
            state["waits"] = 0
            return 0.1
        check_cache_bar("timeline_baked.png", "baked", lambda c: c[2] > 0.8 and c[2] - c[0] > 0.4)
        hapticfluid_blender.unregister()
        finish(f"blender bake display test passed; screenshots in {OUT}")
        return None
    return 0.1


setup()
pacer = BakePacer()  # the bake outlasts the timer's ticks, however fast it is
drive(step, 400, lambda: f"in phase {state['phase']}")
