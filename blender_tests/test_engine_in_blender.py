# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: the engine module
loads in Blender's Python, makes its own EGL context beside Blender's, and steps a simulation
whose probe follows a Blender object. Any failure raises, so Blender exits 1."""

import os
import sys

import bpy
import numpy as np

import hapticfluid as hf
from support import check


def main():
    # The module is built for Debian's /usr/bin/python3 (3.11 on Debian 12, 3.13 on Debian 13), the
    # Python Debian's Blender embeds; its file name says which (e.g. _core.cpython-311-x86_64-linux-gnu.so).
    core = os.path.basename(sys.modules["hapticfluid._core"].__file__)
    tag = f"cpython-{sys.version_info.major}{sys.version_info.minor}-"
    check(tag in core, f"Blender's Python is {sys.version.split()[0]}, the module {core} is built for another")
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.15, location=(0.4, 0.5, 0.5))
    probe = bpy.context.active_object

    sim = hf.Simulation(resolution=(24, 24, 24), domain_size=(1.0, 1.0, 1.0), fluid_density=1000.0,
                        pressure_iterations=30)
    print("hapticfluid in Blender", bpy.app.version_string, "on", sim.device["renderer"])
    sim.set_smoke_source((0.5, 0.5, 0.15), 0.1)

    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 6
    probe.location = (0.35, 0.5, 0.5)
    probe.keyframe_insert("location", frame=1)
    probe.location = (0.55, 0.5, 0.5)
    probe.keyframe_insert("location", frame=6)
    for fcurve in probe.animation_data.action.fcurves:
        for key in fcurve.keyframe_points:
            key.interpolation = "LINEAR"  # constant velocity: the drag must point backwards

    fps = scene.render.fps / scene.render.fps_base
    dt = 1.0 / fps
    previous = None
    forces = []
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        location = np.array(probe.matrix_world.translation, dtype=np.float64)
        velocity = (location - previous) / dt if previous is not None else np.zeros(3)
        previous = location
        radius = 0.15 * max(probe.matrix_world.to_scale())
        sim.set_probe(tuple(location), radius, velocity=tuple(velocity))
        report = sim.step(dt)
        forces.append(report.force)
        print(f"frame {frame}: x={location[0]:.3f} m force={report.force} N")

    forces = np.array(forces)
    check(np.all(np.isfinite(forces)), "forces are finite")
    check(np.all(forces[:, 2] > 0), "buoyancy pushes the submerged probe up")
    check(np.all(forces[1:, 0] < 0), "the fluid resists the probe moving along +x")
    check(sim.density().max() > 0.5, "the smoke source filled its cells")
    classes = sim.cell_classes()
    check(np.count_nonzero(classes == hf.CELL_BOUNDARY) > 0, "the probe is voxelized")

    try:
        sim.set_probe((2.0, 0.5, 0.5), 0.15)
    except hf.InvalidArgumentError as err:
        print("rejected as expected:", err)
    else:
        raise AssertionError("a probe outside the domain was accepted")
    print("blender engine test passed")


main()
