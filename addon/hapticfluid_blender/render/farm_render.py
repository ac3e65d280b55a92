# SPDX-License-Identifier: GPL-3.0-or-later
"""The render task of a farm job, run inside Blender: render a chunk of baked frames in one session.

    blender --background --factory-startup --python-use-system-env --python-exit-code 1 \
        --python-expr "import hapticfluid_blender as a; a.render_main()" -- \
        [--root ROOT] [--size W H] [--samples N] [--density D] CACHE FRAMES OUTDIR

(the add-on's render_main, the entry the farm's job files name, calls main here).

The arguments and the checks (a frame not baked yet is an error, so a render never shows an empty
volume) are hapticfluid.farm.chunks'; the scene is render_scene's. Writes OUTDIR/frame_####.png per
frame, each complete or not at all.
"""

import logging
import os
from typing import List, Sequence

log = logging.getLogger(__name__)


def render(argv: Sequence[str]) -> List[str]:
    """Render the chunk; returns the files written."""
    import bpy

    from hapticfluid.farm import chunks, parse_frames, resolve

    from . import render_scene

    args = chunks.parse_args(argv)
    cache = str(resolve(args.root, args.cache))
    outdir = str(resolve(args.root, args.outdir))
    try:
        frames = parse_frames(args.frames)
    except ValueError as exc:
        raise SystemExit(f"farm_render: {exc}") from None
    manifest = chunks.read_manifest(cache)
    chunks.check_frames(frames, manifest, cache)
    scene = render_scene.setup(bpy, manifest, cache, size=tuple(args.size), samples=args.samples,
                               density=args.density)
    written = []
    for frame in frames:
        out = render_scene.render_frame(bpy, scene, frame, os.path.join(outdir, chunks.OUTPUT_PATTERN.format(frame=frame)))
        written.append(out)
        log.info("frame %d -> %s", frame, out)
    return written


def main(argv: Sequence[str]) -> None:
    logging.basicConfig(level=logging.INFO, format="hapticfluid farm_render: %(message)s")
    render(argv)
