# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a windowed Blender under xvfb-run: the live viewport drawing (live_draw.LiveDrawer)
draws a synthetic smoke plume inside the domain box, the force arrow at the probe and the
workspace box. Screenshots of the window before and after set_density/set_force are compared in
the domain's projected screen region (computed from its 8 corners) and along the arrow's
projected segment. The PNGs are kept in <source>/out/live_draw*.png (HAPTICFLUID_SOURCE_DIR)
to be looked at. Also checks: one texture upload per new array, gpu.state restored after the
callback, remove() idempotent; the smoke respects the scene's depth: a probe in front of the plume
stays unveiled, one behind it is veiled by the smoke in front (live_draw_probe_*.png); prints the
redraw rate at 32^3 and 64^3.
Exits 0 when every check passed, 1 otherwise (os._exit: a timer cannot raise out)."""

import math
import os
import time

import bpy
import gpu
import numpy as np
from bpy_extras.view3d_utils import location_3d_to_region_2d
from mathutils import Euler

from support import (OVERLAY_ONLY_SCREENSHOTS, area, check, clear_objects, cube, drive, on_exit, out_dir, png_rgb,
                     region, screenshot as screenshot_to, uv_sphere, window)

from hapticfluid_blender.live import live_draw, live_draw_gpu  # noqa: E402  (registers nothing)
from hapticfluid_blender.live import live_draw_geometry as geometry  # noqa: E402

# The pictures compared here (texelFetch against texture(), scaled against full resolution) must
# be marched at one pixel scale: no time budget (window_test_live_pace.py measures the budget).
live_draw_gpu.SOFTWARE_SMOKE_BUDGET_MS = math.inf
OUT = out_dir()
LO, HI = (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)
PROBE = (0.33, 0.5, 0.55)
FORCE = (1.9, 0.5, 1.1)       # N
MAX_FORCE = 3.0               # N
WORKSPACE = ((0.05, 0.05, 0.1), (0.95, 0.95, 0.9))
# Redraw-rate runs: (resolution, a new array every timer tick); resolution 0: smoke off.
FPS_PLAN = ((32, False), (32, True), (64, False), (64, True), (0, False))
SMOKE_DIFF = 0.06             # a smoke pixel differs from the empty view by this much (0..1 channel)
# The most the smoke may change the probe in front of the plume: 0.04 over the probe's Solid-mode
# grey (0.62); where the screenshot has no engine colour (support.OVERLAY_ONLY_SCREENSHOTS: the
# probe is black there) the same smoke alpha shows as its premultiplied colour, 0.04 * 0.95 / (0.95 - 0.62).
PROBE_VEIL_MAX = 0.04
PROBE_VEIL_MAX_OVER_BLACK = 0.11
state = {"phase": "start", "t0": time.time(), "wait_frames": 0}
drawer = live_draw.LiveDrawer()
on_exit(drawer.remove)  # the handler goes when a check fails
seen_state = {}


def plume(n):
    """A rising smoke column with a mushroom cap over the cube [0, 1]^3, density 0..1, at n^3."""
    c = (np.arange(n, dtype=np.float32) + 0.5) / n
    x, y, z = np.meshgrid(c, c, c, indexing="ij")
    r2 = (x - 0.5) ** 2 + (y - 0.5) ** 2
    column = np.exp(-r2 / (2 * 0.07 ** 2)) * (z > 0.08) * (z < 0.7) * (1.0 - 0.6 * z)
    cap = np.exp(-(r2 / (2 * 0.16 ** 2) + (z - 0.72) ** 2 / (2 * 0.08 ** 2))) * 0.55
    density = np.clip(column + cap, 0.0, 1.0).astype(np.float32)
    temperature = (8.0 * density * np.clip(1.2 - z, 0.0, 1.0)).astype(np.float32)
    return density, temperature


def view3d():
    return window(), area(), region()


def setup():
    clear_objects()
    cube(1.0, (0.5, 0.5, 0.5), "Domain").display_type = "WIRE"
    uv_sphere(0.08, PROBE, "Probe")
    win, area, region = view3d()
    space = area.spaces.active
    space.overlay.show_floor = True
    rv3d = space.region_3d
    rv3d.view_perspective = "PERSP"
    rv3d.view_location = (0.5, 0.5, 0.45)
    rv3d.view_rotation = Euler((math.radians(72), 0.0, math.radians(30))).to_quaternion()
    rv3d.view_distance = 2.4
    space.lens = 50


def set_view(perspective, distance_m):
    _, area, _ = view3d()
    rv3d = area.spaces.active.region_3d
    rv3d.view_perspective = perspective
    rv3d.view_distance = distance_m


def plume_brightness(image, height_fraction):
    """Mean brightness of a small patch on the plume's axis at that fraction of the domain's height."""
    x, y = project((0.5, 0.5, height_fraction))
    return float(image[int(y) - 6:int(y) + 7, int(x) - 6:int(x) + 7].mean())


def redraw():
    _, area, _ = view3d()
    area.tag_redraw()


def screenshot(name):
    return png_rgb(screenshot_to(os.path.join(OUT, name)))


def project(point):
    _, area, region = view3d()
    xy = location_3d_to_region_2d(region, area.spaces.active.region_3d, point)
    return None if xy is None else (region.x + xy.x, region.y + xy.y)  # window pixels, origin bottom-left


def place_probe(side):
    """The probe sphere 0.22 m from the plume's axis towards the eye (side +1) or away from it (-1),
    at mid height; the drawer told where it is, so the smoke's rays stop there."""
    from mathutils import Vector

    _, area, _ = view3d()
    eye = area.spaces.active.region_3d.view_matrix.inverted().translation
    axis = Vector((0.5, 0.5, 0.45))
    towards = (eye - axis)
    towards.z = 0.0
    at = axis + side * 0.22 * towards.normalized()
    probe = bpy.data.objects["Probe"]
    probe.location = at
    bpy.context.view_layer.update()
    state["probe_at"] = tuple(at)
    drawer.set_probe({"shape": "sphere", "radius": 0.08})
    drawer.set_probe_matrix([list(row) for row in probe.matrix_world])


def smoke_checks(before, after):
    corners = [project(c) for c in geometry.box_corners(LO, HI)]
    check(all(c is not None for c in corners), "the domain's 8 corners project into the view")
    xs, ys = [c[0] for c in corners], [c[1] for c in corners]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    print(f"domain on screen: x {x0:.0f}..{x1:.0f}, y {y0:.0f}..{y1:.0f}", flush=True)
    diff = np.abs(after - before).max(axis=2)
    # The plume's column: the middle third of the box's width, from a fifth to three fifths of its height.
    cx0, cx1 = int(x0 + (x1 - x0) * 0.42), int(x0 + (x1 - x0) * 0.58)
    cy0, cy1 = int(y0 + (y1 - y0) * 0.3), int(y0 + (y1 - y0) * 0.7)
    centre = diff[cy0:cy1, cx0:cx1]
    fraction = float((centre > SMOKE_DIFF).mean())
    check(fraction > 0.6, f"smoke covers the plume's screen region: {fraction:.0%} of "
                          f"{centre.size} px differ by > {SMOKE_DIFF}")
    brightness = float((after[cy0:cy1, cx0:cx1].mean(axis=2) - before[cy0:cy1, cx0:cx1].mean(axis=2)).mean())
    check(brightness > 0.15, f"the smoke is light on the grey background (+{brightness:.2f} brightness)")
    # Outside the domain's screen box nothing changes but the arrow and its label.
    outside = np.ones(diff.shape, dtype=bool)
    outside[int(y0) - 2:int(y1) + 3, int(x0) - 2:int(x1) + 3] = False
    stray = float((diff[outside] > SMOKE_DIFF).mean())
    check(stray < 0.01, f"nothing but the overlay changes outside the domain ({stray:.2%} of the pixels)")


def arrow_checks(after):
    mesh = geometry.arrow_mesh(PROBE, FORCE, MAX_FORCE, math.dist(LO, HI))
    a, b = project(PROBE), project(mesh[2])
    colour = np.array(geometry.force_color(math.sqrt(sum(f * f for f in FORCE)), MAX_FORCE)[:3])
    hits = 0
    samples = 40
    for k in range(samples):
        t = 0.15 + 0.7 * k / (samples - 1)
        x, y = int(a[0] + (b[0] - a[0]) * t), int(a[1] + (b[1] - a[1]) * t)
        patch = after[y - 3:y + 4, x - 3:x + 4]
        # The arrow is shaded: its colour times 0.45..1. Compare hue (normalised RGB).
        norm = patch / np.maximum(patch.sum(axis=2, keepdims=True), 1e-6)
        close = np.abs(norm - colour / colour.sum()).max(axis=2) < 0.06
        hits += bool(close.any())
    length = math.dist(a, b)
    check(length > 30, f"the arrow is long enough to read ({length:.0f} px)")
    check(hits >= 0.9 * samples, f"the arrow's colour lies along its projected segment ({hits}/{samples})")
    label_x, label_y = int(b[0]), int(b[1])
    label = after[label_y:label_y + 40, label_x:label_x + 120]
    norm = label / np.maximum(label.sum(axis=2, keepdims=True), 1e-6)
    text_px = int((np.abs(norm - colour / colour.sum()).max(axis=2) < 0.06).sum())
    check(text_px > 40, f"the '{geometry.label_text(math.sqrt(sum(f * f for f in FORCE)))}' label is drawn "
                        f"by the head ({text_px} px of its colour)")


def sync_gpu():
    import gpu

    gpu.state.active_framebuffer_get().read_color(0, 0, 1, 1, 4, 0, 'FLOAT')  # waits for the GPU


def spy_before():
    import gpu

    if state.get("timing") is not None:
        sync_gpu()
        state["timing"].append(-time.perf_counter())
    seen_state["before"] = (gpu.state.blend_get(), gpu.state.depth_test_get(), gpu.state.depth_mask_get(),
                            gpu.state.line_width_get())


def spy_after():
    import gpu

    seen_state["after"] = (gpu.state.blend_get(), gpu.state.depth_test_get(), gpu.state.depth_mask_get(),
                           gpu.state.line_width_get())
    if state.get("timing"):
        sync_gpu()
        state["timing"][-1] += time.perf_counter()


def readd_drawer():
    """remove() + add(): the shader is made again at the next draw; the spies stay around the drawer."""
    drawer.remove()
    drawer.add()
    space = bpy.types.SpaceView3D
    space.draw_handler_remove(state["spies"][1], "WINDOW")
    state["spies"] = (state["spies"][0], space.draw_handler_add(spy_after, (), "WINDOW", "POST_VIEW"))


def measure_fps(n, upload_every_frame, seconds=3.0):
    """Redraws per second while a timer tags the view every loop (and sets a new array each time)."""
    density, _ = plume(max(n, 32))
    drawer.set_density(density)
    drawer.set_display(live_draw.DEFAULT_DENSITY_SCALE_PER_M if n else 0.0, False)  # n = 0: no smoke
    frames0, uploads0, t0 = drawer.frames_drawn, drawer.uploads, time.time()
    state["fps"] = (n, seconds, upload_every_frame, frames0, uploads0, t0, density)
    state["timing"] = []
    state["phase"] = "fps"


def step():
    now = time.time()
    if drawer.frames_drawn < state["wait_frames"]:  # let the view redraw (slow on a loaded llvmpipe)
        redraw()
        return 0.05
    phase = state["phase"]
    if phase == "start":
        setup()
        space = bpy.types.SpaceView3D
        state["spies"] = (space.draw_handler_add(spy_before, (), "WINDOW", "POST_VIEW"),)
        drawer.add()
        state["spies"] += (space.draw_handler_add(spy_after, (), "WINDOW", "POST_VIEW"),)
        drawer.set_domain(LO, HI)
        drawer.set_workspace_box(*WORKSPACE)
        state.update(phase="empty", wait_frames=3)
    elif phase == "empty":
        check(drawer.frames_drawn >= 2, f"the POST_VIEW callback runs ({drawer.frames_drawn} draws)")
        check(drawer.uploads == 0, "nothing is uploaded before set_density")
        check(drawer.sampling in ("texture", "texelFetch"), f"smoke sampling: {drawer.sampling}")
        state["sampling"] = drawer.sampling
        state["pixel_scale"] = drawer.smoke_pixel_scale
        check(drawer.smoke_pixel_scale == (0.5 if "llvmpipe" in gpu.platform.renderer_get() else 1.0),
              f"smoke pixel scale {drawer.smoke_pixel_scale} on {gpu.platform.renderer_get()}")
        state["before"] = screenshot("live_draw_before.png")
        density, _ = plume(32)
        drawer.set_density(density)
        drawer.set_force(PROBE, FORCE, MAX_FORCE)
        state.update(phase="smoke", wait_frames=drawer.frames_drawn + 3, drawn_at=drawer.frames_drawn)
    elif phase == "smoke":
        check(drawer.frames_drawn >= state["drawn_at"] + 2, "the view redrew after set_density")
        check(drawer.uploads == 1, f"one upload for one array over {drawer.frames_drawn - state['drawn_at']} "
                                   f"redraws ({drawer.uploads})")
        check(seen_state.get("before") == seen_state.get("after"),
              f"gpu.state is restored after the callback: {seen_state}")
        after = screenshot("live_draw.png")
        smoke_checks(state["before"], after)
        arrow_checks(after)
        state["after"] = after
        # The texelFetch fallback (for a Blender whose sampler does not filter) draws the same smoke.
        state["probe"] = live_draw_gpu.samples_linearly
        live_draw_gpu.samples_linearly = lambda: False
        readd_drawer()
        state.update(phase="fallback", wait_frames=drawer.frames_drawn + 3)
    elif phase == "fallback":
        check(drawer.sampling == "texelFetch", "the fallback shader is in use")
        fallback = screenshot("live_draw_texelfetch.png")
        live_draw_gpu.samples_linearly = state["probe"]
        diff = np.abs(fallback - state["after"]).max(axis=2)
        check(float((diff > 0.1).mean()) < 0.002 and float(diff.mean()) < 0.01,
              f"the texelFetch fallback matches hardware filtering (mean difference {diff.mean():.4f}, "
              f"{(diff > 0.1).mean():.3%} of pixels by > 0.1)")
        # Full resolution (a hardware GPU's path) draws the same smoke as the scaled-up one.
        state["scale"] = live_draw_gpu.smoke_pixel_scale
        live_draw_gpu.smoke_pixel_scale = lambda: 1.0
        readd_drawer()
        state.update(phase="full", wait_frames=drawer.frames_drawn + 3)
    elif phase == "full":
        check(drawer.smoke_pixel_scale == 1.0 and drawer.sampling == state["sampling"], "full-resolution smoke")
        full = screenshot("live_draw_full_resolution.png")
        live_draw_gpu.smoke_pixel_scale = state["scale"]
        readd_drawer()  # back to this Blender's own sampling and scale for what follows
        diff = np.abs(full - state["after"]).max(axis=2)
        check(float((diff > 0.1).mean()) < 0.005 and float(diff.mean()) < 0.01,
              f"smoke raymarched at {state['pixel_scale']} of the pixels matches full resolution (mean difference "
              f"{diff.mean():.4f}, {(diff > 0.1).mean():.3%} of pixels by > 0.1)")
        set_view("ORTHO", 2.4)
        state.update(phase="ortho", wait_frames=drawer.frames_drawn + 3)
    elif phase == "ortho":
        brightness = plume_brightness(screenshot("live_draw_ortho.png"), 0.5)
        check(brightness > 0.45, f"smoke in an orthographic view (plume brightness {brightness:.2f})")
        set_view("PERSP", 0.25)  # the eye inside the domain
        state.update(phase="inside", wait_frames=drawer.frames_drawn + 3)
    elif phase == "inside":
        _, _, region = view3d()
        cx, cy = region.x + region.width // 2, region.y + region.height // 2
        brightness = float(screenshot("live_draw_inside.png")[cy - 20:cy + 20, cx - 20:cx + 20].mean())
        check(brightness > 0.45, f"smoke seen with the eye inside the domain (centre brightness {brightness:.2f})")
        set_view("PERSP", 2.4)
        drawer.set_display(live_draw.DEFAULT_DENSITY_SCALE_PER_M, True)
        density, temperature = plume(32)
        drawer.set_density(density, temperature)
        state.update(phase="temperature", wait_frames=drawer.frames_drawn + 3)
    elif phase == "temperature":
        check(drawer.sampling == state["sampling"], f"this Blender's own sampling is back: {drawer.sampling}")
        hot = screenshot("live_draw_temperature.png")
        corners = [project(c) for c in geometry.box_corners(LO, HI)]
        xs, ys = [c[0] for c in corners], [c[1] for c in corners]
        x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
        base = hot[int(y0 + (y1 - y0) * 0.25):int(y0 + (y1 - y0) * 0.4),
                   int(x0 + (x1 - x0) * 0.45):int(x0 + (x1 - x0) * 0.55)]
        red_minus_blue = float((base[:, :, 0] - base[:, :, 2]).mean())
        check(red_minus_blue > 0.1, f"show_temperature tints the hot column warm (red - blue = {red_minus_blue:.2f})")
        drawer.set_display(live_draw.DEFAULT_DENSITY_SCALE_PER_M, False)
        density, _ = plume(32)
        drawer.set_density(density)
        place_probe(+1.0)
        state.update(phase="probe_base", wait_frames=drawer.frames_drawn + 3, side=+1.0, probe_results={})
    elif phase == "probe_base":  # the probe without smoke: what it looks like unveiled
        drawer.set_display(0.0, False)
        state.update(phase="probe_empty", wait_frames=drawer.frames_drawn + 3)
    elif phase == "probe_empty":
        side = state["side"]
        state["probe_base_img"] = screenshot(f"live_draw_probe_{'front' if side > 0 else 'behind'}_empty.png")
        drawer.set_display(live_draw.DEFAULT_DENSITY_SCALE_PER_M, False)
        state.update(phase="probe_smoke", wait_frames=drawer.frames_drawn + 3)
    elif phase == "probe_smoke":
        side = state["side"]
        name = "front" if side > 0 else "behind"
        img = screenshot(f"live_draw_probe_{name}.png")
        x, y = project(state["probe_at"])
        patch = (slice(int(y) - 5, int(y) + 6), slice(int(x) - 5, int(x) + 6))
        veil = float(np.abs(img[patch] - state["probe_base_img"][patch]).max(axis=2).mean())
        state["probe_results"][name] = veil
        print(f"probe {name} of the plume: smoke changes its pixels by {veil:.3f}", flush=True)
        if side > 0:
            over_black = os.path.join(OUT, f"live_draw_probe_{name}.png") in OVERLAY_ONLY_SCREENSHOTS
            limit = PROBE_VEIL_MAX_OVER_BLACK if over_black else PROBE_VEIL_MAX
            check(veil < limit, f"the probe in front of the plume stays visible, not drawn over ({veil:.3f} < {limit}"
                                f"{', probe black: overlay-only screenshot' if over_black else ''})")
            place_probe(-1.0)
            state.update(phase="probe_base", wait_frames=drawer.frames_drawn + 3, side=-1.0)
        else:
            check(veil > 0.1, f"the probe behind the plume is veiled by the smoke in front of it ({veil:.3f})")
            px, py = project((0.5, 0.5, 0.3))
            column = float(np.abs(img[int(py) - 4:int(py) + 5, int(px) - 4:int(px) + 5]
                                  - state["before"][int(py) - 4:int(py) + 5, int(px) - 4:int(px) + 5]).max(axis=2).mean())
            check(column > SMOKE_DIFF, f"the plume beside the probe is still drawn ({column:.3f})")
            bpy.data.objects["Probe"].location = PROBE
            bpy.context.view_layer.update()
            drawer.set_probe(None)
            state["fps_results"] = []
            measure_fps(*FPS_PLAN[0])
    elif phase == "fps":
        n, seconds, every, frames0, uploads0, t0, density = state["fps"]
        if every:
            drawer.set_density(density)
        redraw()
        if now - t0 >= seconds and drawer.frames_drawn - frames0 >= 4:
            frames = drawer.frames_drawn - frames0
            uploads = drawer.uploads - uploads0
            rate = frames / (now - t0)
            label = f"{n}^3, " + ("a new array every timer tick" if every else "one array") if n else "no smoke"
            cost = sorted(state["timing"][1:]) or [float("nan")]
            state["timing"] = None
            print(f"viewport redraws ({label}): {rate:.1f} fps ({frames} frames, {uploads} uploads "
                  f"in {now - t0:.1f} s); live_draw's POST_VIEW callback {1000 * cost[len(cost) // 2]:.0f} ms "
                  f"(median, GPU finished)", flush=True)
            state["fps_results"].append((n, every, rate, uploads))
            done = len(state["fps_results"])
            if done < len(FPS_PLAN):
                measure_fps(*FPS_PLAN[done])
            else:
                state["phase"] = "finish"
        return 0.0
    elif phase == "finish":
        for n, every, rate, uploads in state["fps_results"]:
            if not every:
                check(uploads <= 1, f"{n}^3, one array: at most one upload over the run ({uploads})")
        drawer.remove()
        drawer.remove()
        check(not drawer.is_added and drawer not in live_draw._active, "remove() twice is fine")
        for handle in state["spies"]:
            bpy.types.SpaceView3D.draw_handler_remove(handle, "WINDOW")
        print("blender live draw window test passed", flush=True)
        os._exit(0)
    return 0.05


bpy.context.preferences.view.show_splash = False  # read before the splash opens; not saved (--factory-startup)
drive(step, 420, lambda: f"in phase {state['phase']}")
