# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: re-bake from a
change in Blender. A probe keyed at frames 1, 10, 20 and 24 (linear) is baked with a checkpoint
every 5 frames; moving its key at frame 20 outdates frames 11 on (the segment from 10), the panel
line and the Timeline bar say so ("probe keys changed from frame 11: re-bake 11-24 from the
checkpoint at 10"), Resume re-bakes only 11-24 (frames 1-10 not rewritten), the cache is then up
to date, a changed setting re-bakes every frame, and Free removes the kept checkpoints."""

import os
import tempfile

import bpy

from support import bake_scene, check, finish, move_key

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.bake import cache_plan  # noqa: E402
from hapticfluid_blender.properties import roles  # noqa: E402
from hapticfluid_blender.ui import cache_bar, physics_panels  # noqa: E402

PATH = ((1, (0.3, 0.5, 0.55)), (10, (0.45, 0.5, 0.55)), (20, (0.6, 0.5, 0.5)), (24, (0.65, 0.5, 0.55)))


def frame_ids(cache, frames):
    out = {}
    for f in frames:
        st = os.stat(os.path.join(cache, "data", f"fluid_data_{f:04d}.vdb"))
        out[f] = (st.st_ino, st.st_mtime_ns)
    return out


def main():
    hapticfluid_blender.register()
    from hapticfluid.bake.scene import CHECKPOINT_EVERY

    tmp = tempfile.mkdtemp(prefix="hf_blender_rebake_")
    cache = os.path.join(tmp, "cache")
    scene, s, _domain, probe, _source = bake_scene(cache, resolution=16, frames=(1, 24), probe_path=PATH)
    group = roles.domain_settings_of(scene)
    default = type(group).bl_rna.properties["checkpoint_every"].default
    check(default == CHECKPOINT_EVERY, f"Checkpoint Every defaults to the package's {CHECKPOINT_EVERY} ({default})")
    group.checkpoint_every = 5
    for fc in probe.animation_data.action.fcurves:
        for k in fc.keyframe_points:
            k.interpolation = "LINEAR"
    cost = physics_panels.checkpoint_cost(group)
    check(cost == "Checkpoints: 105 KB each, 4 kept", f"the panel shows the checkpoints' disk cost: {cost!r}")

    check(bpy.ops.hapticfluid.bake() == {"FINISHED"}, f"bake 1-24: {s.status}")
    check(sorted(os.listdir(os.path.join(cache, "checkpoint"))) ==
          ["state.npz"] + [f"state_{f:04d}.npz" for f in (5, 10, 15, 20)], "checkpoints kept at 5, 10, 15, 20")
    entry = cache_plan.refresh(scene)
    check(entry.kind == "complete" and entry.text == "frames 1-24 are baked and up to date",
          f"after the bake every frame is up to date: {entry.text!r} {entry.problem!r}")
    check(cache_bar.runs(scene) == [(1, 24, "baked")], f"the bar is blue over 1-24: {cache_bar.runs(scene)}")

    move_key(probe, 20, 0.05)  # x and z: the linear segments 10-20 and 20-24 change
    cache_plan._pending.discard(scene.name)
    bpy.context.view_layer.update()
    check(scene.name in cache_plan._pending, "editing the probe's keys marks the plan for a refresh")
    entry = cache_plan.refresh(scene)
    check(entry.kind == "inputs"
          and entry.text == "probe keys changed from frame 11: re-bake 11-24 from the checkpoint at 10",
          f"the plan names the first changed frame and the checkpoint: {entry.text!r} {entry.problem!r}")
    check(cache_bar.runs(scene) == [(1, 10, "baked"), (11, 24, "outdated")],
          f"the bar: blue 1-10, red 11-24: {cache_bar.runs(scene)}")

    kept = frame_ids(cache, range(1, 11))
    redone = frame_ids(cache, range(11, 25))
    check(bpy.ops.hapticfluid.bake_resume() == {"FINISHED"}, f"Resume: {s.status}")
    check("re-bake 11-24 from the checkpoint at 10" in s.status and "14 frame(s)" in s.status,
          f"the status says what Resume did: {s.status}")
    check(frame_ids(cache, range(1, 11)) == kept, "frames 1-10 were kept as they were (not rewritten)")
    now = frame_ids(cache, range(11, 25))
    check(all(now[f] != redone[f] for f in now), "frames 11-24 were written again")
    entry = cache_plan.refresh(scene)
    check(entry.kind == "complete", f"after Resume the cache is up to date: {entry.text!r}")

    s.vorticity = 0.9
    check(cache_plan.current(scene) is None and cache_bar.runs(scene) == [(1, 24, "outdated")],
          "a changed setting: the old plan ('up to date') is not shown before the new one is made")
    entry = cache_plan.refresh(scene)
    check(entry.kind == "settings" and entry.text == "fluid.vorticity changed: re-bake every frame, 1-24",
          f"a changed setting outdates every frame: {entry.text!r}")
    check(cache_bar.runs(scene) == [(1, 24, "outdated")], f"the bar is red over 1-24: {cache_bar.runs(scene)}")

    check(bpy.ops.hapticfluid.bake_free() == {"FINISHED"}, f"Free: {s.status}")
    check(not os.path.exists(os.path.join(cache, "checkpoint")), "Free removed the kept checkpoints")
    hapticfluid_blender.unregister()
    finish("re-bake from a change in Blender: ok")


main()
