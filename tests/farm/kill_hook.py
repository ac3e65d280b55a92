# SPDX-License-Identifier: GPL-3.0-or-later
"""A farm worker that dies in the middle of writing a frame, for tests/farm/openjd_chain_test.py.

Used as the job's Python (through a two-line shell wrapper the test writes):

    kill_hook.py -m hapticfluid.farm bake ...   (with HF_TEST_KILL_AT_FRAME=F in the environment)

It runs ``python3 -m hapticfluid.farm`` with the given arguments in this process after wrapping
``hapticfluid.write_vdb`` (the bake's frame writer): when the bake starts writing the file of
frame F, the wrapper writes the first half of that frame's bytes under a temporary name beside it
(the name pattern of the engine's own writer, `.<name>.<pid>.<serial>.tmp`, as a write cut short
leaves it), then sends SIGKILL to its own process: the bake dies as a preempted or crashed
worker does, with no chance to clean up, the frames before F complete, frame F half written and
never renamed into place. Frames other than F are written by the real writer. Nothing in the
package knows about this hook.
"""

import os
import runpy
import signal
import sys
import tempfile
from pathlib import Path

FRAME_ENV = "HF_TEST_KILL_AT_FRAME"


def install(kill_frame: int) -> None:
    import hapticfluid as hf

    real = hf.write_vdb
    target_name = f"fluid_data_{kill_frame:04d}.vdb"

    def write_vdb(path, *args, **kwargs):
        path = Path(path)
        if path.name != target_name:
            return real(str(path), *args, **kwargs)
        with tempfile.TemporaryDirectory() as scratch:  # the frame's real bytes, then half of them
            whole = Path(scratch) / path.name
            real(str(whole), *args, **kwargs)
            data = whole.read_bytes()
        partial = path.parent / f".{path.name}.{os.getpid()}.0.tmp"
        with open(partial, "wb") as f:
            f.write(data[: len(data) // 2])
            f.flush()
            os.fsync(f.fileno())
        print(f"kill_hook: SIGKILL while writing frame {kill_frame} ({len(data) // 2} of {len(data)} bytes in "
              f"{partial.name})", flush=True)
        os.kill(os.getpid(), signal.SIGKILL)

    hf.write_vdb = write_vdb


def main() -> None:
    frame = os.environ.get(FRAME_ENV)
    if not frame:
        sys.exit(f"kill_hook.py: set {FRAME_ENV} to the frame whose writing the bake dies in")
    if sys.argv[1:2] != ["-m"] or len(sys.argv) < 3:
        sys.exit("kill_hook.py: usage: kill_hook.py -m MODULE [ARGS...]")
    install(int(frame))
    module = sys.argv[2]
    sys.argv = [module] + sys.argv[3:]
    runpy.run_module(module, run_name="__main__", alter_sys=True)


if __name__ == "__main__":
    main()
