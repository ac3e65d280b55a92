"""Bake a .blend from the command line, without the UI:

    blender --background scene.blend --python-exit-code 1 --python addon/hapticfluid_blender/bake_blend.py \
        -- [--resume] [--resolution N] [--save]

Registers the add-on (from this folder) if needed, bakes with the scene's hapticfluid settings
(the objects' roles: domain with the bake settings and cache folder, probe, source), and with --save stores the .blend with the Volume
object pointing at the frames. Exits non-zero when the bake fails (1) or an argument is bad (2);
keep --python-exit-code 1 so that an error Blender catches around the script also exits 1.
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
    parser.add_argument("--save", action="store_true", help="save the .blend after baking")
    args = parser.parse_args(argv)

    addon_parent = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if addon_parent not in sys.path:
        sys.path.insert(0, addon_parent)
    import hapticfluid_blender

    if not hasattr(bpy.types.Object, "hapticfluid"):
        # registered after the .blend loaded, so its load handlers did not run: register() itself
        # moves an older file's scene settings onto the objects and clears a stale is_baking
        hapticfluid_blender.register()
    scene = bpy.context.scene
    settings = hapticfluid_blender.roles.settings_of(scene)
    if args.resolution is not None:
        prop = hapticfluid_blender.properties.HapticFluidDomainSettings.bl_rna.properties["resolution"]
        if not prop.hard_min <= args.resolution <= prop.hard_max:  # Blender would clamp it silently
            print(f"bake_blend.py: --resolution must be between {prop.hard_min} and {prop.hard_max}, "
                  f"got {args.resolution}", file=sys.stderr)
            return 2
        if settings.domain is not None:  # else the bake refuses: no domain
            settings.resolution = args.resolution
    logging.basicConfig(level=logging.INFO, format="%(message)s")  # the bake's line per frame
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


if __name__ == "__main__":
    code = main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    if code:
        sys.exit(code)
