# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: roles per object
(issue 16 item 1). The Set Role operator gives roles, refuses a second Domain naming the object
that has it and a non-mesh Domain; the property itself takes a refused role back; a removed role
keeps its settings on the object; a duplicated domain is refused at Bake with both names. The
Physics tab's button and panels draw per role. roles.settings_of reads each setting from the
role that owns it. A .blend saved with the old scene-level layout migrates on load (and when the
add-on is enabled after the file was opened) with every setting kept and a log line; a .blend
saved with roles reopens with them. The timeline's cache bar range follows the bake. The fluid's
fields offer the engine's ranges (FluidSettings.limits()), the bake's scene check the same."""

import logging
import os
import tempfile
from types import SimpleNamespace

import bpy

from support import bake_scene, check, cube, empty_file, ico_sphere, refused, settings, uv_sphere

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.properties import legacy, object_props, roles  # noqa: E402
from hapticfluid_blender.ui import cache_bar, panels, physics_panels  # noqa: E402


class Recorder:
    """A stand-in for UILayout recording the calls a draw function makes."""

    def __init__(self, log=None):
        self.log = log if log is not None else []

    def __getattr__(self, name):  # row, column, split, box, label, prop, operator, ...
        def call(*args, **kw):
            child = Recorder(self.log)
            self.log.append((name, args, kw, child))
            return child
        return call

    def calls(self, name):
        return [(args, kw, child) for kind, args, kw, child in self.log if kind == name]


def draw(function, obj):
    layout = Recorder()
    context = SimpleNamespace(scene=bpy.context.scene, object=obj, region=SimpleNamespace(width=320),
                              preferences=bpy.context.preferences)
    stand_in = SimpleNamespace(layout=layout)
    stand_in._layout = lambda ctx: physics_panels._RolePanel._layout(stand_in, ctx)
    function(stand_in, context)
    return layout


def set_role(obj, role):
    with bpy.context.temp_override(object=obj):
        return bpy.ops.hapticfluid.set_role(role=role)


def set_role_operator():
    scene = empty_file()
    a, b = cube(1.0, (0.5, 0.5, 0.5), "BoxA"), cube(1.0, (3.0, 0.5, 0.5), "BoxB")
    pointer = bpy.data.objects.new("Pointer", None)
    scene.collection.objects.link(pointer)
    check(set_role(a, "DOMAIN") == {"FINISHED"} and a.hapticfluid.role == "DOMAIN", "Set Role makes BoxA the Domain")
    refused(lambda: set_role(b, "DOMAIN"), "Remove the Domain role from 'BoxA' first", "one domain")
    check(b.hapticfluid.role == "NONE", "BoxB was not made a second domain")
    refused(lambda: set_role(pointer, "DOMAIN"), "Choose a mesh for the Domain role", "'Pointer' is of type Empty")
    b.hapticfluid.role = "DOMAIN"  # a script, past the operator: the property's update takes it back
    check(b.hapticfluid.role == "NONE", "the role property refuses a second domain too")
    check(set_role(pointer, "PROBE") == {"FINISHED"}, "an Empty can be the probe")
    s = settings(scene)
    check((s.domain, s.probe, s.source) == (a, pointer, None), "settings_of finds the holders")

    s.resolution, s.probe_shape = 40, "SPHERE"
    check(a.hapticfluid.domain_settings.resolution == 40 and pointer.hapticfluid.probe_settings.probe_shape == "SPHERE",
          "the view writes each setting onto the object holding its role")
    check(s.source_density == object_props.HapticFluidSourceSettings.bl_rna.properties["source_density"].default,
          "without a source, its settings read as their defaults")
    try:
        s.source_density = 2.0
        raise AssertionError("a source setting was written with no source")
    except roles.RoleError as err:
        check(str(err).startswith("give an object the Smoke Source role first"), f"refused: {err}")

    check(set_role(a, "NONE") == {"FINISHED"} and settings(scene).domain is None, "None removes the role")
    check(a.hapticfluid.domain_settings.resolution == 40, "the settings stay on the object")
    set_role(a, "DOMAIN")
    check(settings(scene).resolution == 40, "and come back with the role")

    dup = a.copy()  # what Shift+D does: the role is copied, no check runs
    scene.collection.objects.link(dup)
    problem = settings(scene).problem
    check(problem is not None and "'BoxA'" in problem and f"'{dup.name}'" in problem,
          f"a duplicated domain is a problem naming both: {problem}")
    refused(bpy.ops.hapticfluid.bake, "keep the Domain role on one object", "BoxA")
    bpy.data.objects.remove(dup)
    bystander = cube(0.2, (5.0, 0.0, 0.0), "Bystander")
    check(settings(scene).domain == a and roles.role_of(bystander) == "NONE"
          and not bystander.is_property_set("hapticfluid"),
          "looking up the roles stores nothing on objects without one")
    return a, b, pointer


def physics_tab(a, b, pointer):
    button = draw(physics_panels.draw_physics_button, b)
    menus = button.calls("operator_menu_enum")
    check(len(menus) == 1 and menus[0][0] == ("hapticfluid.set_role", "role") and menus[0][1]["text"] == "hapticfluid",
          "an object with no role gets the hapticfluid button (a role menu) among the physics buttons")
    button = draw(physics_panels.draw_physics_button, a)
    ops = button.calls("operator")
    check(len(ops) == 1 and ops[0][1]["icon"] == "X" and ops[0][2].role == "NONE",
          "an object with a role gets the button with X, which removes the role")
    check(not physics_panels.HAPTICFLUID_PT_physics.poll(SimpleNamespace(object=b))
          and physics_panels.HAPTICFLUID_PT_physics.poll(SimpleNamespace(object=a)),
          "the hapticfluid panel shows for an object with a role only")
    for cls in physics_panels.classes[2:]:
        shown = [o.name for o in (a, b, pointer) if cls.poll(SimpleNamespace(object=o))]
        want = {"DOMAIN": ["BoxA"], "PROBE": ["Pointer"], "SOURCE": []}[cls.role]
        check(shown == want, f"sub-panel {cls.bl_label} shows for the {cls.role.lower()}: {shown}")
    main = draw(physics_panels.HAPTICFLUID_PT_physics.draw, a)
    ops = [(kw.get("text"), kw.get("depress")) for args, kw, _ in main.calls("operator")
           if args[0].endswith("set_role")]
    check(ops == [("Domain", True), ("Probe", False), ("Smoke Source", False)], f"the role as buttons: {ops}")
    bake_ops = [args[0] for args, _kw, _ in main.calls("operator") if not args[0].endswith("set_role")]
    check(bake_ops == ["hapticfluid.bake", "hapticfluid.bake_resume", "hapticfluid.bake_free"],
          f"the domain's panel has the bake buttons: {bake_ops}")
    summary = draw(panels.HAPTICFLUID_PT_bake.draw, None)
    texts = [kw.get("text") for _a, kw, _ in summary.calls("label")]
    check(all(t in texts for t in ("Domain", "BoxA", "Probe", "Pointer", "Smoke Source", "(none)")),
          f"the Scene tab's summary lists who holds which role: {texts}")


def old_layout_values():
    """A value differing from the default for every setting of the old scene-level group."""
    values = {}
    for _attr, cls in roles.GROUPS.values():
        for key in cls.__annotations__:
            prop = cls.bl_rna.properties[key]
            if prop.type == "INT":
                values[key] = prop.default + 1 if prop.default + 1 <= prop.hard_max else prop.default - 1
            elif prop.type == "FLOAT":
                values[key] = prop.default + 0.5 if prop.default + 0.5 <= prop.hard_max else prop.default / 2
            elif prop.type == "BOOLEAN":
                values[key] = not prop.default
            elif prop.type == "ENUM":
                values[key] = next(i.identifier for i in prop.enum_items if i.identifier != prop.default)
            elif prop.type == "STRING":
                values[key] = prop.default + "_old"
    values["is_baking"] = True  # saved during a bake: cleared after the move, with a note
    return values


class Lines(logging.Handler):
    def __init__(self):
        super().__init__()
        self.lines = []

    def emit(self, record):
        self.lines.append(record.getMessage())


def check_migrated(values, how):
    scene = bpy.context.scene
    s = settings(scene)
    check((s.domain.name, s.probe.name, s.source.name) == ("OldDomain", "OldProbe", "OldSource"),
          f"{how}: the old pointers became roles")
    for key, want in values.items():
        if key in ("is_baking", "status"):
            continue
        got = getattr(s, key)
        same = abs(got - want) <= 1e-6 * max(1.0, abs(want)) if isinstance(want, float) else got == want
        check(same, f"{how}: {key} kept ({got!r})")
    check(s.volume_object is not None and s.volume_object.name == "OldVolume", f"{how}: the Volume kept")
    check(not s.is_baking and s.status == object_props.INTERRUPTED_NOTE,
          f"{how}: is_baking moved, then cleared as interrupted: {s.status!r}")
    check(not scene.is_property_set("hapticfluid_bake"), f"{how}: the old scene group is gone")


def old_file_migrates(tmp):
    scene = empty_file()
    domain = cube(1.0, (0.5, 0.5, 0.5), "OldDomain")
    probe = uv_sphere(0.1, (0.4, 0.5, 0.5), "OldProbe")
    source = ico_sphere(0.1, (0.5, 0.5, 0.2), "OldSource")
    vol = bpy.data.objects.new("OldVolume", bpy.data.volumes.new("OldVolume"))
    scene.collection.objects.link(vol)
    old = scene.hapticfluid_bake  # the layout before roles, still registered (hidden)
    old.domain, old.probe, old.source = domain, probe, source
    values = old_layout_values()
    for key, value in values.items():
        setattr(old, key, value)
    old.volume_object = vol
    check(all(o.hapticfluid.role == "NONE" for o in (domain, probe, source)), "the old layout: no roles on objects")
    path = os.path.join(tmp, "old_layout.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)

    lines = Lines()
    logging.getLogger(legacy.__name__).addHandler(lines)
    bpy.ops.wm.open_mainfile(filepath=path)
    check_migrated(values, "on load")
    check(len(lines.lines) == 1 and all(w in lines.lines[0] for w in (
        "moved scene 'Scene'", "Domain 'OldDomain' (with the bake settings and cache)", "Probe 'OldProbe'",
        "Smoke Source 'OldSource'")), f"one log line says what moved: {lines.lines}")

    roles_path = os.path.join(tmp, "with_roles.blend")
    bpy.ops.wm.save_as_mainfile(filepath=roles_path)
    bpy.ops.wm.open_mainfile(filepath=roles_path)
    check_migrated(values, "saved with roles and reopened")
    check(len(lines.lines) == 1, "a file with roles has nothing to move")

    hapticfluid_blender.unregister()  # an old file opened while the add-on is disabled
    bpy.ops.wm.open_mainfile(filepath=path)
    check("hapticfluid_bake" in bpy.context.scene.keys(), "the old group is in the file")
    hapticfluid_blender.register()
    check_migrated(values, "on enable")
    check(len(lines.lines) == 2, f"enabling logged the move: {lines.lines[-1:]}")
    logging.getLogger(legacy.__name__).removeHandler(lines)


def old_file_without_domain(tmp):
    scene = empty_file()
    probe = uv_sphere(0.1, (0.4, 0.5, 0.5), "OnlyProbe")
    scene.hapticfluid_bake.probe = probe
    scene.hapticfluid_bake.resolution = 33
    lines = legacy.migrate()
    check(probe.hapticfluid.role == "PROBE" and len(lines) == 1 and "no domain was chosen" in lines[0],
          f"without a domain the probe moves and the line says the bake settings stay: {lines}")
    check(scene.hapticfluid_bake.resolution == 33 and scene.hapticfluid_bake.probe is None,
          "the unused settings stay in the old group; the pointer is cleared (nothing moves twice)")
    check(legacy.migrate() == [], "a second migration moves nothing")


def cache_bar_range(tmp):
    scene, s, _domain, _probe, _source = bake_scene(os.path.join(tmp, "bar"), resolution=12, frames=(3, 5))
    s.pressure_iterations = 4
    check(cache_bar.baked_range(scene) is None, "no bake: no bar")
    check(bpy.ops.hapticfluid.bake() == {"FINISHED"}, f"bake 3..5: {s.status}")
    check(cache_bar.baked_range(scene) == (3, 5, "baked"), f"the bar spans the baked frames: "
                                                           f"{cache_bar.baked_range(scene)}")
    s.vorticity = 0.9
    check(cache_bar.baked_range(scene) == (3, 5, "outdated"), "a changed setting: the bar says out of date")
    s.vorticity = 0.4
    s.is_baking = True
    check(cache_bar.baked_range(scene)[2] == "baking", "while baking")
    s.is_baking = False
    check(bpy.ops.hapticfluid.bake_free() == {"FINISHED"} and cache_bar.baked_range(scene) is None,
          "Free: no bar")
    check(cache_bar._handle is None, "no draw handler in background mode")


def limits_are_the_engines(tmp):
    """The fluid's and the source's fields offer what the engine takes: their min and max are
    hapticfluid.FluidSettings.limits() (MAX_SOURCE_DENSITY, MAX_SOURCE_TEMPERATURE_K for the
    source; an excluded max is the float32 below it), the slider's range inside them. One answer
    to "is 500 allowed?": the field takes it and so does the bake's scene check."""
    import hapticfluid as hf
    from hapticfluid.bake import scene_from_dict

    from hapticfluid_blender.bake import blender_scene

    def near(a, b):
        return abs(a - b) <= 1e-6 * max(1.0, abs(b))

    ranges = dict(hf.FluidSettings.limits(),
                  source_density={"min": 0.0, "max": hf.MAX_SOURCE_DENSITY, "max_exclusive": False},
                  source_temperature={"min": 0.0, "max": hf.MAX_SOURCE_TEMPERATURE_K, "max_exclusive": False})
    seen = []
    for cls in (object_props.HapticFluidDomainSettings, object_props.HapticFluidSourceSettings):
        for name, r in ranges.items():
            if name not in cls.bl_rna.properties:
                continue
            p = cls.bl_rna.properties[name]
            top = p.hard_max < r["max"] and near(p.hard_max, r["max"]) if r["max_exclusive"] else near(p.hard_max,
                                                                                                     r["max"])
            check(near(p.hard_min, r["min"]) and top and p.hard_min <= p.soft_min <= p.soft_max <= p.hard_max,
                  f"{name}: the field's {p.hard_min}..{p.hard_max} (slider {p.soft_min}..{p.soft_max}) is the "
                  f"engine's {r}")
            seen.append(name)
    check({"fluid_density", "vorticity", "heat_buoyancy", "smoke_dissipation", "heat_dissipation",
           "pressure_iterations", "pressure_tolerance", "source_density", "source_temperature"} <= set(seen),
          f"every fluid and source field with an engine range reads it: {seen}")
    scene, s, _domain, _probe, _source = bake_scene(os.path.join(tmp, "limits"), resolution=12,
                                                    frames=(1, 1))
    s.vorticity = 500.0
    check(s.vorticity == 500.0, f"the field takes vorticity 500 ({s.vorticity})")
    baked = scene_from_dict(blender_scene.scene_dict(scene, s))
    check(baked.fluid["vorticity"] == 500.0, "and so does the bake's scene check")
    s.vorticity = 2000.0
    check(s.vorticity == 1000.0, f"the field stops at the engine's 1000 ({s.vorticity})")


def main():
    hapticfluid_blender.register()
    with tempfile.TemporaryDirectory() as tmp:
        limits_are_the_engines(tmp)
        physics_tab(*set_role_operator())
        old_file_migrates(tmp)
        old_file_without_domain(tmp)
        cache_bar_range(tmp)
    hapticfluid_blender.unregister()
    print("add-on roles test passed")


main()
