# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender 4.3's crash after disabling the add-on under a running modal operator, and the guard
that every modal operator of the add-on (Bake, Resume, the live session's Start) goes through.

Blender 4.3 (not 3.4) segfaults in ``modal_handler_add`` while a window still lists the handler
of a modal operator whose class was unregistered as it ran: ``unregister_class`` frees the
operator and leaves its handler to be dropped the next time that window handles an event.
Disabling the add-on during a UI bake or a live session leaves one, and then any modal start (not
only the same operator's) crashes. ``keep_ticking`` keeps the ended operator's event timer
running in its window for ``DROP_S`` (at least two events there: the bake's timer ticks every
0.2 s, the live session's every 25 ms), and the operators refuse to start while ``pending()``.
State is module-level and main-thread only; it outlives a disable/enable (the module stays
imported)."""

import time

import bpy

DROP_S = 0.5
REFUSAL = ("Try again in a moment: Blender is still dropping the {what} that disabling the add-on ended (starting "
           "one now would crash Blender 4.x)")
_dropping = {"timers": [], "until": 0.0}  # event timers kept for the drop, till when


def keep_ticking(timer):
    """The add-on is being disabled under a running modal operator: keep its event timer (from
    ``event_timer_add``) for DROP_S, then remove it."""
    if not _dropping["timers"]:
        bpy.app.timers.register(_end_drop, first_interval=DROP_S)
    _dropping["timers"].append(timer)
    _dropping["until"] = time.monotonic() + DROP_S


def pending():
    """Whether a modal operator ended by disabling the add-on may still be listed by its window."""
    if _dropping["timers"] and time.monotonic() >= _dropping["until"]:
        _end_drop()  # the app timer may not have run yet
    return bool(_dropping["timers"])


def _end_drop():
    wm = bpy.context.window_manager
    for timer in _dropping["timers"]:
        if wm is not None:
            wm.event_timer_remove(timer)  # a no-op for a timer the window manager no longer has
    _dropping["timers"] = []
    return None  # one-shot
