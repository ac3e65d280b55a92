# SPDX-License-Identifier: GPL-3.0-or-later
"""What every Blender test script here shares: the add-on on sys.path, checks that report and
fail the same way, the scene the tests build (a domain cube, a probe, a smoke source and their
roles), and, for the windowed tests, the window's areas, redraws, screenshots and a timer that
drives a test step by step and turns any exception or time-out into a failed run.

The scripts run inside Blender (`--background` or a window under xvfb-run) with
HAPTICFLUID_SOURCE_DIR naming the checkout. Not collected by CMake: only test_*.py and
window_test_*.py are tests."""

import os
import shutil
import sys
import time
import traceback

import bpy

SOURCE_DIR = os.environ["HAPTICFLUID_SOURCE_DIR"]
ADDON_DIR = os.path.join(SOURCE_DIR, "addon")
if ADDON_DIR not in sys.path:
    sys.path.insert(0, ADDON_DIR)

_cleanups = []


def out_dir(*parts):
    """The folder screenshots are kept in (HAPTICFLUID_OUT_DIR, else out/ in the checkout), made."""
    folder = os.path.join(os.environ.get("HAPTICFLUID_OUT_DIR") or os.path.join(SOURCE_DIR, "out"), *parts)
    os.makedirs(folder, exist_ok=True)
    return folder


def on_exit(action):
    """Run ``action()`` when the test fails or finishes through fail() / finish()."""
    _cleanups.append(action)
    return action


def remove_on_exit(path):
    on_exit(lambda: shutil.rmtree(path, ignore_errors=True))
    return path


def _run_cleanups():
    while _cleanups:
        try:
            _cleanups.pop()()
        except Exception:  # a cleanup must not hide the failure being reported
            traceback.print_exc()


def check(condition, message):
    """Print ``ok: message`` or raise AssertionError(message): background scripts exit 1 through
    --python-exit-code, windowed scripts through drive()'s handler."""
    if not condition:
        raise AssertionError(message)
    print("ok:", message, flush=True)


def fail(message):
    """End a windowed test now (a timer cannot raise out of Blender): exit status 1."""
    print("FAILED:", message, flush=True)
    _run_cleanups()
    os._exit(1)


def finish(message, quit_blender=True):
    print(message, flush=True)
    _run_cleanups()
    if quit_blender:
        bpy.ops.wm.quit_blender()


def refused(call, *fragments):
    """Run ``call`` (an operator whose ERROR report raises in background mode); check the message
    holds every fragment and return it."""
    try:
        call()
    except RuntimeError as err:
        text = str(err)
        check(all(f in text for f in fragments), f"refused with {fragments}: {text}")
        return text
    raise AssertionError(f"not refused: expected {fragments}")


# --- the scene -------------------------------------------------------------------------------

def empty_file():
    """A factory-settings file with no objects; returns its scene."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def clear_objects(scene=None):
    """Remove every object of the scene (windowed tests keep their window and screen)."""
    scene = scene or bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj)
    return scene


def _added(name):
    obj = bpy.context.active_object
    if name:
        obj.name = name
    return obj


def cube(size, location, name=None):
    bpy.ops.mesh.primitive_cube_add(size=size, location=location)
    return _added(name)


def uv_sphere(radius, location, name=None):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=location)
    return _added(name)


def ico_sphere(radius, location, name=None):
    bpy.ops.mesh.primitive_ico_sphere_add(radius=radius, location=location)
    return _added(name)


def key_locations(obj, keys):
    """Keyframe ``obj.location`` at each (frame, location) of ``keys``."""
    for frame, location in keys:
        obj.location = location
        obj.keyframe_insert("location", frame=frame)


def move_key(obj, frame, delta, indices=(0, 2)):
    """What a drag of a key in the Graph Editor does: the location F-curves ``indices`` of
    ``obj``'s action get their key at ``frame`` (and its handles) moved by ``delta`` (m)."""
    for fc in obj.animation_data.action.fcurves:
        if fc.data_path != "location" or fc.array_index not in indices:
            continue
        for k in fc.keyframe_points:
            if k.co[0] == frame:
                k.co[1] += delta
                k.handle_left[1] += delta
                k.handle_right[1] += delta
        fc.update()
    obj.animation_data.action.update_tag()


def settings(scene=None):
    """The scene's roles and settings as the add-on reads them (roles.settings_of): ``domain``,
    ``probe``, ``source`` are the objects holding the roles (assigning moves a role), the other
    names the settings of the role that owns them."""
    from hapticfluid_blender.properties import roles

    return roles.settings_of(scene or bpy.context.scene)


def set_roles(scene, domain, probe, source=None):
    """Give the objects their hapticfluid roles, as the Physics tab stores them (each object's
    ``hapticfluid.role``, one object per role); returns ``settings(scene)``."""
    from hapticfluid_blender.properties import roles

    for obj, role in ((domain, "DOMAIN"), (probe, "PROBE"), (source, "SOURCE")):
        if obj is not None:
            roles.assign(scene, role, obj)  # taken from another object that had it
            if obj.hapticfluid.role != role:
                raise AssertionError(f"'{obj.name}' did not get the {role} role")
    return settings(scene)


def bake_scene(cache_dir, resolution=24, frames=(1, 4), substeps=1, probe_radius=0.12,
               probe_path=((1, (0.3, 0.5, 0.55)), (4, (0.65, 0.5, 0.55))), source_radius=0.1):
    """An empty file with a 1 m domain cube (corner at the origin), an animated UV-sphere probe and
    an ico-sphere smoke source at the floor; returns (scene, bake settings, domain, probe, source)."""
    scene = empty_file()
    domain = cube(1.0, (0.5, 0.5, 0.5), "Domain")
    probe = uv_sphere(probe_radius, probe_path[0][1], "Probe")
    key_locations(probe, probe_path)
    source = ico_sphere(source_radius, (0.5, 0.5, 0.2), "Source")
    bake = set_roles(scene, domain, probe, source)
    bake.resolution, bake.substeps = resolution, substeps
    bake.frame_start, bake.frame_end = frames
    bake.cache_dir = cache_dir
    scene.frame_start, scene.frame_end = frames
    return scene, bake, domain, probe, source


def live_scene(resolution=16):
    """The current scene without its meshes, then a 1 m wire-frame domain cube, a UV-sphere probe and
    smoke source, and a live session on the simulated Falcon at a fixed ``resolution``; returns
    the scene."""
    scene = bpy.context.scene
    for obj in list(scene.objects):
        if obj.type == "MESH":
            bpy.data.objects.remove(obj)
    domain = cube(1.0, (0.5, 0.5, 0.5))
    domain.display_type = "WIRE"
    bake = set_roles(scene, domain, uv_sphere(0.1, (0.4, 0.5, 0.5)), uv_sphere(0.06, (0.5, 0.5, 0.12)))
    bake.pressure_iterations = 20
    live = scene.hapticfluid_live
    live.device = "SIMULATED_FALCON"
    live.auto_resolution = False
    live.resolution = resolution
    return scene


class BakePacer:
    """Holds the add-on's bake (hapticfluid.bake.driver's frame loop, on the bake's worker thread)
    to the test's timer: a frame starts only once the timer has ticked (tick()) since the last
    one started, or after ``wait_s`` (so a UI that froze fails its own check instead of hanging
    the bake). The CPU backend bakes these 24^3 scenes at about 0.03 s a frame, faster than a
    window's timer runs: a check made while the bake runs (the modal's ticks, the Volume that
    follows the frames, a disable or an Esc in the middle) needs the bake to outlast the
    timer's ticks, on any machine. release() lets the bake run at its own pace again."""

    def __init__(self, wait_s=5.0):
        import threading

        from hapticfluid.bake import driver

        self._driver = driver
        self._original = driver.substeps_for_frame
        self._ticked = threading.Event()

        def paced(*args, **kwargs):
            self._ticked.wait(wait_s)
            self._ticked.clear()
            return self._original(*args, **kwargs)

        driver.substeps_for_frame = paced
        on_exit(self.release)

    def tick(self):
        self._ticked.set()

    def release(self):
        self._driver.substeps_for_frame = self._original
        self._ticked.set()


def frames_on_disk(cache_dir):
    folder = os.path.join(cache_dir, "data")
    return sorted(os.listdir(folder)) if os.path.isdir(folder) else []


# --- the window (tests under xvfb-run) -------------------------------------------------------

def window():
    return bpy.context.window_manager.windows[0]


def area(kind="VIEW_3D"):
    """The window's largest area of that type."""
    return max((a for a in window().screen.areas if a.type == kind), key=lambda a: a.width * a.height)


def region(kind="VIEW_3D"):
    return next(r for r in area(kind).regions if r.type == "WINDOW")


def invoke(op, kind="VIEW_3D"):
    """Invoke an operator as a click in that area would."""
    with bpy.context.temp_override(window=window(), area=area(kind)):
        return op("INVOKE_DEFAULT")


def redraw_all():
    for each in window().screen.areas:
        each.tag_redraw()


def close_splash():
    """Esc the splash screen away before any modal operator listens for Esc."""
    window().event_simulate(type="ESC", value="PRESS")
    window().event_simulate(type="ESC", value="RELEASE")


def screenshot(path, kind=None):
    """Save a PNG of the whole window, or of the largest area of ``kind``; return its path.

    Blender 4.x reads the window's front buffer for the screenshot operators; under Xvfb with
    Mesa 25's llvmpipe (Debian 13) that read gives an all-black image (Blender 3.4 with Mesa 22
    reads the drawn window). A window is never all black (its header and panels are grey), so
    then the area's main region is read from its own framebuffer instead (region_screenshot)."""
    with bpy.context.temp_override(window=window(), area=area(kind or "VIEW_3D")):
        if kind is None:
            bpy.ops.screen.screenshot(filepath=path)
        else:
            bpy.ops.screen.screenshot_area(filepath=path)
    check(os.path.getsize(path) > 1000, f"screenshot {path}")
    if not png_rgb(path).any():
        print(f"note: the screenshot operator gave a black image; {path} is read from the region's "
              "framebuffer instead (Blender 4.x front-buffer read under Xvfb)", flush=True)
        region_screenshot(path, kind)
        OVERLAY_ONLY_SCREENSHOTS.add(path)
    else:
        OVERLAY_ONLY_SCREENSHOTS.discard(path)
    return path


# Screenshots saved by region_screenshot: Blender 4.x draws Python draw callbacks into the
# viewport's overlay layer (with the background, grid and outlines; the scene's depth is shared)
# and blends it over the render engine's colour only when the region is put on screen, so in
# these the objects' own shading (Solid mode's grey) is missing: black where an object is.
OVERLAY_ONLY_SCREENSHOTS = set()


def region_screenshot(path, kind=None):
    """Save a PNG of the largest ``kind`` area's main region (VIEW_3D for None), read in a
    POST_PIXEL draw callback of a forced redraw: what was drawn into the region up to then, draw
    callbacks included. The PNG is the window's size (kind None) or the area's, the region at
    its place and the rest black, so pixel coordinates match the screenshot operators'."""
    import numpy as np

    the_area = area(kind or "VIEW_3D")
    the_region = next(r for r in the_area.regions if r.type == "WINDOW")
    got = {}

    def capture():
        import gpu

        if bpy.context.region != the_region or "rgba" in got:
            return
        w, h = the_region.width, the_region.height
        buf = gpu.state.active_framebuffer_get().read_color(0, 0, w, h, 4, 0, 'FLOAT')
        buf.dimensions = w * h * 4
        got["rgba"] = np.array(buf, dtype=np.float32).reshape(h, w, 4)

    space_type = type(the_area.spaces.active)
    handle = space_type.draw_handler_add(capture, (), 'WINDOW', 'POST_PIXEL')
    try:
        the_area.tag_redraw()
        with bpy.context.temp_override(window=window(), area=the_area, region=the_region):
            bpy.ops.wm.redraw_timer(type='DRAW_WIN', iterations=1)
    finally:
        space_type.draw_handler_remove(handle, 'WINDOW')
    check("rgba" in got, f"the {kind or 'VIEW_3D'} region was drawn for {path}")
    if kind is None:
        width, height, x0, y0 = window().width, window().height, the_region.x, the_region.y
    else:
        width, height = the_area.width, the_area.height
        x0, y0 = the_region.x - the_area.x, the_region.y - the_area.y
    image_rgba = np.zeros((height, width, 4), dtype=np.float32)
    image_rgba[:, :, 3] = 1.0
    rgba = got["rgba"]
    h, w = min(rgba.shape[0], height - y0), min(rgba.shape[1], width - x0)
    image_rgba[y0:y0 + h, x0:x0 + w, :3] = np.clip(rgba[:h, :w, :3], 0.0, 1.0)
    image = bpy.data.images.new("hapticfluid_region_screenshot", width, height)
    try:
        image.pixels.foreach_set(image_rgba.reshape(-1))
        image.filepath_raw = path
        image.file_format = 'PNG'
        image.save()
    finally:
        bpy.data.images.remove(image)
    return path


def png_rgb(path):
    """The PNG's pixels as a numpy array (height, width, 3) in 0..1, rows bottom-up."""
    import numpy as np

    image = bpy.data.images.load(path)
    width, height = image.size
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(height, width, 4)[:, :, :3]
    bpy.data.images.remove(image)
    return pixels


def drive(step, timeout_s, describe=lambda: "", first_interval=1.0):
    """Run ``step()`` from a Blender timer until it returns None; it returns the seconds to the next
    call. An exception (a failed check included) or running past ``timeout_s`` fails the test,
    with ``describe()`` added to the time-out message (the phase, a status line)."""
    t0 = time.time()

    def tick():
        try:
            if time.time() - t0 > timeout_s:
                fail(f"timed out after {timeout_s} s {describe()}")
            return step()
        except Exception:
            traceback.print_exc()
            fail("exception in the test timer")

    bpy.app.timers.register(tick, first_interval=first_interval)
