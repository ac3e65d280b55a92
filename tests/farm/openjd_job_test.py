# SPDX-License-Identifier: GPL-3.0-or-later
"""The OpenJD job end to end with openjd-cli: `openjd check` on the shipped template, then
`openjd run` of the whole job (bake, then the render chunks) on a tiny scene in a temporary
shared root, then the bake step again as a re-queued task (it must resume and write nothing).

Run by ctest (label farm) as: python3 openjd_job_test.py PYTHONPATH_FOR_JOB BLENDER
openjd-cli comes from ~/.cache/hapticfluid/openjd-venv (installed there from PyPI if missing);
where it cannot be installed the test prints why and exits 77, which ctest reports as skipped.
"""

import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import venv
from pathlib import Path

SKIP = 77
HERE = Path(__file__).resolve().parent
VENV = Path.home() / ".cache" / "hapticfluid" / "openjd-venv"
FRAMES, CHUNK = (1, 4), 3
SIZE = (48, 36)


def fail(message):
    print(f"FAIL: {message}", flush=True)
    sys.exit(1)


def openjd_executable() -> Path:
    exe = VENV / "bin" / "openjd"
    if exe.exists():
        return exe
    print(f"openjd-cli not found in {VENV}: installing it from PyPI", flush=True)
    try:
        venv.EnvBuilder(with_pip=True, clear=True).create(VENV)
        r = subprocess.run([str(VENV / "bin" / "pip"), "install", "--quiet", "openjd-cli"],
                           capture_output=True, text=True, timeout=600)
    except (OSError, subprocess.SubprocessError) as exc:
        print(f"SKIP: openjd-cli cannot be installed ({exc})", flush=True)
        sys.exit(SKIP)
    if r.returncode != 0 or not exe.exists():
        print(f"SKIP: openjd-cli cannot be installed (pip exit {r.returncode}): {r.stderr.strip()[-800:]}",
              flush=True)
        shutil.rmtree(VENV, ignore_errors=True)  # so that a later run tries again
        sys.exit(SKIP)
    return exe


def png_size(path: Path):
    data = path.read_bytes()[:24]
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(f"{path} is not a PNG")
    return struct.unpack(">II", data[16:24])


def run(cmd, **kw):
    print("$", " ".join(map(str, cmd)), flush=True)
    r = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    print(r.stdout[-6000:], r.stderr[-3000:], sep="\n", flush=True)
    return r


def main(job_python_path: str, blender: str) -> None:
    import hapticfluid.farm as farm

    openjd = openjd_executable()
    r = run([openjd, "check", farm.OPENJD_TEMPLATE])
    if r.returncode != 0 or "passes validation" not in r.stdout:
        fail("openjd check refused the shipped template")

    root = Path(tempfile.mkdtemp(prefix="hf_farm_root_"))
    try:
        (root / "scenes").mkdir()
        shutil.copy(HERE / "tiny_scene.json", root / "scenes" / "tiny.json")
        r = run([sys.executable, "-m", "hapticfluid.farm", "write", "scenes/tiny.json", "--root", root,
                 "--cache", root / "caches" / "tiny", "--output", root / "renders" / "tiny",
                 "--frames", f"{FRAMES[0]}-{FRAMES[1]}", "--resolution", "16", "--chunk-size", str(CHUNK),
                 "--job", root / "jobs" / "tiny"], cwd=root)
        if r.returncode != 0:
            fail("hapticfluid.farm write failed")
        params = json.loads((root / "jobs" / "tiny" / "parameters.json").read_text())
        if params["CacheDir"] != "caches/tiny" or params["SceneFile"] != "scenes/tiny.json":
            fail(f"the parameters are not relative to the shared root: {params}")

        job = [openjd, "run", root / "jobs" / "tiny" / "template.yaml",
               "-p", f"file://{root / 'jobs' / 'tiny' / 'parameters.json'}", "-p", f"SharedRoot={root}",
               "-p", f"PythonPath={job_python_path}", "-p", f"Python={sys.executable}", "-p", f"Blender={blender}",
               "-p", "RenderSamples=2", "-p", f"RenderWidth={SIZE[0]}", "-p", f"RenderHeight={SIZE[1]}"]
        r = run(job, timeout=1500)
        if r.returncode != 0:
            fail(f"openjd run exited {r.returncode}")
        cache = root / "caches" / "tiny"
        manifest = json.loads((cache / "hapticfluid_bake.json").read_text())
        frames = list(range(FRAMES[0], FRAMES[1] + 1))
        if manifest["frames_done"] != frames or not manifest["complete"]:
            fail(f"the bake did not finish frames {frames}: {manifest['frames_done']}, complete={manifest['complete']}")
        if sorted(p.name for p in (cache / "data").iterdir()) != [f"fluid_data_{f:04d}.vdb" for f in frames]:
            fail(f"cache frames: {sorted(p.name for p in (cache / 'data').iterdir())}")
        chunks = [tuple(map(int, m.groups())) for m in re.finditer(r"Frames\(CHUNK\[INT\]\) = (\d+)-(\d+)", r.stdout)]
        covered = [f for a, b in chunks for f in range(a, b + 1)]
        if covered != frames or any(b - a + 1 > CHUNK for a, b in chunks) or len(chunks) < 2:
            fail(f"render chunks {chunks} do not cover {frames} contiguously in chunks of at most {CHUNK}")
        for f in frames:
            png = root / "renders" / "tiny" / f"frame_{f:04d}.png"
            if not png.exists() or png_size(png) != SIZE:
                fail(f"{png} missing or not {SIZE[0]}x{SIZE[1]}")
        print(f"job OK: bake of frames {frames}, render chunks {chunks}", flush=True)

        # A re-queued bake task (the worker died, the farm retries it): resumes, writes nothing new.
        before = (cache / "data" / "fluid_data_0004.vdb").stat().st_mtime_ns
        r = run(job + ["--step", "Bake"], timeout=600)
        if r.returncode != 0 or "finished: 0 frame(s)" not in r.stdout:
            fail("the re-queued bake task did not resume a finished bake as a no-op")
        if (cache / "data" / "fluid_data_0004.vdb").stat().st_mtime_ns != before:
            fail("the re-queued bake task rewrote a complete frame")
        print("re-queued bake OK: resumed, 0 frames written", flush=True)
    finally:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
