# SPDX-License-Identifier: GPL-3.0-or-later
"""Baking: the probe's motion in, an OpenVDB frame sequence out (see docs/ARCHITECTURE.md).

    from hapticfluid.bake import load_scene, bake
    scene = load_scene("scene.json").with_resolution(192)   # perform at 64^3, bake at 192^3
    result = bake(scene, progress=lambda p: print(p.text()))

Modules: :mod:`~hapticfluid.bake.scene` (the scene description and its JSON form),
:mod:`~hapticfluid.bake.trajectory` (keyed rigid transforms, interpolation, velocities),
:mod:`~hapticfluid.bake.cache` (file naming, manifest, checkpoint, atomic writes),
:mod:`~hapticfluid.bake.verify` (are the frame files what the bake wrote? used by resume and --verify),
:mod:`~hapticfluid.bake.plan` (which frames still hold what the scene bakes, and where a re-bake starts),
:mod:`~hapticfluid.bake.driver` (the loop), :mod:`~hapticfluid.bake.command` (the CLI).
"""

from hapticfluid.bake.cache import BakeError, free_cache, frame_path, list_frames, read_manifest
from hapticfluid.bake.driver import BakeProgress, BakeResult, apply_probe, bake
from hapticfluid.bake.plan import RebakePlan, rebake_plan
from hapticfluid.bake.scene import BakeScene, ProbeSpec, SmokeSource, load_scene, scene_from_dict
from hapticfluid.bake.trajectory import Motion, Pose, Trajectory

__all__ = [
    "BakeError",
    "BakeProgress",
    "BakeResult",
    "BakeScene",
    "Motion",
    "Pose",
    "ProbeSpec",
    "RebakePlan",
    "SmokeSource",
    "Trajectory",
    "apply_probe",
    "bake",
    "free_cache",
    "frame_path",
    "list_frames",
    "load_scene",
    "read_manifest",
    "rebake_plan",
    "scene_from_dict",
]
