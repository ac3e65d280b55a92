# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside a Blender 4.2+ that has a window (scripts/prefs_screenshot.sh starts it under Xvfb):
what an artist does with the extension repository, then two screenshots of Preferences.

    blender --python prefs_screenshot.py -- REPO_DIR OUT_DIR

With Blender's user folders wherever the caller's environment put them (a fresh, empty set):
  1. turns off the splash and the extensions.blender.org repository (offline here, it would put
     an alert above the entry in Get Extensions), allows online access (Blender asks before
     installing from any repository), adds REPO_DIR (the folder build_extension.sh writes: one
     zip and its index.json) with the Add Remote Repository operator, URL
     file://REPO_DIR/index.json, refreshes it, installs hapticfluid from it and enables it (the
     operators behind the buttons),
  2. imports hapticfluid from the wheel Blender unpacked and steps an 8^3 smoke simulation,
     printing "engine: ..." lines (a failure here fails the run: exit status 1),
  3. opens Preferences (Edit > Preferences: its own window, made 1000x460) on Add-ons, searched
     for "hapticfluid", its entry expanded (tagline, type, maintainer, version, file, and the
     add-on's own preferences), and captures that window from the X server into
     OUT_DIR/prefs_addons.png once two captures SETTLE_S apart are the same (drawn),
  4. switches it to Get Extensions, searched and expanded the same way (version, license,
     repository, path), and captures OUT_DIR/prefs_get_extensions.png; then quits.
Captures are taken from outside Blender (xwd of the Preferences window, found by its title with
xdotool, else of the root window; ImageMagick's convert writes the PNG): Blender's own
screen.screenshot gives black images under Xvfb (Blender 4.3).
"""

import os
import subprocess
import sys
import traceback

import bpy

ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(ARGS) != 2:
    sys.exit("usage: blender --python prefs_screenshot.py -- REPO_DIR OUT_DIR")
REPO, OUT = (os.path.abspath(a) for a in ARGS)
PKG_ID = "hapticfluid"
SETTLE_S = 3.0  # seconds between captures: Xvfb + llvmpipe under load redraw slowly
MAX_CAPTURES = 20
MIN_PNG_BYTES = 20000  # a window not drawn yet (one flat colour) compresses to ~2 KB
WINDOW = (1000, 460)  # the Preferences window's size in the 1280x800 screen


def log(message):
    print("prefs_screenshot:", message, flush=True)


def fail(message):
    log("FAILED: " + message)
    os._exit(1)  # from a timer, sys.exit would only end the timer


def install_from_repository():
    prefs = bpy.context.preferences
    prefs.system.use_online_access = True  # the artist's "Allow Online Access"
    prefs.view.show_splash = False
    for repo in prefs.extensions.repos:
        if repo.module == "blender_org" and repo.use_remote_url:
            # Offline here (a chroot, an air-gapped studio): otherwise Get Extensions opens with
            # "Repository Alert: extensions.blender.org remote data unavailable" above the entry.
            repo.enabled = False
    url = "file://" + os.path.join(REPO, "index.json")
    result = bpy.ops.preferences.extension_repo_add(name="hapticfluid", remote_url=url, type="REMOTE")
    if result != {"FINISHED"}:
        fail(f"adding the repository {url}: {result}")
    repo = prefs.extensions.repos[-1]
    # The extensions operators' repo_index counts enabled repositories only.
    index = [r.module for r in prefs.extensions.repos if r.enabled].index(repo.module)
    if bpy.ops.extensions.repo_sync(repo_index=index) != {"FINISHED"}:
        fail(f"refreshing the repository '{repo.name}'")
    result = bpy.ops.extensions.package_install(repo_index=index, pkg_id=PKG_ID, enable_on_install=True)
    module = f"bl_ext.{repo.module}.{PKG_ID}"
    if result != {"FINISHED"} or module not in prefs.addons:
        fail(f"installing {PKG_ID} from '{repo.name}' and enabling it as {module}: {result}")
    log(f"Blender {bpy.app.version_string}: repository '{repo.name}' ({url}) added, {module} installed and enabled")
    return index, module


def engine_check():
    """The add-on's package, imported inside this Blender, is the native one from the wheel."""
    try:
        import numpy as np
        import hapticfluid as hf

        log(f"engine: hapticfluid {hf.__version__} from {hf.__file__}")
        log(f"engine: _core from {hf._core.__file__}")
        log(f"engine: Python {sys.version.split()[0]}, numpy {np.__version__}, OpenVDB {hf.openvdb_version()}")
        sim = hf.Simulation(resolution=(8, 8, 8), domain_size=(1.0, 1.0, 1.0))
        sim.set_smoke_source(centre=(0.5, 0.5, 0.2), radius=0.2, density=1.0, temperature=1.0)
        sim.step(1 / 30)
        peak = float(np.asarray(sim.density()).max())
        log(f"engine: 8^3 Simulation stepped once, density max {peak:.4f}")
        if not peak > 0:
            fail("the simulation's density stayed 0")
    except Exception:
        traceback.print_exc()
        fail("hapticfluid does not run inside Blender")


def prefs_window():
    for window in bpy.context.window_manager.windows:
        if window.screen.areas[0].type == "PREFERENCES":
            return window
    return None


def x_window():
    """The X id of Preferences' window (its title is "Blender Preferences" or "Preferences")."""
    found = subprocess.run(["xdotool", "search", "--name", "Preferences"], capture_output=True, text=True)
    ids = found.stdout.split()
    return ids[-1] if found.returncode == 0 and ids else None


def grab(window_id):
    """The window's pixels as PNG bytes, read from the X server."""
    target = ["-id", window_id] if window_id else ["-root"]
    xwd = subprocess.run(["xwd", "-silent", *target], capture_output=True)
    if xwd.returncode != 0 or not xwd.stdout:
        fail(f"xwd {' '.join(target)}: {xwd.stderr.decode(errors='replace')}")
    conv = subprocess.run(["convert", "xwd:-", "-strip", "png:-"], input=xwd.stdout, capture_output=True)
    if conv.returncode != 0:
        fail(f"convert: {conv.stderr.decode(errors='replace')}")
    return conv.stdout


def redraw():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            area.tag_redraw()


def steps(repo_index, module):
    """A generator the timer steps through; each yield is the seconds until the next step."""
    wm = bpy.context.window_manager
    prefs = bpy.context.preferences

    # Edit > Preferences > Add-ons, searched, the entry expanded.
    wm.addon_search = PKG_ID
    bpy.ops.preferences.addon_expand(module=module)
    window = wm.windows[0]  # a timer has no window in its context
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.screen.userpref_show(section="ADDONS")
    if prefs_window() is None:
        fail("Preferences did not open")
    yield SETTLE_S
    window_id = x_window()
    if window_id:
        # Blender opens Preferences at about 690x540; larger, the expanded entry fits without
        # scrolling. With no window manager (Xvfb) X applies the size and place as asked.
        subprocess.run(["xdotool", "windowsize", window_id, str(WINDOW[0]), str(WINDOW[1])], check=False)
        subprocess.run(["xdotool", "windowmove", window_id, "60", "40"], check=False)
    yield from settled_capture(window_id, "prefs_addons.png")

    # Get Extensions, searched, the entry expanded.
    wm.extension_search = PKG_ID
    bpy.ops.extensions.package_show_set(pkg_id=PKG_ID, repo_index=repo_index)
    prefs.active_section = "EXTENSIONS"
    yield from settled_capture(window_id, "prefs_get_extensions.png")


def settled_capture(window_id, name):
    """Captures every SETTLE_S seconds until two captures in a row are the same (the UI has
    finished drawing: llvmpipe under load can take many seconds), then writes the last."""
    path = os.path.join(OUT, name)
    previous = None
    for attempt in range(1, MAX_CAPTURES + 1):
        redraw()
        yield SETTLE_S
        png = grab(window_id)
        if png == previous and len(png) > MIN_PNG_BYTES:
            with open(path, "wb") as f:
                f.write(png)
            log(f"captured {path} (window {window_id or 'root'}, {len(png)} bytes, stable after {attempt} captures)")
            return
        previous = png
    fail(f"{name}: the window kept changing over {MAX_CAPTURES} captures")


class Timer:
    def __init__(self, generator):
        self.generator = generator

    def __call__(self):
        try:
            return next(self.generator)
        except StopIteration:
            log("done")
            os._exit(0)  # both PNGs are written; nothing to save
        except Exception:
            traceback.print_exc()
            fail("a step raised")


def main():
    os.makedirs(OUT, exist_ok=True)
    repo_index, module = install_from_repository()
    engine_check()
    bpy.app.timers.register(Timer(steps(repo_index, module)), first_interval=SETTLE_S)


main()
