# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: the add-on's
defects of issue 16 stay fixed. A refused bake replaces the status line; mirrored and
90-degree-turned domains bake their world box, other turns and a rotation applied to the mesh
are refused with what is wrong; an Empty or a plane as probe get messages about their size and
volume; an unsaved .blend bakes into Blender's temporary folder; bake_blend.py exits 1 when the
bake fails; a stale is_baking is cleared by enabling the add-on; the Volume goes into the active
collection with the material's density in the viewport; a changed setting shows "cache out of
date"; Resume extends after End is raised; Free removes the Volume and restores the domain; the
panels (drawn into a recording layout) show units, headings, the read-only progress, wrapped
errors with the fix first, and the missing-package warning."""

import os
import subprocess
import sys
import tempfile
from types import SimpleNamespace

import bpy

from support import SOURCE_DIR as SOURCE, bake_scene, check, cube, refused, settings

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.bake import blender_scene, cache_plan  # noqa: E402
from hapticfluid_blender.properties import object_props  # noqa: E402
from hapticfluid_blender.render import volume  # noqa: E402
from hapticfluid_blender.ui import panels, physics_panels, prefs  # noqa: E402


class Recorder:
    """A stand-in for UILayout that records what a panel draws."""

    def __init__(self, log=None, **attrs):
        self.log = log if log is not None else []
        self.attrs = attrs
        self.enabled = True
        self.active = True
        self.use_property_split = False
        self.use_property_decorate = True
        self.scale_y = 1.0

    def _child(self, kind, **kw):
        child = Recorder(self.log, parent=self, **kw)
        self.log.append((kind, kw, child))
        return child

    def column(self, **kw):
        return self._child("column", **kw)

    def row(self, **kw):
        return self._child("row", **kw)

    def split(self, **kw):
        return self._child("split", **kw)

    def box(self):
        return self._child("box")

    def separator(self):
        pass

    def label(self, text="", icon="NONE"):
        self.log.append(("label", {"text": text, "icon": icon}, self))

    def prop(self, data, name, **kw):
        self.log.append(("prop", {"name": name, **kw}, self))

    def operator(self, idname, **kw):
        props = SimpleNamespace()
        self.log.append(("operator", {"idname": idname, **kw, "props": props}, self))
        return props

    def operator_menu_enum(self, idname, prop, **kw):
        self.log.append(("operator_menu_enum", {"idname": idname, "prop": prop, **kw}, self))

    def labels(self):
        return [kw["text"] for kind, kw, _ in self.log if kind == "label"]


class FakeRegion:
    width = 320


class FakeContext:
    def __init__(self, obj=None):
        self.scene = bpy.context.scene
        self.object = obj
        self.region = FakeRegion()
        self.preferences = bpy.context.preferences


def draw(panel_cls, obj=None):
    """Call the panel's draw with a stand-in self holding a Recorder as its layout (``obj``: the
    active object, for the Physics tab's panels)."""
    layout = Recorder()
    stand_in = SimpleNamespace(layout=layout)
    stand_in._layout = lambda context: physics_panels._RolePanel._layout(stand_in, context)
    panel_cls.draw(stand_in, FakeContext(obj))
    return layout


def new_scene(cache_dir):
    scene, s, _, _, _ = bake_scene(cache_dir, resolution=12, frames=(1, 2), probe_radius=0.1,
                                   probe_path=((0, (0.4, 0.5, 0.5)), (4, (0.55, 0.5, 0.5))))
    s.pressure_iterations = 4
    return scene, s


def domains(tmp):
    scene, s = new_scene(os.path.join(tmp, "domains"))
    d = s.domain
    d.scale = (-2.0, 1.0, 1.0)  # mirrored along x, 2 m wide
    d.location = (1.0, 0.5, 0.5)
    bpy.context.view_layer.update()
    box = blender_scene.scene_dict(scene, s)["domain"]
    rounded = [[round(v, 6) for v in box[k]] for k in ("origin", "size")]
    check(rounded == [[0.0, 0.0, 0.0], [2.0, 1.0, 1.0]], f"a mirrored domain bakes its world box: {box}")
    d.scale = (2.0, 1.0, 1.0)
    d.rotation_euler = (0.0, 0.0, 1.5707963267948966)  # a quarter turn: 1 m along x, 2 m along y
    bpy.context.view_layer.update()
    box = blender_scene.scene_dict(scene, s)["domain"]
    check([round(v, 5) for v in box["size"]] == [1.0, 2.0, 1.0],
          f"a domain turned 90 degrees bakes its world bounding box: {box}")
    d.rotation_euler = (0.0, 0.0, 0.5235987755982988)  # 30 degrees
    bpy.context.view_layer.update()
    refused(bpy.ops.hapticfluid.bake, "clear the rotation", "turned 30 degrees",
            "90-degree turns and mirrors are accepted")
    check(s.status.startswith("bake not started: clear the rotation"),
          f"the refusal replaces the status line, fix first: {s.status!r}")
    d.scale = (1.0, 1.0, 1.0)
    d.rotation_euler = (0.0, 0.0, 0.7853981633974483)
    bpy.context.view_layer.update()
    bpy.ops.object.select_all(action="DESELECT")
    d.select_set(True)
    bpy.context.view_layer.objects.active = d
    bpy.ops.object.transform_apply(location=False, rotation=True, scale=False)  # Ctrl+A > Rotation
    check(tuple(d.rotation_euler) == (0.0, 0.0, 0.0), "the rotation is applied to the mesh")
    refused(bpy.ops.hapticfluid.bake, "make the domain", "an axis-aligned box", "not a box along its axes")


def probes(tmp):
    scene, s = new_scene(os.path.join(tmp, "probes"))
    empty = bpy.data.objects.new("Pointer", None)  # an Empty: display size 1 m, the domain is 1 m
    scene.collection.objects.link(empty)
    empty.location = (0.5, 0.5, 0.5)
    s.probe, s.probe_shape = empty, "SPHERE"
    text = refused(bpy.ops.hapticfluid.bake, "resize the sphere probe 'Pointer'", "Empty's Size (1)",
                   "radius 1 m", "the radius must be at most")
    check("[" not in text, f"no coordinate ranges in the message: {text}")
    empty.empty_display_size = 0.1
    radius = blender_scene.scene_dict(scene, s)["probe"]["radius"]
    check(abs(radius - 0.1) < 1e-6, f"an Empty of Size 0.1 is a 0.1 m sphere ({radius})")
    bpy.ops.mesh.primitive_plane_add(size=0.2, location=(0.5, 0.5, 0.5))
    s.probe, s.probe_shape = bpy.context.active_object, "MESH"
    text = refused(bpy.ops.hapticfluid.bake, "give the probe 'Plane' a closed mesh with thickness",
                   "the probe mesh has no volume")
    check("triangles" not in text.split("no volume")[0] and "rows" not in text,
          f"no JSON internals in the message: {text}")


def unsaved_file():
    scene, s = new_scene("//hapticfluid_cache")  # the default, and the file was never saved
    check(not bpy.data.filepath, "the .blend is unsaved")
    check(bpy.ops.hapticfluid.bake() == {"FINISHED"}, f"an unsaved .blend bakes: {s.status}")
    folder = os.path.join(bpy.app.tempdir, "hapticfluid_cache")
    check(os.path.exists(os.path.join(folder, "data", "fluid_data_0002.vdb")),
          f"its relative cache folder is in Blender's temporary folder {folder}")
    check(folder in s.status and "temporary folder" in s.status and "until you save" in s.status,
          f"the status says where: {s.status}")


def command_line_failure(tmp):
    scene, s = new_scene(os.path.join(tmp, "cli"))
    s.domain = None  # the bake must fail
    path = os.path.join(tmp, "no_domain.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    script = os.path.join(SOURCE, "addon", "hapticfluid_blender", "bake", "bake_blend.py")
    run = subprocess.run([bpy.app.binary_path, "--background", "--factory-startup", "--python-use-system-env", path,
                          "--python-exit-code", "1",
                          "--python", script], capture_output=True, text=True, timeout=300)
    check(run.returncode == 1 and "give a mesh the Domain role" in run.stderr,
          f"bake_blend.py exits 1 when the bake fails (exit {run.returncode}): {run.stderr[-300:]}")
    with open(os.path.join(SOURCE, "README.md"), encoding="utf-8") as f:
        readme = [line for line in f if "bake_blend.py" in line and line.startswith("blender ")]
    check(readme and all("--python-exit-code 1" in line for line in readme),
          f"the README's bake_blend.py command line exits non-zero on failure: {readme}")


def stale_flag_cleared_on_enable():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    s = settings()
    s.domain = cube(1.0, (0.5, 0.5, 0.5))
    s.is_baking = True  # what disabling the add-on in the middle of a bake used to leave
    hapticfluid_blender.unregister()
    hapticfluid_blender.register()
    s = settings()
    check(not s.is_baking and "add-on was disabled" in s.status, f"enabling the add-on clears it: {s.status!r}")
    check(bpy.ops.hapticfluid.bake.poll(), "Bake is usable again")


def bake_cycle(tmp):
    scene, s = new_scene(os.path.join(tmp, "cycle"))
    fx = bpy.data.collections.new("FX")
    scene.collection.children.link(fx)
    bpy.context.view_layer.active_layer_collection = bpy.context.view_layer.layer_collection.children["FX"]
    s.density_scale = 30.0
    check(bpy.ops.hapticfluid.bake() == {"FINISHED"}, f"bake 1..2: {s.status}")
    vol = s.volume_object
    check(vol is not None and vol.name in fx.objects and vol.name not in scene.collection.objects,
          "the Volume object is in the active collection")
    factor = volume.VIEWPORT_DENSITY_FACTOR
    check(vol.data.display.density == 30.0 * factor,
          f"viewport display density = the material's x {factor} ({vol.data.display.density})")
    s.density_scale = 12.0
    nodes = [n for n in vol.active_material.node_tree.nodes if n.bl_idname == "ShaderNodeVolumePrincipled"]
    check(vol.data.display.density == 12.0 * factor and len(nodes) == 2
          and all(n.inputs["Density"].default_value == 12.0 for n in nodes),
          "changing Render Density after the bake updates the material (Cycles' and EEVEE's shaders) and the "
          "viewport density together")
    check(s.domain.display_type == "WIRE" and s.domain.hide_render, "the domain shows as a wire frame after the bake")
    check(cache_plan.changed_inputs(scene, s) == [], "right after the bake the cache is up to date")
    from hapticfluid.bake.scene import CACHE_INPUTS

    check(set(cache_plan.inputs(scene, s)) == set(CACHE_INPUTS),
          f"the record holds what the package lists as the cache's inputs: {sorted(cache_plan.inputs(scene, s))}")
    scene.frame_set(3)  # playing the timeline does not change the inputs
    check(cache_plan.changed_inputs(scene, s) == [], "moving the timeline keeps the cache up to date")

    s.frame_end = 3  # raise End and Resume: the bake is extended
    check(cache_plan.changed_inputs(scene, s) == [], "raising End alone does not put the cache out of date")
    check(bpy.ops.hapticfluid.bake_resume() == {"FINISHED"}, f"Resume after raising End: {s.status}")
    check(os.path.exists(os.path.join(tmp, "cycle", "data", "fluid_data_0003.vdb"))
          and s.volume_object.data.frame_duration == 3, "Resume baked frame 3 and the Volume shows frames 1..3")

    s.vorticity = 0.9
    check(cache_plan.changed_inputs(scene, s) == ["fluid.vorticity"],
          "a changed fluid setting is named as the re-bake plan names it")
    labels = " ".join(draw(panels.HAPTICFLUID_PT_bake).labels())
    check("Bake again" in labels and "cache is out of date" in labels and "fluid.vorticity" in labels,
          f"the panel says the cache is out of date: {labels}")
    s.vorticity = 0.4
    s.source_density, s.cache_dir = 2.0, s.cache_dir + "_elsewhere"
    check(cache_plan.changed_inputs(scene, s) == ["source.density"],
          f"the source's settings count, the cache's folder does not: {cache_plan.changed_inputs(scene, s)}")
    s.source_density, s.cache_dir = 1.0, s.cache_dir[:-len("_elsewhere")]
    record = s.baked_inputs
    s.baked_inputs = '{"Vorticity": 0.4, "Resolution": 12}'  # a record from before the package's list
    check(cache_plan.changed_inputs(scene, s) == [], "an old record is no answer (the plan says)")
    s.baked_inputs = record

    layout = draw(panels.HAPTICFLUID_PT_bake)
    check(not any("out of date" in t for t in layout.labels()), "set back: no warning")
    s.vorticity = 0.9
    check(bpy.ops.hapticfluid.bake_resume() == {"FINISHED"}
          and "fluid.vorticity changed: re-bake every frame, 1-3" in s.status,
          f"Resume after a changed setting re-bakes every frame and says why: {s.status}")
    check(cache_plan.changed_inputs(scene, s) == [], "after it the cache is up to date")
    s.is_baking, s.progress = True, 0.25
    layout = draw(panels.HAPTICFLUID_PT_bake)
    bars = [(kw, owner) for kind, kw, owner in layout.log if kind == "prop" and kw["name"] == "progress"]
    check(len(bars) == 1 and not bars[0][1].enabled and bars[0][0].get("slider") and "25 %" in bars[0][0]["text"],
          f"progress is a read-only bar while baking: {bars}")
    s.is_baking = False

    s.status = ("bake not started: make the domain 'Cube' an axis-aligned box (e.g. a new cube scaled to size, or "
                "Clear Rotation before applying): its mesh is not a box along its axes (face 0 is not axis-aligned)")
    lines = [t for t in draw(panels.HAPTICFLUID_PT_bake).labels() if t]
    start = next(i for i, t in enumerate(lines) if t.startswith("bake not started"))
    wrapped = lines[start:start + 4]
    check(len(wrapped) >= 3 and all(len(t) <= 50 for t in wrapped) and "make the domain" in wrapped[0],
          f"a long error wraps at the panel's width with the fix on the first line: {wrapped}")

    free = bpy.ops.hapticfluid.bake_free
    check(free() == {"FINISHED"}, f"Free: {s.status}")
    check(s.volume_object is None and not any(o.type == "VOLUME" for o in bpy.data.objects),
          "Free removed the Volume object showing the deleted frames")
    check(s.domain.display_type == "TEXTURED" and not s.domain.hide_render, "Free restored the domain's display")
    check(cache_plan.changed_inputs(scene, s) == [], "no cache, nothing out of date")
    check("invoke" in vars(hapticfluid_blender.operators.bake_ops.HAPTICFLUID_OT_bake_free),
          "Free has an invoke (invoke_confirm: it asks before deleting when clicked)")


def sub_panels():
    """The Physics tab's sub-panels (the domain left by bake_cycle is the active object's role)."""
    domain = settings().domain
    check(domain is not None, "a domain to draw the panels for")
    expected = {"DOMAIN": ["Resolution", "Fluid", "Pressure Solver", "Cache", "Display"],
                "PROBE": ["Shape", "Velocity Source"], "SOURCE": ["Emission"]}
    found = {}
    for cls in physics_panels.classes:
        if getattr(cls, "bl_parent_id", None) == "HAPTICFLUID_PT_physics":
            check(hasattr(bpy.types, cls.bl_idname) and cls.bl_context == "physics",
                  f"sub-panel {cls.bl_label} is registered in the Physics tab")
            found.setdefault(cls.role, []).append(cls.bl_label)
    check(found == expected, f"the roles' sub-panels: {found}")
    fluid = draw(physics_panels.SUB_PANELS["HAPTICFLUID_PT_domain_fluid"], domain)
    names = {kw["name"]: kw for kind, kw, _ in fluid.log if kind == "prop"}
    ui = object_props.ui_name
    check("kg/m³" in ui("fluid_density") and "m/s²" in names["gravity"]["text"]
          and "(K)" in ui("source_temperature") and "(Pa)" in ui("write_pressure"),
          "units: kg/m³, m/s², K, Pa")
    cache = draw(physics_panels.SUB_PANELS["HAPTICFLUID_PT_domain_cache"], domain)
    headings = [kw.get("heading") for kind, kw, _ in cache.log if kind == "column"]
    check("Grids" in headings, f"the grid check boxes have a heading: {headings}")
    frame_owners = {id(owner) for kind, kw, owner in cache.log
                    if kind == "prop" and kw["name"] in ("frame_start", "frame_end")}
    check(len(frame_owners) == 1 and any(kind == "column" and id(child) in frame_owners
                                         for kind, _kw, child in cache.log),
          "Start and End are one above the other (a column), readable at the default width")
    resolution = draw(physics_panels.SUB_PANELS["HAPTICFLUID_PT_domain_resolution"], domain)
    headings = [kw.get("heading") for kind, kw, _ in resolution.log if kind == "column"]
    check("Time Steps" in headings, f"the substep check box has a heading: {headings}")


def missing_package():
    check(prefs.HapticFluidPreferences.bl_idname == hapticfluid_blender.__name__,
          f"the preferences are the add-on's, not its ui folder's: {prefs.HapticFluidPreferences.bl_idname}")
    saved = sys.modules.get("hapticfluid")
    sys.modules["hapticfluid"] = None  # import hapticfluid now raises ImportError
    try:
        problem = prefs.package_problem()
        check(problem is not None and problem.startswith("Install the hapticfluid package"),
              f"the missing package is detected, fix first: {problem}")
        # The source tree's manifest lists no wheels (its comment names placeholder ones): the
        # add-on came without its engine, whatever this Blender's Python (a Python 3.13 Blender
        # was told "built for CPython 3.11", read from the comment).
        check("came without its engine" in problem and "build_extension.sh" in problem and "CPython" not in problem,
              f"a wheel-less install says the engine did not come with it and how to get it: {problem}")
        p = draw(prefs.HapticFluidPreferences)
        check(any("Install the hapticfluid package" in t for t in p.labels()), "the preferences show the warning")
        panel = draw(panels.HAPTICFLUID_PT_bake)
        check(panel.labels() and panel.labels()[0].startswith("Install the hapticfluid"),
              f"the panel shows it first: {panel.labels()[:2]}")
    finally:
        sys.modules["hapticfluid"] = saved
    check(prefs.package_problem() is None, "with the package back, no warning")
    check(any("is importable" in t for t in draw(prefs.HapticFluidPreferences).labels()),
          "the preferences say the package is importable")
    check(prefs.manifest_wheels() == [] and prefs.unsupported_here() is None,
          f"the source tree's manifest lists no wheels: {prefs.manifest_wheels()}, {prefs.unsupported_here()}")
    with tempfile.TemporaryDirectory() as tmp:  # a built extension's manifest: wheels appended
        manifest = os.path.join(tmp, "blender_manifest.toml")
        with open(manifest, "w", encoding="utf-8") as f:
            f.write('# `wheels = ["./wheels/hapticfluid-<version>-cp311-...whl"]` appended\nid = "hapticfluid"\n'
                    'wheels = ["./wheels/hapticfluid-0.1.0-cp311-cp311-manylinux_2_28_x86_64.whl",\n'
                    '          "./wheels/hapticfluid-0.1.0-cp313-cp313-manylinux_2_28_x86_64.whl"]\n')
        listed = prefs.manifest_wheels(manifest)
    check(listed == ["hapticfluid-0.1.0-cp311-cp311-manylinux_2_28_x86_64.whl",
                     "hapticfluid-0.1.0-cp313-cp313-manylinux_2_28_x86_64.whl"],
          f"the wheels the manifest lists, not its comment's: {listed}")
    other = prefs.unsupported_here(["hapticfluid-0.1.0-cp310-cp310-manylinux_2_28_x86_64.whl"])
    check(other is not None and "CPython 3.10, not this Blender's Python" in other, f"another Python's wheel: {other}")
    py = f"cp{sys.version_info[0]}{sys.version_info[1]}"
    compound = prefs.unsupported_here([f"hapticfluid-0.1.0-{py}-{py}-manylinux_2_98_x86_64.manylinux_2_99_x86_64.whl"])
    check(compound is not None and "glibc 2.98 or newer" in compound,
          f"a wheel tagged for two glibc floors needs the older one: {compound}")


def main():
    hapticfluid_blender.register()
    with tempfile.TemporaryDirectory() as tmp:
        domains(tmp)
        probes(tmp)
        unsaved_file()
        command_line_failure(tmp)
        stale_flag_cleared_on_enable()
        bake_cycle(tmp)
        sub_panels()
        missing_package()
    hapticfluid_blender.unregister()
    print("add-on defects test passed")


main()
