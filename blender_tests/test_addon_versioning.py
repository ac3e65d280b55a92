# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: files saved before a
domain default changed keep what they simulated (properties/versioning.py). A new Domain gets
today's defaults (multigrid CG to a relative residual of 1e-3) and stores them, so reopening it
changes nothing; a domain saved before (its pressure settings not stored, as the older add-on
left them) reopens with the old defaults (Jacobi, no tolerance) and one log line naming it, on
load and when the add-on is enabled after the file was opened; a value the user had set stays;
an object that never was a domain is left alone; a scene-level file from before roles migrates
with the old defaults too. The feel benchmark's scene (hapticfluid.bench.feel.SCENE, "the
add-on's defaults") is the fluid a new domain gives the live session."""

import logging
import os
import tempfile

import bpy

from support import check, cube, empty_file, uv_sphere

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.properties import roles, versioning  # noqa: E402

KEYS = [name for name, _before in versioning.CHANGED_DEFAULTS]


class Lines(logging.Handler):
    def __init__(self):
        super().__init__(logging.DEBUG)
        self.lines = []

    def emit(self, record):
        self.lines.append(record.getMessage())


def same(a, b):
    """Equal settings: names and flags exactly, numbers and vectors to float32's rounding."""
    if isinstance(b, (str, bool)):
        return a == b
    a, b = (list(x) if isinstance(x, (list, tuple)) else [x] for x in (a, b))
    return len(a) == len(b) and all(abs(x - y) <= 1e-6 * max(1.0, abs(y)) for x, y in zip(a, b))


def pressure(obj):
    s = obj.hapticfluid.domain_settings
    return s.pressure_solver, round(s.pressure_tolerance, 9)


def new_domain_keeps_new_defaults(tmp):
    scene = empty_file()
    domain = cube(1.0, (0.5, 0.5, 0.5), "NewDomain")
    roles.assign(scene, "DOMAIN", domain)
    s = domain.hapticfluid.domain_settings
    check(pressure(domain) == ("MULTIGRID", 0.001), f"a new domain: multigrid to 1e-3 ({pressure(domain)})")
    check(all(s.is_property_set(k) for k in KEYS), "a new domain stores the changed settings")
    # The benchmarks of what the hand feels run "the add-on's defaults" (hapticfluid.bench.feel):
    # the fluid a new domain gives the live session.
    from hapticfluid.bench import feel
    from hapticfluid_blender.bake import blender_scene

    fluid = blender_scene.fluid_dict(scene, s)
    differ = {k: (fluid[k], v) for k, v in feel.SCENE.items() if not same(fluid[k], v)}
    check(not differ, f"bench.feel.SCENE is a new domain's fluid (new domain, bench): {differ}")
    path = os.path.join(tmp, "new.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    lines = Lines()
    logging.getLogger(versioning.__name__).addHandler(lines)
    bpy.ops.wm.open_mainfile(filepath=path)
    check(pressure(bpy.data.objects["NewDomain"]) == ("MULTIGRID", 0.001) and lines.lines == [],
          f"reopened: unchanged, nothing logged ({lines.lines})")
    logging.getLogger(versioning.__name__).removeHandler(lines)


def old_file(tmp):
    """A file as the older add-on saved it: a domain whose pressure settings were left at their
    defaults (not stored), one whose user chose multigrid, and a probe."""
    scene = empty_file()
    old = cube(1.0, (0.5, 0.5, 0.5), "OldDomain")
    roles.assign(scene, "DOMAIN", old)
    chosen = cube(1.0, (3.5, 0.5, 0.5), "ChosenDomain")
    chosen.hapticfluid.domain_settings.pressure_solver = "MULTIGRID"  # set by the user (stored)
    chosen.hapticfluid.domain_settings.frame_end = 30
    probe = uv_sphere(0.1, (0.4, 0.5, 0.5), "Probe")
    roles.assign(scene, "PROBE", probe)
    for obj in (old, chosen):
        for key in KEYS:
            if obj is old or key != "pressure_solver":
                obj.hapticfluid.domain_settings.property_unset(key)
    check(not any(old.hapticfluid.domain_settings.is_property_set(k) for k in KEYS), "the old layout: not stored")
    path = os.path.join(tmp, "old.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path


def check_old(how):
    got = {name: pressure(bpy.data.objects[name]) for name in ("OldDomain", "ChosenDomain")}
    check(got == {"OldDomain": ("JACOBI", 0.0), "ChosenDomain": ("MULTIGRID", 0.0)},
          f"{how}: the old domain keeps Jacobi, the chosen solver stays, the unset tolerance is the old 0: {got}")
    probe = bpy.data.objects["Probe"].hapticfluid.domain_settings
    check(not any(probe.is_property_set(k) for k in KEYS), f"{how}: the probe is left alone")


def old_file_keeps_old_defaults(tmp):
    path = old_file(tmp)
    lines = Lines()
    logging.getLogger(versioning.__name__).addHandler(lines)
    bpy.ops.wm.open_mainfile(filepath=path)
    check_old("on load")
    check(len(lines.lines) == 2 and any("'OldDomain'" in ln and "pressure_solver JACOBI" in ln for ln in lines.lines),
          f"a line per domain changed: {lines.lines}")
    resaved = os.path.join(tmp, "resaved.blend")
    bpy.ops.wm.save_as_mainfile(filepath=resaved)
    bpy.ops.wm.open_mainfile(filepath=resaved)
    check_old("saved again and reopened")
    check(len(lines.lines) == 2, "a migrated file has nothing to change")

    hapticfluid_blender.unregister()  # an old file opened while the add-on is disabled
    bpy.ops.wm.open_mainfile(filepath=path)
    hapticfluid_blender.register()
    check_old("on enable")
    check(len(lines.lines) == 4, f"enabling logged the change: {lines.lines[-2:]}")
    logging.getLogger(versioning.__name__).removeHandler(lines)


def linked_domain_is_left_to_its_file(tmp):
    """A domain linked from an older file is read-only here: migrate passes it by (no error)."""
    path = old_file(tmp)
    empty_file()
    with bpy.data.libraries.load(path, link=True) as (src, dst):
        dst.objects = ["OldDomain"]
    linked = bpy.data.objects["OldDomain"]
    bpy.context.scene.collection.objects.link(linked)
    check(linked.library is not None, "the domain is linked")
    check(versioning.migrate() == [] and pressure(linked) == ("MULTIGRID", 0.001),
          f"a linked domain is left as its file has it: {pressure(linked)}")


def scene_level_file_keeps_old_defaults():
    scene = empty_file()
    domain = cube(1.0, (0.5, 0.5, 0.5), "LegacyDomain")
    scene.hapticfluid_bake.domain = domain  # the layout before roles: settings on the scene, unset
    from hapticfluid_blender.properties import legacy

    legacy.migrate()
    check(domain.hapticfluid.role == "DOMAIN" and pressure(domain) == ("JACOBI", 0.0),
          f"a scene-level file's domain keeps the old defaults: {pressure(domain)}")


def main():
    hapticfluid_blender.register()
    tmp = tempfile.mkdtemp(prefix="hf_versioning_")
    new_domain_keeps_new_defaults(tmp)
    old_file_keeps_old_defaults(tmp)
    scene_level_file_keeps_old_defaults()
    linked_domain_is_left_to_its_file(tmp)
    hapticfluid_blender.unregister()
    print("versioning checks passed")


main()
