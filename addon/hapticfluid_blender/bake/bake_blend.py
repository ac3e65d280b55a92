# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake a .blend from the command line, without the UI, through the add-on's entry point:

    blender --background scene.blend --python-use-system-env --python-exit-code 1 \
        --python-expr "import hapticfluid_blender as a; a.bake_main()" \
        -- [--resume] [--resolution N] [--cache DIR] [--save | --until FRAME]

or, with the add-on's folder not on Blender's path, this file as the script
(``--python addon/hapticfluid_blender/bake/bake_blend.py -- ...``: it puts its add-on on the path
and calls the same entry point). bake_main registers the add-on unless it is, then main() bakes
with the scene's hapticfluid settings (the objects' roles: domain with the bake settings and cache
folder, probe, source) and with --save stores the .blend with the Volume object pointing at the
frames. --cache DIR bakes into DIR instead of the domain's cache folder (a farm job's shared
cache). --until FRAME bakes up to that frame and stops, keeping its checkpoint, so that the next
`--resume --until` continues from it (a farm job's chained bake chunks): it runs
hapticfluid.bake.bake on the exported scene directly, without the Volume object, so not with
--save. Exits non-zero when the bake fails (1) or an argument is bad (2); keep
--python-exit-code 1 so that an error Blender catches around the script also exits 1.
"""

import argparse
import logging
import os
import sys

import bpy


def main(argv):
    parser = argparse.ArgumentParser(prog="bake_blend.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--resume", action="store_true", help="continue after the last complete frame")
    parser.add_argument("--resolution", type=int, default=None, help="cells along the domain's longest edge")
    parser.add_argument("--cache", default=None, metavar="DIR",
                        help="bake into this folder instead of the domain's cache folder")
    parser.add_argument("--save", action="store_true", help="save the .blend after baking")
    parser.add_argument("--until", type=int, default=None, metavar="FRAME",
                        help="bake up to this frame, then stop keeping its checkpoint (a farm chunk; --resume "
                             "continues from it); not with --save")
    args = parser.parse_args(argv)
    if args.until is not None and args.save:
        print("bake_blend.py: --until bakes a chunk of the frames and does not make the Volume object that --save "
              "stores: drop --save (save after the last chunk with a plain --resume --save)", file=sys.stderr)
        return 2

    from ..properties import object_props, roles

    scene = bpy.context.scene
    settings = roles.settings_of(scene)
    if args.cache is not None and settings.domain is not None:  # else the bake refuses: no domain
        settings.cache_dir = args.cache
    if args.resolution is not None:
        prop = object_props.HapticFluidDomainSettings.bl_rna.properties["resolution"]
        if not prop.hard_min <= args.resolution <= prop.hard_max:  # Blender would clamp it silently
            print(f"bake_blend.py: --resolution must be between {prop.hard_min} and {prop.hard_max}, "
                  f"got {args.resolution}", file=sys.stderr)
            return 2
        if settings.domain is not None:  # else the bake refuses: no domain
            settings.resolution = args.resolution
    logging.basicConfig(level=logging.INFO, format="%(message)s")  # the bake's line per frame
    if args.until is not None:
        return bake_until(scene, settings, args.until, args.resume)
    op = bpy.ops.hapticfluid.bake_resume if args.resume else bpy.ops.hapticfluid.bake
    try:
        result = op()
    except RuntimeError as exc:  # in background mode an ERROR report is raised, not returned
        print(f"bake_blend.py: {exc}", file=sys.stderr)
        return 1
    print("hapticfluid:", settings.status)
    if "FINISHED" not in result:
        return 1
    if args.save:
        bpy.ops.wm.save_mainfile()
    return 0


def bake_until(scene, settings, until, resume):
    """Bake the scene up to frame ``until`` (a farm chunk) with hapticfluid.bake.bake, as the Bake
    operator exports it; 0 when done, 1 when the scene or the bake fails."""
    from . import blender_scene

    try:
        from hapticfluid.bake import bake, scene_from_dict

        bake_scene = scene_from_dict(blender_scene.scene_dict(scene, settings))
        result = bake(bake_scene, resume=resume, until=until,
                      log=lambda line: logging.getLogger("hapticfluid_blender.bake.bake_blend").info("bake: %s", line))
    except Exception as exc:  # the bake's errors name the setting or argument (until) with the fix
        print(f"bake_blend.py: {exc}", file=sys.stderr)
        return 1
    print(f"hapticfluid: bake {result.status}: {result.frames_written} frame(s) in {result.seconds:.1f} s, up to "
          f"frame {until}; last complete frame {result.last_frame}")
    return 0 if result.status == "finished" else 1


if __name__ == "__main__":  # run as a script: the add-on this file is in, through its entry point
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    import hapticfluid_blender

    hapticfluid_blender.bake_main()
