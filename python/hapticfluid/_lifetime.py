# SPDX-License-Identifier: GPL-3.0-or-later
"""Haptic sessions still running when the interpreter ends are stopped first.

A session's threads (the haptic loop, the simulation) must not outlive the objects they use,
and Python does not promise to destroy every object at exit. install() makes every started
session (start(), or a ``with`` block) join a WeakSet and registers an atexit hook that stops
those still running, force ramped down, threads joined. This is Python's business (the
interpreter's lifetime), so it lives here and not in the bindings.
"""

from __future__ import annotations

import atexit
import functools
import weakref
from typing import Any

_started: "weakref.WeakSet[Any]" = weakref.WeakSet()
STOP_TIMEOUT_S = 30.0


def _tracked(method: Any) -> Any:
    @functools.wraps(method)
    def call(self: Any, *args: Any, **kwargs: Any) -> Any:
        _started.add(self)
        return method(self, *args, **kwargs)

    return call


def stop_all(error_type: type = Exception) -> int:
    """Stop every started session that is still running; returns how many were asked."""
    sessions = list(_started)
    for session in sessions:
        try:
            session.stop(STOP_TIMEOUT_S)
        except error_type:  # exiting: the error that ended it was readable through .error
            pass
    return len(sessions)


def install(core: Any) -> None:
    """Track the native HapticSession's starts and stop the sessions at exit (once)."""
    cls = core.HapticSession
    if getattr(cls, "_lifetime_installed", False):
        return
    cls.start = _tracked(cls.start)
    cls.__enter__ = _tracked(cls.__enter__)
    cls._lifetime_installed = True
    atexit.register(functools.partial(stop_all, core.HapticFluidError))
