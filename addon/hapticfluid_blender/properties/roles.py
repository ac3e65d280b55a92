# SPDX-License-Identifier: GPL-3.0-or-later
"""Which object holds which hapticfluid role in a scene, and the scene's settings read through
the roles: the one place every reader (bake, live session, farm job, panels, bake_blend.py)
asks. A scene has at most one object per role (Domain, Probe, Smoke Source): the Set Role
operator refuses a second one with a report naming the object that has it, and the property's
update refuses it too (a log line), so scripts get the same rule. A duplicated object (Shift+D)
copies its role without either check: the bake and the live session then refuse with
``problem(scene)``, which names the objects.

``settings_of(scene)`` returns a view that reads and writes like the scene-level settings of
older versions (``scene.hapticfluid_bake``): ``domain``, ``probe`` and ``source`` are the
objects holding the roles (assigning one moves the role), ``probe_shape`` is the probe's,
``source_density`` and ``source_temperature`` the source's, everything else the domain's
(bake settings, cache, status). Without a holder, reads give the property's default and writes
raise ``RoleError``. The view looks the holders up once (``scene.objects`` is scanned per role,
not per read): make a new one after roles were changed elsewhere.
"""

import logging

from . import object_props

log = logging.getLogger(__name__)

PHYSICS_PATH = "Properties > Physics > hapticfluid"
ROLE_ATTRS = {"domain": "DOMAIN", "probe": "PROBE", "source": "SOURCE"}  # view attribute -> role
GROUPS = {  # role -> (the object's settings group attribute, its class)
    "DOMAIN": ("domain_settings", object_props.HapticFluidDomainSettings),
    "PROBE": ("probe_settings", object_props.HapticFluidProbeSettings),
    "SOURCE": ("source_settings", object_props.HapticFluidSourceSettings),
}
_ROLE_OF_SETTING = {name: role for role, (_attr, cls) in GROUPS.items() for name in cls.__annotations__}


class RoleError(LookupError):
    """A setting of a role was written while no object holds that role (the message says which)."""


def label(role) -> str:
    return object_props.ROLE_LABELS[role]


def role_of(obj):
    """The object's role, 'NONE' without one. Asks is_property_set first: reading
    ``obj.hapticfluid`` through RNA would store an empty group on every object scanned."""
    return obj.hapticfluid.role if obj.is_property_set("hapticfluid") else "NONE"


def holders(scene, role):
    """The scene's objects holding ``role``, by name (one, normally; more after a Shift+D)."""
    return sorted((o for o in scene.objects if role_of(o) == role), key=lambda o: o.name)


def holder(scene, role):
    found = holders(scene, role)
    return found[0] if found else None


def domain_of(scene):
    return holder(scene, "DOMAIN")


def probe_of(scene):
    return holder(scene, "PROBE")


def source_of(scene):
    return holder(scene, "SOURCE")


def settings_of(scene):
    """The scene's roles and settings as one object (see the module's docstring)."""
    return SceneRoles(scene)


def domain_settings_of(scene):
    """The domain's settings group (for panels' ``layout.prop``) or None without a domain."""
    domain = domain_of(scene)
    return None if domain is None else domain.hapticfluid.domain_settings


def role_settings(obj):
    """The settings group of the object's role, or None when it has none."""
    role = obj.hapticfluid.role
    return None if role == "NONE" else getattr(obj.hapticfluid, GROUPS[role][0])


def problem(scene):
    """None, or what to fix when several objects of the scene hold one role."""
    for role in GROUPS:
        found = holders(scene, role)
        if len(found) > 1:
            names = ", ".join(f"'{o.name}'" for o in found)
            return (f"keep the {label(role)} role on one object (remove it from the others in {PHYSICS_PATH}): "
                    f"{names} all have it, and a scene has one {label(role).lower()}")
    return None


def conflict(obj, role):
    """None, or why ``obj`` cannot take ``role`` (fix first): the domain must be a mesh, and no
    other object of its scenes may hold the role."""
    if role == "NONE":
        return None
    if role == "DOMAIN" and obj.type != "MESH":
        return (f"choose a mesh for the Domain role: '{obj.name}' is of type {obj.type.title()}, and the "
                "domain is a mesh's bounding box")
    for scene in obj.users_scene:
        other = next((o for o in holders(scene, role) if o != obj), None)
        if other is not None:
            return (f"remove the {label(role)} role from '{other.name}' first ({PHYSICS_PATH}): it already has it "
                    f"in scene '{scene.name}', and a scene has one {label(role).lower()}")
    return None


def check_new_role(obj, role):
    """The role property's update: a role ``conflict`` refuses is taken back (role None) and logged."""
    why = conflict(obj, role)
    if why is not None:
        obj.hapticfluid.role = "NONE"
        log.warning("hapticfluid: '%s' was not given the %s role: %s", obj.name, label(role), why)


def assign(scene, role, obj):
    """Give ``role`` to ``obj`` (None: to nobody), taking it from the scene's other holders; a
    role the object held before is replaced. RoleError if ``obj`` cannot hold it."""
    for other in holders(scene, role):
        if other != obj:
            other.hapticfluid.role = "NONE"
    if obj is None or obj.hapticfluid.role == role:
        return
    why = conflict(obj, role)
    if why is not None:
        raise RoleError(why)
    obj.hapticfluid.role = role


def _default(cls, name):
    prop = cls.bl_rna.properties[name]
    if prop.type == "POINTER":
        return None
    return tuple(prop.default_array) if getattr(prop, "is_array", False) else prop.default


class SceneRoles:
    """A scene's roles and their settings, read and written as one object (``settings_of``)."""

    __slots__ = ("scene", "_found")

    def __init__(self, scene):
        object.__setattr__(self, "scene", scene)
        object.__setattr__(self, "_found", {})

    def _holder(self, role):
        if role not in self._found:
            self._found[role] = holder(self.scene, role)
        return self._found[role]

    @property
    def problem(self):
        """None, or what to fix when a role has several holders (see ``problem``)."""
        return problem(self.scene)

    def __getattr__(self, name):
        if name in ROLE_ATTRS:
            return self._holder(ROLE_ATTRS[name])
        role = _ROLE_OF_SETTING.get(name)
        if role is None:
            raise AttributeError(f"hapticfluid settings have no '{name}'")
        obj = self._holder(role)
        attr, cls = GROUPS[role]
        return _default(cls, name) if obj is None else getattr(getattr(obj.hapticfluid, attr), name)

    def __setattr__(self, name, value):
        if name in ROLE_ATTRS:
            self._found.clear()  # the object may have held another role
            assign(self.scene, ROLE_ATTRS[name], value)
            return
        role = _ROLE_OF_SETTING.get(name)
        if role is None:
            raise AttributeError(f"hapticfluid settings have no '{name}'")
        obj = self._holder(role)
        if obj is None:
            raise RoleError(f"give an object the {label(role)} role first ({PHYSICS_PATH}): '{name}' is a "
                            f"setting of the {label(role).lower()}, and no object in scene '{self.scene.name}' "
                            "has that role")
        setattr(getattr(obj.hapticfluid, GROUPS[role][0]), name, value)
