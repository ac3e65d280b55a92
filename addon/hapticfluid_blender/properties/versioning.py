# SPDX-License-Identifier: GPL-3.0-or-later
"""Files saved before a default changed keep what they simulated. Blender stores a setting only
once it is set, so a setting left at its default in an older file would read as the new default.
``CHANGED_DEFAULTS`` names each domain setting whose default changed and the value it had before:
an object given the Domain role now stores these settings (``stamp``, a role hook), and when a file
is opened (or the add-on enabled) every domain that does not store one is given the old value
(``migrate``), with a log line. An object that never held the Domain role gets today's defaults
when it first does."""

import logging

import bpy

log = logging.getLogger(__name__)

# The domain's settings whose default changed: (name, the default before). Round 4 (2026-12-06):
# the pressure solve, Jacobi (40 sweeps) -> multigrid CG to a relative residual of 1e-3. On the
# seed grid (100 x 100 x 70, CPU backend, 2 cores) Jacobi's 40 sweeps took 99 ms of a 149 ms step
# and left a relative residual of 0.20; multigrid took 35 ms of 80 and left 2e-4. At the live
# session's 32^3, 15.2 -> 9.8 ms a step (residual 0.055 -> 5e-4).
CHANGED_DEFAULTS = (("pressure_solver", "JACOBI"), ("pressure_tolerance", 0.0))


def _domain_group(obj):
    """The object's domain settings if it stores a hapticfluid group (reading it otherwise would
    store an empty one), else None."""
    if not obj.is_property_set("hapticfluid"):
        return None
    return obj.hapticfluid.domain_settings


def _was_domain(obj, group) -> bool:
    """The object holds the Domain role or its domain settings were ever set (a role taken off
    keeps them, and they come back with it)."""
    return obj.hapticfluid.role == "DOMAIN" or any(group.is_property_set(k) for k in group.__annotations__)


def stamp(obj, role):
    """Role hook (object_props.ROLE_CHANGED_HOOKS): a new Domain stores today's value of each
    changed setting it does not store yet, so that migrate() leaves it alone when it is opened."""
    if role != "DOMAIN":
        return
    group = obj.hapticfluid.domain_settings
    for name, _before in CHANGED_DEFAULTS:
        if not group.is_property_set(name):
            setattr(group, name, getattr(group, name))


def migrate():
    """Give every domain of the open file that does not store a changed setting its value from
    before the change. Returns the log lines (one per object changed)."""
    lines = []
    for obj in bpy.data.objects:
        if obj.library is not None:  # linked from another file: read-only here, that file's to migrate
            continue
        group = _domain_group(obj)
        if group is None or not _was_domain(obj, group):
            continue
        kept = []
        for name, before in CHANGED_DEFAULTS:
            if not group.is_property_set(name):
                setattr(group, name, before)
                kept.append(f"{name} {before}")
        if kept:
            line = (f"hapticfluid: '{obj.name}' was saved before these defaults changed and keeps what it simulated "
                    f"with: " + ", ".join(kept) + " (new domains solve the pressure by multigrid to 1e-3: the "
                    f"Domain's fluid settings, Pressure Solver and Pressure Tolerance)")
            log.warning("%s", line)
            lines.append(line)
    return lines

