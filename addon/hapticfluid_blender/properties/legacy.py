# SPDX-License-Identifier: GPL-3.0-or-later
"""Files saved before roles: the scene-level settings (``scene.hapticfluid_bake``: domain, probe
and source pointers with every setting on the scene) stay registered, hidden, so such a file
still loads, and ``migrate`` moves them onto the objects once: each pointed-to object gets its
role, the domain the bake settings (cache, status and Volume included), the probe its shape, the
source its density and temperature. Then the scene's old group is deleted (it held nothing
else); with no domain chosen its bake settings have no object to go to and stay, unused, in the
old group. A log line per scene says what moved. It runs from a load_post handler and when the
add-on is enabled (a file opened while it was disabled); a migrated file has nothing to move."""

import logging

import bpy
from bpy.props import PointerProperty

from . import roles, versioning

log = logging.getLogger(__name__)

SCENE_PROP = "hapticfluid_bake"


def _annotations():
    """The old group's properties: the three pointers, then every role's settings, defined once
    in object_props.py (same names, defaults and limits as when they lived on the scene)."""
    found = {
        "domain": PointerProperty(name="Domain", type=bpy.types.Object),
        "probe": PointerProperty(name="Probe", type=bpy.types.Object),
        "source": PointerProperty(name="Smoke Source", type=bpy.types.Object),
    }
    for _attr, cls in roles.GROUPS.values():
        found.update(cls.__annotations__)
    return found


HapticFluidBakeSettings = type("HapticFluidBakeSettings", (bpy.types.PropertyGroup,), {
    "__annotations__": _annotations(),
    "__doc__": "The scene-level settings of files saved before roles (read by the migration only)",
})


def migrate():
    """Move every scene's old settings onto its objects; returns the log lines (one per scene
    that had something to move)."""
    lines = []
    for scene in bpy.data.scenes:
        if not scene.is_property_set(SCENE_PROP):  # (not keys(): bpy.props are no custom props in 5.0)
            continue
        old = getattr(scene, SCENE_PROP)
        if old.domain is None and old.probe is None and old.source is None:
            continue
        moved, kept = [], []
        for attr, role in roles.ROLE_ATTRS.items():
            obj = getattr(old, attr)
            if obj is None:
                continue
            name = roles.label(role)
            if obj.hapticfluid.role not in ("NONE", role):
                kept.append(f"'{obj.name}' already is the {roles.label(obj.hapticfluid.role)}, so it did not become "
                            f"the {name}")
                continue
            why = None if obj.hapticfluid.role == role else roles.conflict(obj, role)
            if why is not None:
                kept.append(f"'{obj.name}' did not become the {name}: {why}")
                continue
            obj.hapticfluid.role = role
            group_attr, cls = roles.GROUPS[role]
            group = getattr(obj.hapticfluid, group_attr)
            before = dict(versioning.CHANGED_DEFAULTS) if role == "DOMAIN" else {}
            for key in cls.__annotations__:
                # a setting the old group does not store had the default of its day
                value = before[key] if key in before and not old.is_property_set(key) else getattr(old, key)
                setattr(group, key, value)
            moved.append(f"{name} '{obj.name}'" + (" (with the bake settings and cache)" if role == "DOMAIN" else ""))
        domain_moved = old.domain is not None and old.domain.hapticfluid.role == "DOMAIN"
        old.domain = old.probe = old.source = None
        if domain_moved:
            scene.property_unset(SCENE_PROP)  # everything it held is on the domain now
        else:
            kept.append("the bake settings stay unused in the old scene settings: no domain was chosen (give a "
                        f"mesh the Domain role in {roles.PHYSICS_PATH} and set them there)")
        line = (f"hapticfluid: moved scene '{scene.name}' settings (saved before roles) onto objects: "
                + (", ".join(moved) if moved else "nothing") + ("; " + "; ".join(kept) if kept else ""))
        log.warning("%s", line)
        lines.append(line)
    return lines



def attach():
    bpy.types.Scene.hapticfluid_bake = PointerProperty(type=HapticFluidBakeSettings, options={"HIDDEN"})


def detach():
    del bpy.types.Scene.hapticfluid_bake
