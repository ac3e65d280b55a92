# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a Python that has Blender as a module (`bpy` from PyPI), never in the build tree.

    python bpy_check.py ORDER EXTENSION_ZIP WORK_DIR

ORDER is `bpy-first` or `hapticfluid-first`: which of the two native worlds loads first into the
one process (Blender's own OpenVDB/TBB/Imath and the ones the hapticfluid wheel vendors). Either
way the process then
  - installs the extension zip through `bpy.ops.extensions.package_install_files` (Blender
    unpacks its wheel) and enables it,
  - gives the objects their roles through the Physics tab's Set Role operator, bakes 3 frames of
    a 16^3 scene through the add-on's Bake operator and loads the Volume,
  - starts a live session on the simulated Falcon through the Start operator (background mode:
    the main-thread ticks that Blender's timer would run are run here), reads field snapshots and
    a non-zero fluid force while the simulated hand sweeps the probe, records the motion through
    the Record operator (keys on the probe), and stops it through the Stop operator,
  - steps a 16^3 simulation with `hapticfluid`, writes a VDB holding a known box of density and
    reads it back through bpy's Volume grids: the grid's name, type and bounds must be the box's.
and at the end disables the add-on (its unregister() runs, the session's threads are gone).
Exits non-zero on the first failed check. WORK_DIR must be new: Blender's user folders
(config, scripts, extensions) are put there, so the user's own profile is never touched.
"""

import importlib
import os
import sys
import threading
import time
import zipfile

# Inside a Blender binary (`blender -b --python bpy_check.py -- bpy-first ZIP WORK`, as
# test_blender.sh runs it) bpy is loaded already: only bpy-first, and the caller sets the
# BLENDER_USER_* folders under WORK before Blender starts.
IN_BLENDER = "bpy" in sys.modules
ARGS = sys.argv[sys.argv.index("--") + 1:] if IN_BLENDER else sys.argv[1:]
ORDER, ZIP, WORK = ARGS[0], os.path.abspath(ARGS[1]), os.path.abspath(ARGS[2])
if ORDER not in ("bpy-first", "hapticfluid-first") or (IN_BLENDER and ORDER != "bpy-first"):
    sys.exit(f"ORDER must be bpy-first or (bpy module only) hapticfluid-first, not {ORDER!r}")
os.makedirs(WORK, exist_ok=IN_BLENDER)
for name in ("CONFIG", "SCRIPTS", "EXTENSIONS", "DATAFILES"):  # read when bpy starts
    if IN_BLENDER and os.environ.get(f"BLENDER_USER_{name}") != os.path.join(WORK, name.lower()):
        sys.exit(f"start Blender with BLENDER_USER_{name}={os.path.join(WORK, name.lower())} (test_blender.sh does)")
    os.environ[f"BLENDER_USER_{name}"] = os.path.join(WORK, name.lower())

EXTENSION_MODULE = "bl_ext.user_default.hapticfluid"  # id "hapticfluid" in the user repository
RES = 16
H = 1.0 / RES  # m, cell size of the bake's and the engine's 1 m domain
# The known VDB: a 32^3 grid of 1/32 m voxels, density 1 in cells [lo, hi) and 0 elsewhere.
# Blender bounds a volume by the OpenVDB leaf nodes (8^3 voxels) that hold active voxels, so
# the bounds it must report are the box rounded out to multiples of 8 voxels: 0.25, 0.0, 0.5 ..
# 0.5, 0.75, 1.0 m (a different extent on each axis, so a swapped axis fails too).
# Blender 4.2 puts the bounds through the outer voxels' centres, 5.0 on their outer faces: both
# are within half a voxel of these.
BOX_RES, BOX_LEAF = 32, 8
BOX_H = 1.0 / BOX_RES
BOX_LO, BOX_HI = (9, 2, 17), (14, 20, 31)


def check(condition, message):
    if not condition:
        raise AssertionError(message)
    print("ok:", message, flush=True)


def loaded_native_libraries():
    """Shared objects mapped into this process whose names say OpenVDB, TBB, Imath or blosc."""
    keys = ("openvdb", "tbb", "imath", "blosc")
    with open("/proc/self/maps") as f:
        paths = {line.split()[-1] for line in f if "/" in line and ".so" in line}
    return sorted(p for p in paths if any(k in os.path.basename(p).lower() for k in keys))


def import_hapticfluid_from_extension_wheel():
    """Before bpy exists: put the extension's wheel for this Python, unpacked, on sys.path and import it."""
    site = os.path.join(WORK, "wheel-site")
    with zipfile.ZipFile(ZIP) as z:
        tag = f"-cp{sys.version_info[0]}{sys.version_info[1]}-"  # the wheel Blender would pick
        wheel_name = next(n for n in z.namelist() if n.startswith("wheels/") and n.endswith(".whl") and tag in n)
        z.extract(wheel_name, WORK)
    with zipfile.ZipFile(os.path.join(WORK, wheel_name)) as w:
        w.extractall(site)
    sys.path.insert(0, site)
    import hapticfluid

    check(hapticfluid.__file__.startswith(site), f"hapticfluid imported from the extension's wheel: {hapticfluid.__file__}")
    return hapticfluid


def engine_writes_known_vdb(hf, path):
    import numpy as np

    sim = hf.Simulation(resolution=(RES, RES, RES), domain_size=(1.0, 1.0, 1.0))
    sim.set_smoke_source(centre=(0.5, 0.5, 0.15), radius=0.15, density=1.0, temperature=1.0)
    sim.set_probe(centre=(0.3, 0.5, 0.5), radius=0.12, velocity=(0.5, 0.0, 0.0))
    for _ in range(3):
        report = sim.step(1 / 30)
    density = sim.density()
    check(density.shape == (RES, RES, RES) and np.isfinite(density).all() and density.max() > 0,
          f"a {RES}^3 simulation steps (max density {density.max():.3f}, force {report.force.tolist()} N)")
    box = np.zeros((BOX_RES, BOX_RES, BOX_RES), np.float32)
    box[BOX_LO[0]:BOX_HI[0], BOX_LO[1]:BOX_HI[1], BOX_LO[2]:BOX_HI[2]] = 1.0
    hf.write_vdb(path, box, voxel_size=BOX_H)
    check(os.path.getsize(path) > 0, f"hapticfluid wrote {os.path.basename(path)} (OpenVDB {hf.openvdb_version()})")


def world_bounds(obj):
    import bpy
    from mathutils import Vector

    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    corners = [obj.matrix_world @ Vector(c) for c in ev.bound_box]
    return ([min(c[i] for c in corners) for i in range(3)], [max(c[i] for c in corners) for i in range(3)])


def bpy_reads_known_vdb(path):
    import bpy

    vol = bpy.data.volumes.new("known box")
    vol.filepath = path
    check(vol.grids.load(), "bpy loads the VDB that hapticfluid wrote")
    grids = {g.name: g.data_type for g in vol.grids}
    check(grids == {"density": "FLOAT"}, f"bpy sees one float grid 'density': {grids}")
    obj = bpy.data.objects.new("known box", vol)
    bpy.context.scene.collection.objects.link(obj)
    lo, hi = world_bounds(obj)
    want_lo = [(c // BOX_LEAF) * BOX_LEAF * BOX_H for c in BOX_LO]
    want_hi = [-(-c // BOX_LEAF) * BOX_LEAF * BOX_H for c in BOX_HI]
    check(all(abs(lo[i] - want_lo[i]) <= 0.5 * BOX_H and abs(hi[i] - want_hi[i]) <= 0.5 * BOX_H for i in range(3)),
          f"bpy's bounds of the density {lo} .. {hi} m are the written box's leaf nodes {want_lo} .. {want_hi} m")


def install_extension():
    import bpy

    result = bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
    check(result == {"FINISHED"}, f"the extension zip installs ({result})")
    check(EXTENSION_MODULE in bpy.context.preferences.addons, f"the add-on {EXTENSION_MODULE} is enabled")
    prefs = importlib.import_module(EXTENSION_MODULE + ".ui.prefs")
    check(prefs.unsupported_here() is None and prefs.package_problem() is None,
          "the add-on finds its engine loadable here (platform, Python, glibc)")
    py = f"cp{sys.version_info[0]}{sys.version_info[1]}"
    too_new = prefs.unsupported_here([f"hapticfluid-0.1.0-{py}-{py}-manylinux_2_99_x86_64.whl"])
    check(too_new is not None and "glibc 2.99" in too_new, f"where glibc is too old it says so in one line: {too_new}")
    import builtins

    real_import = builtins.__import__

    def no_egl(name, *args, **kwargs):  # a system without libglvnd's libEGL
        if name == "hapticfluid":
            raise ImportError("libEGL.so.1: cannot open shared object file: No such file or directory")
        return real_import(name, *args, **kwargs)

    builtins.__import__ = no_egl
    try:
        no_egl_problem = prefs.package_problem()
    finally:
        builtins.__import__ = real_import
    check(no_egl_problem is not None and no_egl_problem.startswith("Install your system's libEGL.so.1 (Debian/Ubuntu: apt"),
          f"without libEGL it names the package to install: {no_egl_problem}")
    other = prefs.unsupported_here(["hapticfluid-0.1.0-cp310-cp310-manylinux_2_28_x86_64.whl"])
    check(other is not None and "CPython 3.10, not this Blender's Python" in other, f"and for another Python: {other}")
    import hapticfluid

    return hapticfluid


def bake_through_operator(cache_dir):
    import bpy

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.5, 0.5, 0.5))
    domain = bpy.context.active_object
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.12, location=(0.3, 0.5, 0.55))
    probe = bpy.context.active_object
    probe.keyframe_insert("location", frame=1)
    probe.location = (0.65, 0.5, 0.55)
    probe.keyframe_insert("location", frame=3)
    bpy.ops.mesh.primitive_ico_sphere_add(radius=0.12, location=(0.5, 0.5, 0.2))
    source = bpy.context.active_object
    for obj, role in ((domain, "DOMAIN"), (probe, "PROBE"), (source, "SOURCE")):  # the Physics tab's button
        bpy.context.view_layer.objects.active = obj
        result = bpy.ops.hapticfluid.set_role(role=role)
        check(result == {"FINISHED"} and obj.hapticfluid.role == role, f"Set Role makes {obj.name} the {role} ({result})")
    s = importlib.import_module(EXTENSION_MODULE + ".properties.roles").settings_of(scene)  # the settings, through the roles
    check((s.domain, s.probe, s.source) == (domain, probe, source), "the objects hold their roles")
    s.resolution, s.frame_start, s.frame_end, s.substeps = RES, 1, 3, 1
    s.cache_dir = cache_dir
    scene.frame_start, scene.frame_end = 1, 3
    result = bpy.ops.hapticfluid.bake()
    check(result == {"FINISHED"}, f"the Bake operator finished ({result}, status: {s.status})")
    files = sorted(os.listdir(os.path.join(cache_dir, "data")))
    check(files == [f"fluid_data_{f:04d}.vdb" for f in (1, 2, 3)], f"three frame files: {files}")
    obj = s.volume_object
    check(obj is not None and obj.type == "VOLUME" and obj.data.is_sequence, "a Volume sequence shows the bake")
    scene.frame_set(3)
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    check(ev.data.grids.load(), "frame 3's grids load")
    names = {g.name: g.data_type for g in ev.data.grids}
    check(names.get("density") == "FLOAT", f"frame 3 has a float density grid: {names}")
    lo, hi = world_bounds(obj)
    check(all(-H <= lo[i] and hi[i] <= 1 + H and hi[i] > lo[i] for i in range(3)),
          f"the baked smoke {lo} .. {hi} m lies inside the 1 m domain")


def live_threads():
    return [t for t in threading.enumerate() if t.name.startswith("hapticfluid-live")]


def live_session_through_operators():
    """Start, Record (twice: begin and end) and Stop through the operators, on the simulated
    Falcon with the sweeping hand. In background mode nothing runs bpy.app.timers, so the
    ticks the Start operator's timer would make are made here, through the add-on's own tick."""
    import bpy

    live_ops = importlib.import_module(EXTENSION_MODULE + ".live.live_ops")
    scene = bpy.context.scene
    live = scene.hapticfluid_live
    live.device, live.hand_gesture = "SIMULATED_FALCON", "SWEEP"
    live.auto_resolution, live.resolution = False, RES
    result = bpy.ops.hapticfluid.live_start()
    check(result == {"FINISHED"}, f"the Start operator starts a session on the simulated Falcon ({result}, {live.status})")
    run = live_ops.run_for(scene)
    run.controller.wait_started()

    def run_for_seconds(seconds):
        forces, end = [], time.monotonic() + seconds
        while time.monotonic() < end:
            state = live_ops.tick(run)
            if state == "stopped":
                raise AssertionError(f"the session stopped: {run.controller.report}")
            forces.append(live.force_n)
            time.sleep(live_ops.TICK_S)
        return forces

    forces = run_for_seconds(1.5)
    check(bpy.ops.hapticfluid.live_record() == {"FINISHED"} and live.is_recording, "Record starts recording")
    forces += run_for_seconds(1.5)
    check(bpy.ops.hapticfluid.live_record() == {"FINISHED"} and not live.is_recording, "Record again finishes it")
    c = run.controller
    check(live.is_running and c.last_sequence >= 2, f"the session runs and field snapshots arrive ({c.last_sequence})")
    check(max(forces) >= 1e-3, f"the sweeping probe feels the fluid: |F| up to {max(forces):.4g} N (>= 1 mN) "
          f"(sim {live.sim_rate_hz:.1f} Hz, haptic {live.haptic_rate_hz:.0f} Hz, {live.device_state})")
    check(c.keys_written > 0, f"Record keyed {c.keys_written} pose(s) of the probe")
    session = c.session
    check(bpy.ops.hapticfluid.live_stop() == {"FINISHED"}, "the Stop operator stops it")
    check(session.state == "stopped" and not live_threads() and not live.is_running
          and live_ops.run_for(scene) is None, "the session stopped, its threads joined")


def main():
    vdb_path = os.path.join(WORK, "known_box.vdb")
    if ORDER == "hapticfluid-first":
        hf = import_hapticfluid_from_extension_wheel()
        engine_writes_known_vdb(hf, vdb_path)
        import bpy

        print("bpy", bpy.app.version_string, "imported after hapticfluid", flush=True)
        install_extension()
    else:
        import bpy

        print("bpy", bpy.app.version_string, "imported first", flush=True)
        hf = install_extension()
        ext_dir = os.environ["BLENDER_USER_EXTENSIONS"]
        check(hf.__file__.startswith(ext_dir), f"hapticfluid comes from the installed extension's wheel: {hf.__file__}")
        engine_writes_known_vdb(hf, vdb_path)
    bake_through_operator(os.path.join(WORK, "bake_cache"))
    bpy_reads_known_vdb(vdb_path)
    live_session_through_operators()
    libs = loaded_native_libraries()
    print("native libraries in this process:\n  " + "\n  ".join(libs), flush=True)
    ours = [p for p in libs if "hapticfluid.libs" in p or os.path.basename(os.path.dirname(p)) == "hapticfluid"]
    check(not ours, "hapticfluid loads no OpenVDB/TBB/Imath/blosc library of its own: they are inside "
          f"its module, hidden from Blender's ({len(libs)} mapped are Blender's or the system's)")
    bpy.ops.preferences.addon_disable(module=EXTENSION_MODULE)
    check(EXTENSION_MODULE not in bpy.context.preferences.addons and not hasattr(bpy.types.Scene, "hapticfluid_live")
          and not live_threads(), "the add-on disables (unregister() runs, no operator or session thread left)")
    print(f"PASS {ORDER} with Blender {bpy.app.version_string}", flush=True)
    if bpy.app.version[:2] == (4, 2):
        # bpy 4.2 as a module segfaults in its own C++ exit handlers (type destructors calling
        # into the finalized interpreter) once any property with a Python callback (update=,
        # poll=) was registered, even after it was unregistered: a bare PropertyGroup with
        # FloatProperty(update=...) does it, no hapticfluid loaded; bpy 5.0 exits cleanly.
        # Everything is checked by now, so leave without running those handlers.
        os._exit(0)


if __name__ == "__main__":
    main()
