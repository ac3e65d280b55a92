# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: a Blender object's
own mesh (vertices + loop triangles) and matrix_world become a mesh probe, as the add-on and the
bake driver will pass them; its buoyancy is rho g V of the scaled, turned cube, its pose follows
the object's animation through set_probe_pose, and an open mesh (Suzanne) is refused with a
message that names the Blender fix. Any failure raises, so Blender exits 1."""

import bpy
import numpy as np

import hapticfluid as hf
from support import check


def object_mesh(obj):
    mesh = obj.data
    mesh.calc_loop_triangles()
    vertices = np.array([v.co[:] for v in mesh.vertices], dtype=np.float32)
    triangles = np.array([t.vertices[:] for t in mesh.loop_triangles], dtype=np.int32)
    return vertices, triangles


def main():
    rho, g = 1000.0, 9.81
    bpy.ops.mesh.primitive_cube_add(size=0.3, location=(0.5, 0.5, 0.5), rotation=(0.3, 0.2, 0.1))
    cube = bpy.context.active_object
    cube.scale = (1.0, 0.6, 0.8)
    bpy.context.view_layer.update()
    volume = 0.3**3 * 0.6 * 0.8

    sim = hf.Simulation(resolution=(32, 32, 32), fluid_density=rho, pressure_iterations=2)
    vertices, triangles = object_mesh(cube)
    sim.set_mesh_probe(vertices, triangles, cube.matrix_world)  # mathutils.Matrix taken as is
    report = sim.step(0.01)
    print("cube buoyancy", report.force, "expected", rho * g * volume)
    check(abs(report.force[2] - rho * g * volume) < 0.03 * rho * g * volume, f"buoyancy {report.force}")
    check(np.abs(report.torque_centre - np.array(cube.location)).max() < sim.cell_size, "centroid off the cube")

    scene = bpy.context.scene
    for frame, x in ((2, 0.45), (3, 0.55)):
        cube.location.x = x
        cube.keyframe_insert("location", frame=frame)
    for frame in (2, 3):
        scene.frame_set(frame)
        sim.set_probe_pose(cube.matrix_world, velocity=(0.05 * 30, 0, 0))
        report = sim.step(1 / 30)
        check(abs(report.torque_centre[0] - cube.matrix_world.translation.x) < sim.cell_size,
              f"frame {frame}: probe at {report.torque_centre}, object at {cube.matrix_world.translation}")

    bpy.ops.mesh.primitive_monkey_add(size=0.4, location=(0.5, 0.5, 0.5))
    monkey = bpy.context.active_object
    vertices, triangles = object_mesh(monkey)
    try:
        sim.set_mesh_probe(vertices, triangles, monkey.matrix_world)
    except hf.InvalidArgumentError as e:
        check("Fill Holes" in str(e), f"unhelpful message: {e}")
    else:
        raise AssertionError("Suzanne (open) was accepted")
    check(sim.probe["kind"] == "mesh" and sim.probe["triangle_count"] == 12, "the refused mesh changed the probe")
    sim.close()
    print("mesh probe in Blender: ok")


main()
