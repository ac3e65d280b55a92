# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's preferences: the machine's choices (the simulation's backend), and say at once
when the hapticfluid package is not importable (enabling the add-on works without it; Bake would
be the first to fail)."""

import os
import platform
import re
import sys

import bpy

from ..properties.machine import BACKEND_ITEMS
from .ui_text import wrapped_label


def _glibc_floor(wheel_names):
    """The newest glibc any manylinux_2_NN wheel in the list needs, as (2, NN), or None. A wheel
    tagged for several (``manylinux_2_24_x86_64.manylinux_2_28_x86_64``) needs the oldest of them."""
    floors = [min((2, int(v)) for v in found) for n in wheel_names
              for found in [re.findall(r"manylinux_2_(\d+)_", n)] if found]
    return max(floors) if floors else None


MANIFEST = os.path.join(os.path.dirname(os.path.dirname(__file__)), "blender_manifest.toml")


def manifest_wheels(manifest=MANIFEST):
    """The wheel file names the manifest's ``wheels = [...]`` lists (scripts/build_extension.sh
    appends it): [] where it lists none (the source tree, a zip built without wheels) or there is
    no manifest (a legacy add-on install). Comments are not read (they name placeholder wheels)."""
    try:
        with open(manifest, encoding="utf-8") as f:
            text = "".join(line for line in f if not line.lstrip().startswith("#"))
    except OSError:
        return []
    listed = re.search(r"^wheels\s*=\s*\[(.*?)\]", text, re.M | re.S)
    return [os.path.basename(n) for n in re.findall(r"[\"']([^\"']+\.whl)[\"']", listed.group(1))] if listed else []


def unsupported_here(wheel_names=None):
    """One line saying why the engine cannot load on this system, or None where it can (as far as
    the platform, Python and glibc tell). The extension's wheels are Linux x86_64 only, for CPython
    3.11 (Blender 4.2 to 5.0) and 3.13 (5.1 to 5.3), each needing at least the glibc its
    manylinux tag names; wheel_names defaults to those the installed manifest lists (none listed:
    the engine did not come with the add-on, so only the platform is judged here)."""
    system, machine = platform.system(), platform.machine().lower()
    if system != "Linux" or machine not in ("x86_64", "amd64"):
        return (f"hapticfluid's engine is built for Linux x86_64 only: none for {system} {machine} "
                f"(Windows, macOS and arm64 are not supported)")
    if wheel_names is None:
        wheel_names = manifest_wheels()
    py = f"cp{sys.version_info[0]}{sys.version_info[1]}"
    mine = [n for n in wheel_names if f"-{py}-" in n]
    if wheel_names and not mine:
        built = sorted({m.group(1) for n in wheel_names for m in [re.search(r"-cp3(\d+)-", n)] if m}, key=int)
        return (f"hapticfluid's engine is built for CPython {' and '.join('3.' + v for v in built)}, "
                f"not this Blender's Python {sys.version_info[0]}.{sys.version_info[1]}")
    floor = _glibc_floor(mine)
    libc, version = platform.libc_ver()
    if floor and libc == "glibc" and version and tuple(int(x) for x in version.split(".")[:2]) < floor:
        return f"hapticfluid's engine needs glibc {floor[0]}.{floor[1]} or newer; this system has glibc {version}"
    return None


def package_problem():
    """None if ``hapticfluid`` imports, else what to do (for the preferences and the panels)."""
    try:
        import hapticfluid  # noqa: F401
    except ImportError as exc:
        wheels = manifest_wheels()
        why = unsupported_here(wheels)
        if why:
            return f"{why}: the add-on's engine cannot load ({exc})"
        missing = re.match(r"(lib(EGL|OpenGL)\.so\.\d+): cannot open shared object file", str(exc))
        if missing:  # libglvnd is the system's on purpose (the wheel does not carry it)
            return (f"Install your system's {missing.group(1)} (Debian/Ubuntu: apt install libegl1 libopengl0; "
                    f"Fedora/RHEL: dnf install libglvnd-egl libglvnd-opengl): the engine needs it ({exc})")
        install = ("Install the hapticfluid package into Blender's Python (see README) or add it to PYTHONPATH "
                   "(read by Blender 4.x only with --python-use-system-env)")
        if not wheels:  # the source tree, a zip built without wheels, a legacy install
            return (f"{install}, or install the extension zip scripts/build_extension.sh builds, which carries it: "
                    f"this add-on came without its engine (its manifest lists no wheels) and it is not importable "
                    f"({exc})")
        return f"{install}: it is not importable ({exc})"
    return None


class HapticFluidPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__.rpartition(".")[0]  # the add-on's module: this file is in its ui/

    backend: bpy.props.EnumProperty(
        name="Backend", items=BACKEND_ITEMS, default="AUTO",
        description="Where the simulation computes, for the bake and the live session (the stats and the "
                    "bake's log name the one in use)")

    def draw(self, context):
        problem = package_problem()
        if problem:
            wrapped_label(self.layout, context, problem, icon="ERROR")
        else:
            import hapticfluid

            self.layout.label(text=f"hapticfluid {hapticfluid.__version__} is importable", icon="CHECKMARK")
        self.layout.prop(self, "backend")
