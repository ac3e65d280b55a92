# SPDX-License-Identifier: GPL-3.0-or-later
"""A chained bake run with openjd-cli, a worker killed in the middle of a chunk, and the job
completing with every frame identical to a single-task bake (issue 31, item 4).

The scene is tests/farm/tiny_scene.json made 9 frames long (16^3 cells). Steps:

1. Reference: the one-task bake (`python3 -m hapticfluid.farm bake`, as the shipped template's
   single Bake step runs it) of frames 1-9 into its own cache.
2. `hapticfluid.farm write --bake-chunk 3 --chunk-size 2`: the chained template (steps Bake 1-3,
   Render 1-3, Bake 4-6, Render 4-6, Bake 7-9, Render 7-9), which `openjd check` must pass.
3. `openjd run` of the whole job with the job's Python set to tests/farm/kill_hook.py, which
   SIGKILLs the bake process while it writes frame 5 (half the file under its temporary name):
   the run must fail in step Bake 4-6 after Bake 1-3 and Render 1-3 ran (a chunk's renders start
   as soon as it is baked), with frames 1-4 complete, frame 5 not in place, no later step run.
4. The re-queue, as a farm does it: the failed step and the steps after it, one `openjd run
   --step` each, with the plain Python. The chunk must bake from the checkpoint at frame 4 (the
   bake says so) and frames 1-4 must not be rewritten (same inode and mtime), so the kill cost
   the one frame in flight; the cache must end with frames
   1-9 and no temporary file, and each frame file must equal the reference's byte for byte,
   the header's UUID included (the writer derives it from the file's content instead of
   OpenVDB's random one); the 9 renders must exist at the job's size.

Run by ctest (label farm) as: python3 openjd_chain_test.py PYTHONPATH_FOR_JOB BLENDER
openjd-cli as in openjd_job_test.py (exit 77, skipped, where it cannot be installed).
"""

import json
import os
import re
import shutil
import stat
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from openjd_job_test import fail, openjd_executable, png_size, run  # noqa: E402

FRAMES = (1, 9)
BAKE_CHUNK, RENDER_CHUNK = 3, 2
KILL_FRAME = 5  # in the middle of chunk 4-6: frame 4 is complete, frame 5 is being written
SIZE = (48, 36)
RESOLUTION = 16
VDB_MAGIC = b" BDV\0\0\0\0"  # OpenVDB's file header starts with it


def steps_run(stdout: str):
    return re.findall(r"Running step '([^']+)'", stdout)


def frame_files(cache: Path):
    return sorted(p.name for p in (cache / "data").iterdir())


def main(job_python_path: str, blender: str) -> None:
    import hapticfluid.farm as farm

    openjd = openjd_executable()
    frames = list(range(FRAMES[0], FRAMES[1] + 1))
    expected_steps = [f"{kind} {a}-{b}" for a, b in farm.frame_chunks(*FRAMES, BAKE_CHUNK) for kind in ("Bake", "Render")]
    root = Path(tempfile.mkdtemp(prefix="hf_farm_chain_"))
    figures = {}
    try:
        (root / "scenes").mkdir()
        scene = json.loads((HERE / "tiny_scene.json").read_text())
        scene["frames"]["end"] = FRAMES[1]
        scene["probe"]["keys"][-1]["frame"] = FRAMES[1]
        (root / "scenes" / "chain.json").write_text(json.dumps(scene, indent=1))

        # 1. the single-task bake to compare with
        t0 = time.monotonic()
        r = run([sys.executable, "-m", "hapticfluid.farm", "bake", "--root", root, "--resolution", RESOLUTION,
                 "--cache", "caches/single", "scenes/chain.json"], cwd=root, timeout=600)
        figures["single-task bake"] = time.monotonic() - t0
        single = root / "caches" / "single"
        if r.returncode != 0 or frame_files(single) != [f"fluid_data_{f:04d}.vdb" for f in frames]:
            fail(f"the single-task bake did not write frames {frames}")

        # 2. the chained job
        job_dir = root / "jobs" / "chain"
        r = run([sys.executable, "-m", "hapticfluid.farm", "write", "scenes/chain.json", "--root", root,
                 "--cache", root / "caches" / "chain", "--output", root / "renders" / "chain",
                 "--frames", f"{FRAMES[0]}-{FRAMES[1]}", "--resolution", RESOLUTION, "--chunk-size", RENDER_CHUNK,
                 "--bake-chunk", BAKE_CHUNK, "--job", job_dir], cwd=root)
        if r.returncode != 0:
            fail("hapticfluid.farm write --bake-chunk failed")
        template = job_dir / "template.yaml"
        r = run([openjd, "check", template])
        if r.returncode != 0 or "passes validation" not in r.stdout:
            fail("openjd check refused the chained template")
        names = [s["name"] for s in yaml.safe_load(template.read_text())["steps"]]
        if names != expected_steps:
            fail(f"the chained template's steps are {names}, expected {expected_steps}")

        def job(python):
            return [openjd, "run", template, "-p", f"file://{job_dir / 'parameters.json'}", "-p", f"SharedRoot={root}",
                    "-p", f"PythonPath={job_python_path}", "-p", f"Python={python}", "-p", f"Blender={blender}",
                    "-p", "RenderSamples=2", "-p", f"RenderWidth={SIZE[0]}", "-p", f"RenderHeight={SIZE[1]}"]

        # 3. the worker dies in the middle of chunk 4-6, while frame 5 is written
        killer = root / "kill_python"
        killer.write_text(f"#!/bin/sh\nexec {sys.executable} {HERE / 'kill_hook.py'} \"$@\"\n")
        killer.chmod(killer.stat().st_mode | stat.S_IXUSR)
        env = dict(os.environ, HF_TEST_KILL_AT_FRAME=str(KILL_FRAME))
        t0 = time.monotonic()
        r = run(job(killer), timeout=1200, env=env)
        figures["run killed in Bake 4-6"] = time.monotonic() - t0
        cache = root / "caches" / "chain"
        killed_steps = steps_run(r.stdout)
        if r.returncode == 0 or f"kill_hook: SIGKILL while writing frame {KILL_FRAME}" not in r.stdout:
            fail(f"the bake was not killed while writing frame {KILL_FRAME} (openjd run exit {r.returncode}); "
                 "does the bake still write frames through hapticfluid.write_vdb?")
        if killed_steps != expected_steps[:3]:
            fail(f"steps run until the kill: {killed_steps}, expected {expected_steps[:3]} (the renders of chunk "
                 "1-3 before the bake of 4-6, nothing after the killed step)")
        before = frame_files(cache)
        partial = [n for n in before if n.startswith(f".fluid_data_{KILL_FRAME:04d}.vdb.") and n.endswith(".tmp")]
        if [n for n in before if not n.startswith(".")] != [f"fluid_data_{f:04d}.vdb" for f in range(1, KILL_FRAME)] \
                or not partial:
            fail(f"after the kill the cache holds {before}: expected frames 1..{KILL_FRAME - 1} and frame "
                 f"{KILL_FRAME}'s partial temporary file")
        kept = {f: (cache / "data" / f"fluid_data_{f:04d}.vdb").stat() for f in range(1, KILL_FRAME)}
        renders = root / "renders" / "chain"
        if sorted(p.name for p in renders.glob("frame_*.png")) != [f"frame_{f:04d}.png" for f in (1, 2, 3)]:
            fail(f"after the kill the renders are {sorted(p.name for p in renders.iterdir())}, expected frames 1-3")
        print(f"killed as planned: steps {killed_steps}, cache {before}", flush=True)

        # 4. the farm re-queues the failed step; the steps after it follow
        t0 = time.monotonic()
        for step in expected_steps[2:]:
            r = run(job(sys.executable) + ["--step", step], timeout=1200)
            if r.returncode != 0 or steps_run(r.stdout) != [step]:
                fail(f"the re-queued step {step!r} failed (openjd run exit {r.returncode})")
            if step == expected_steps[2]:
                resumed = re.findall(r"from the checkpoint at (\d+)", r.stdout)
                if resumed[-1:] != [str(KILL_FRAME - 1)]:
                    fail(f"the re-queued {step} did not say it baked from the checkpoint at {KILL_FRAME - 1} (the "
                         f"last frame complete before the kill): {resumed}")
        figures["re-queued steps Bake 4-6 .. Render 7-9"] = time.monotonic() - t0
        for f, st in kept.items():
            now = (cache / "data" / f"fluid_data_{f:04d}.vdb").stat()
            if (now.st_ino, now.st_mtime_ns) != (st.st_ino, st.st_mtime_ns):
                fail(f"frame {f}, complete before the kill, was rewritten by the re-queued chunk")
        if frame_files(cache) != [f"fluid_data_{f:04d}.vdb" for f in frames]:
            fail(f"the finished cache holds {frame_files(cache)}, expected frames {frames} and nothing else")
        manifest = json.loads((cache / "hapticfluid_bake.json").read_text())
        if manifest["frames_done"] != frames:
            fail(f"the manifest's frames_done is {manifest['frames_done']}, expected {frames}")
        for f in frames:
            a, b = cache / "data" / f"fluid_data_{f:04d}.vdb", single / "data" / f"fluid_data_{f:04d}.vdb"
            if a.read_bytes()[:8] != VDB_MAGIC:
                fail(f"{a} does not start with OpenVDB's header")
            if a.read_bytes() != b.read_bytes():
                fail(f"frame {f} of the chained bake differs from the single-task bake's")
        for f in frames:
            png = renders / f"frame_{f:04d}.png"
            if not png.exists() or png_size(png) != SIZE:
                fail(f"{png} missing or not {SIZE[0]}x{SIZE[1]}")
        print(f"chained job OK: frames {FRAMES[0]}-{FRAMES[1]} at {RESOLUTION}^3 in bake chunks of {BAKE_CHUNK} "
              f"(steps {', '.join(expected_steps)}); killed while writing frame {KILL_FRAME}, re-queued: frames "
              f"1-{KILL_FRAME - 1} kept, {len(frames)} frame files equal to the single-task bake's byte for byte, "
              f"{len(frames)} renders; "
              + "; ".join(f"{k} {v:.1f} s" for k, v in figures.items()), flush=True)
    finally:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
