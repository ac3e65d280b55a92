# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's machine choices (Edit > Preferences > Add-ons > hapticfluid), read where a
simulation is made: the bake's scene and the live session."""

# The Backend preference's items: identifiers are the engine's names (hapticfluid.BACKENDS) in
# upper case, checked by tests/python/test_addon_roles.py.
BACKEND_ITEMS = (
    ("AUTO", "Auto", "A hardware GPU where one gives an OpenGL 4.5 context, else the CPU backend"),
    ("GPU", "GPU", "OpenGL compute shaders on the GPU (Mesa's llvmpipe, on the CPU, where there is no GPU)"),
    ("CPU", "CPU", "The same kernels compiled for the CPU, on every core: several times faster than "
                   "llvmpipe where the only OpenGL is a software renderer"),
)

ADDON_MODULE = __package__.rpartition(".")[0]  # the add-on's module: this file is in its properties/


def backend_choice(context) -> str:
    """The Backend preference as the engine takes it: 'gpu' or 'cpu', and '' for Auto or where the
    add-on's preferences are not there (the engine then takes HAPTICFLUID_BACKEND, else auto)."""
    addon = context.preferences.addons.get(ADDON_MODULE) if context.preferences else None
    prefs = getattr(addon, "preferences", None)
    choice = prefs.backend if prefs is not None and hasattr(prefs, "backend") else "AUTO"
    return "" if choice == "AUTO" else choice.lower()
