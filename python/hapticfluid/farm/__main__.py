# SPDX-License-Identifier: GPL-3.0-or-later
"""``python3 -m hapticfluid.farm bake|write ...``: the farm job's bake task, and the job writer.

* ``bake --root ROOT SCENE --resolution N --cache CACHE [--until LAST]``: the bake task, or one
  chunk task of a chained bake (see :mod:`hapticfluid.farm.bake_step`); paths relative to ROOT
  or absolute.
* ``write --root ROOT SCENE --cache CACHE --output OUT --frames A-B --resolution N --job DIR
  [--bake-chunk N]``: write the OpenJD template + parameters (a Deadline Cloud job bundle) and
  the Flamenco job script + submission into DIR, and print the commands that run or submit them.
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
from typing import Optional, Sequence

from hapticfluid.cli_types import cells, int_at_least, positive_int
from hapticfluid.farm import FarmJob, bake_step, parse_frames, write_flamenco_job, write_openjd_job


def frame_number(text: str) -> int:
    """A frame number (an integer, possibly negative, as Blender allows)."""
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a frame number (an integer), got {text!r}") from None


def bake_chunk(text: str) -> int:
    """Frames per bake task: 0 (one task) or more."""
    return int_at_least(text, 0, "a number of frames", "must be 0 (one bake task) or a number of frames >= 1")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python3 -m hapticfluid.farm", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)

    b = sub.add_parser("bake", help="the farm job's bake task (or one chunk of a chained bake): bakes the frames "
                                    "the cache lacks, from its latest checkpoint before them")
    b.add_argument("scene", metavar="SCENE", help="scene .json or .blend (relative to --root, or absolute)")
    b.add_argument("--root", default=".", help="shared root the relative paths start at (default: .)")
    b.add_argument("--resolution", type=cells, required=True, metavar="N",
                   help="cells along the domain's longest edge")
    b.add_argument("--cache", required=True, metavar="DIR", help="cache folder (relative to --root, or absolute)")
    b.add_argument("--blender", default="blender", help="Blender executable for a .blend scene (default: blender)")
    b.add_argument("--until", type=frame_number, default=None, metavar="LAST",
                   help="bake up to frame LAST, then stop leaving its checkpoint (a chunk of a chained bake; "
                        "default: the scene's last frame)")

    w = sub.add_parser("write", help="write the OpenJD and Flamenco job files for a scene")
    w.add_argument("scene", metavar="SCENE", help="scene .json or .blend under --root")
    w.add_argument("--root", required=True, help="the shared root every worker mounts; all paths must be under it")
    w.add_argument("--cache", required=True, metavar="DIR", help="cache folder under --root")
    w.add_argument("--output", required=True, metavar="DIR", help="render output folder under --root")
    w.add_argument("--frames", required=True, metavar="A-B", help="frames to bake and render, e.g. 1-48")
    w.add_argument("--resolution", type=cells, required=True, metavar="N", help="cells along the longest edge")
    w.add_argument("--chunk-size", type=positive_int, default=8, metavar="N", help="frames per render task")
    w.add_argument("--bake-chunk", type=bake_chunk, default=0, metavar="N",
                   help="frames per bake task: the bake becomes a chain of tasks of N frames, each continuing "
                        "from the checkpoint of the one before, the renders of a chunk starting when it is "
                        "baked (default 0: one bake task)")
    w.add_argument("--job", required=True, metavar="DIR", help="folder to write the job files into")
    w.add_argument("--python-path", default=None, help="PYTHONPATH on the workers (default: empty)")
    return parser


def cmd_write(args: argparse.Namespace) -> int:
    if not os.path.isfile(args.scene):
        raise ValueError(f"scene file '{args.scene}' does not exist")
    frames = parse_frames(args.frames)
    if frames != list(range(frames[0], frames[-1] + 1)):
        raise ValueError(f"--frames '{args.frames}' must be one contiguous range A-B")
    job = FarmJob(shared_root=args.root, scene_file=args.scene, cache_dir=args.cache, output_dir=args.output,
                  frame_start=frames[0], frame_end=frames[-1], resolution=args.resolution,
                  chunk_size=args.chunk_size, bake_chunk_size=args.bake_chunk, python_path=args.python_path)
    openjd = write_openjd_job(job, args.job)
    flamenco = write_flamenco_job(job, args.job)
    for path in openjd["files"] + flamenco["files"]:
        print(f"wrote {path}")
    print(f"run with OpenJD:         {openjd['command']}")
    print(f"submit to Deadline:      {openjd['deadline_command']}")
    print(f"submit to Flamenco:      {flamenco['command']}")
    return 0


def main(argv: Optional[Sequence[str]] = None) -> int:
    logging.basicConfig(level=logging.INFO, format="hapticfluid.farm: %(message)s")
    args = build_parser().parse_args(argv)
    if args.command == "bake":
        return bake_step.run(args.root, args.scene, args.resolution, args.cache, args.blender, args.until)
    try:
        return cmd_write(args)
    except ValueError as exc:
        print(f"python3 -m hapticfluid.farm write: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
