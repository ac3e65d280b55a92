# SPDX-License-Identifier: GPL-3.0-or-later
"""Opens the live demo in a windowed Blender: a 1 m smoke domain with a source at its floor and a
sphere probe, the add-on registered from this source tree, and the live session started in the
3D view (smoke drawn in the viewport, force arrow at the probe, stats in the sidebar).

    blender --factory-startup --python-use-system-env --python scripts/live_demo.py -- [--device SIMULATED_FALCON]
    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --python-use-system-env --enable-event-simulate \
        --python scripts/live_demo.py -- --screenshot out/live_session.png --seconds 20

The hapticfluid package must be importable (scripts/demo.sh puts build/python on PYTHONPATH, which
Blender reads only with --python-use-system-env).
Devices: SIMULATED_FALCON (default: the Falcon driver on a simulated Falcon whose scripted hand
sweeps the probe through the plume; --gesture rest, sweep, circle or relaxed: hapticfluid.hand_gestures),
MOUSE (grab the probe with G), TIMELINE (the probe's keyed sweep plays), FALCON (a real one).
Stop with Esc or right-click in the viewport, or Stop in the sidebar. --screenshot PATH saves the
window to PATH after --seconds of running and quits (the README's picture, under xvfb-run).
"""

import argparse
import logging
import math
import os
import sys
import time

import bpy
from mathutils import Euler

log = logging.getLogger("hapticfluid.live_demo")
SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEVICES = ("SIMULATED_FALCON", "MOUSE", "TIMELINE", "FALCON")
state = {}


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="blender --python scripts/live_demo.py --",
                                     description="Open the hapticfluid live demo scene and start the session.")
    parser.add_argument("--device", choices=DEVICES, default="SIMULATED_FALCON",
                        help="what moves the probe (default: SIMULATED_FALCON)")
    try:
        from hapticfluid.hand_gestures import NAMES as gestures
    except ImportError:  # the add-on reports the missing package when the session starts
        gestures = ("rest", "sweep")
    parser.add_argument("--gesture", choices=gestures, default="sweep",
                        help="what the simulated Falcon's hand does (SIMULATED_FALCON; default: sweep)")
    parser.add_argument("--screenshot", metavar="PATH",
                        help="save a screenshot of the window to PATH (.png) after --seconds, then quit")
    parser.add_argument("--seconds", type=float, default=20.0,
                        help="seconds the session runs before --screenshot (s, default 20)")
    args = parser.parse_args(argv)
    if not args.seconds > 0.0:
        parser.error(f"--seconds must be a positive number of seconds, got {args.seconds}")
    return args


def screenshot_and_quit(path, t_end):
    """A bpy.app.timers callback: once t_end (time.monotonic) has passed, the window to path, then quit."""
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    if time.monotonic() < t_end:
        if not state.get("tab") and time.monotonic() > t_end - 3.0:
            state["tab"] = True
            show_hapticfluid_tab(window, area)
        return 0.5
    path = os.path.abspath(path)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with bpy.context.temp_override(window=window, area=area):
        bpy.ops.screen.screenshot_area(filepath=path)
    live = bpy.context.scene.hapticfluid_live
    log.info("screenshot %s (sim %.1f Hz, haptic %.0f Hz, hand force %.3f N, fluid force %.4f N, gain %.3g, %s, "
             "%s)", path, live.sim_rate_hz, live.haptic_rate_hz, live.device_force_n, live.force_n,
             live.force_gain_used, live.device_state, live.status)
    bpy.ops.wm.quit_blender()
    return None


def build_scene():
    """Domain [0, 1]^3 m (drawn as wire, so the smoke inside shows), probe sphere r = 0.08 m at
    the left of the plume (keyed across it for TIMELINE), source sphere at the floor."""
    scene = bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.5, 0.5, 0.5))
    domain = bpy.context.active_object
    domain.name = "Smoke Domain"
    domain.display_type = "WIRE"
    domain.hide_render = True
    bpy.ops.mesh.primitive_ico_sphere_add(radius=0.08, location=(0.5, 0.5, 0.14))
    source = bpy.context.active_object
    source.name = "Smoke Source"
    source.display_type = "WIRE"
    source.hide_render = True
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.08, location=(0.28, 0.5, 0.55))
    probe = bpy.context.active_object
    probe.name = "Probe"
    bpy.ops.object.shade_smooth()
    probe.keyframe_insert("location", frame=1)
    probe.location = (0.72, 0.5, 0.55)
    probe.keyframe_insert("location", frame=120)
    scene.frame_start, scene.frame_end, scene.frame_current = 1, 120, 1
    from hapticfluid_blender.properties import roles

    for obj, role in ((domain, "DOMAIN"), (probe, "PROBE"), (source, "SOURCE")):
        roles.assign(scene, role, obj)  # the Physics tab's roles (scene.hapticfluid_bake is the pre-roles one)
    return domain, probe


def frame_view():
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    space = area.spaces.active
    space.show_region_ui = True  # the sidebar, where the hapticfluid tab shows the session
    rv3d = space.region_3d
    rv3d.view_perspective = "PERSP"
    rv3d.view_location = (0.5, 0.5, 0.45)
    rv3d.view_rotation = Euler((math.radians(72), 0.0, math.radians(30))).to_quaternion()
    rv3d.view_distance = 2.4
    return window, area


def show_hapticfluid_tab(window, area):
    """Brings the sidebar's hapticfluid tab to the front (Python cannot set a region's active tab):
    Ctrl+wheel over the sidebar steps through its tabs (Item, Tool, View, hapticfluid in a factory
    setup). Needs --enable-event-simulate; without it the user clicks the tab."""
    if not bpy.app.use_event_simulate:
        log.info("open the sidebar's hapticfluid tab to see the session (N, then the tab at the right)")
        return
    sidebar = next(r for r in area.regions if r.type == "UI")
    x, y = sidebar.x + sidebar.width // 2, sidebar.y + sidebar.height // 2
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    for _ in range(3):
        window.event_simulate(type="WHEELDOWNMOUSE", value="PRESS", x=x, y=y, ctrl=True)


def start(device, gesture):
    scene = bpy.context.scene
    if not hasattr(bpy.ops.hapticfluid, "live_start") or not hasattr(scene, "hapticfluid_live"):
        log.error("this add-on has no live session (hapticfluid.live_start): the scene is built, nothing runs")
        return None
    scene.hapticfluid_live.device = device
    if device == "SIMULATED_FALCON":
        scene.hapticfluid_live.hand_gesture = gesture.upper()
    window, area = frame_view()
    region = next(r for r in area.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=window, area=area, region=region):
        result = bpy.ops.hapticfluid.live_start("INVOKE_DEFAULT")
    live = scene.hapticfluid_live
    log.info("live session (%s): %s %s", device, sorted(result), live.status)
    return None  # a bpy.app.timers callback: run once


def main():
    logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")
    if bpy.app.background:
        raise SystemExit("live_demo.py needs a window: run it without --background (scripts/demo.sh does, "
                         "when $DISPLAY is set)")
    args = parse_args()
    # Read before the splash opens (after --python scripts); --factory-startup does not save it.
    bpy.context.preferences.view.show_splash = False
    sys.path.insert(0, os.path.join(SOURCE_DIR, "addon"))
    import hapticfluid_blender

    hapticfluid_blender.register()
    build_scene()
    # The window and its 3D view exist once the event loop runs: start from a timer.
    bpy.app.timers.register(lambda: start(args.device, args.gesture), first_interval=0.5)
    if args.screenshot:
        t_end = time.monotonic() + 0.5 + args.seconds
        bpy.app.timers.register(lambda: screenshot_and_quit(args.screenshot, t_end), first_interval=1.0)


main()
