# SPDX-License-Identifier: GPL-3.0-or-later
"""Ready-made paths for the simulated Falcon's hand (``open_simulated_falcon(hand_path=...)``):
demos and tests move the probe with them, no hardware needed.

Each gesture is a list of waypoints ``(t, x, y, z)``: seconds after the homing gesture, and where
the hand pulls the grip in the Falcon's frame (m, the workspace centre at the origin, reach about
+-0.04 m). All of them loop (``hand_loop=True``); ``rest`` is None (the hand rests at the centre);
``relaxed`` too, and once the Falcon is homed the hand holds the grip only lightly, so a playback
guide (``HapticSession.set_guide``) leads it.

    device = hapticfluid.open_simulated_falcon(**hapticfluid.hand_gestures.falcon_args("circle"))
"""

import math
from typing import Dict, List, Optional, Tuple

Waypoint = Tuple[float, float, float, float]

REACH_M = 0.025        # how far from the centre the gestures go (m): well inside the Falcon's reach
SWEEP_PERIOD_S = 3.0   # one sweep there and back (s)
CIRCLE_PERIOD_S = 4.0  # one turn (s)
CIRCLE_POINTS = 32     # waypoints per turn

RELAXED_STIFFNESS_N_M = 5.0  # the relaxed hand once the Falcon is homed (N/m) ...
RELAXED_DAMPING_N_S_M = 3.0  # ... and its damping (N s/m), homing included

DESCRIPTIONS: Dict[str, str] = {
    "rest": "The hand rests at the middle of the workspace (the probe stays at the domain's centre)",
    "sweep": f"Back and forth along x, {REACH_M * 100:.1f} cm either side of the centre, every {SWEEP_PERIOD_S:g} s",
    "circle": f"A horizontal circle of {REACH_M * 100:.1f} cm radius about the centre, every {CIRCLE_PERIOD_S:g} s",
    "relaxed": (f"After homing the hand rests lightly on the grip ({RELAXED_STIFFNESS_N_M:g} N/m): the device leads it "
                f"(feel a played motion)"),
}
NAMES = tuple(DESCRIPTIONS)


def waypoints(name: str) -> Optional[List[Waypoint]]:
    """The gesture's waypoints (t s, x, y, z m), or None for 'rest'. ValueError for an unknown name."""
    if name in ("rest", "relaxed"):
        return None
    if name == "sweep":
        half = SWEEP_PERIOD_S / 2.0
        return [(half / 2.0, -REACH_M, 0.0, 0.0), (half * 1.5, REACH_M, 0.0, 0.0), (half * 2.5, -REACH_M, 0.0, 0.0)]
    if name == "circle":
        dt = CIRCLE_PERIOD_S / CIRCLE_POINTS
        return [(1.0 + k * dt, REACH_M * math.cos(2.0 * math.pi * k / CIRCLE_POINTS),
                 REACH_M * math.sin(2.0 * math.pi * k / CIRCLE_POINTS), 0.0) for k in range(CIRCLE_POINTS + 1)]
    raise ValueError(f"gesture must be one of {', '.join(NAMES)}; got {name!r}")


def falcon_args(name: str) -> Dict[str, object]:
    """Keyword arguments of open_simulated_falcon for the gesture: hand_path and hand_loop (and for
    'relaxed' the hand's stiffness once homed and its damping)."""
    path = waypoints(name)
    args: Dict[str, object] = {"hand_path": path, "hand_loop": path is not None}
    if name == "relaxed":
        args.update(hand_stiffness_homed=RELAXED_STIFFNESS_N_M, hand_damping=RELAXED_DAMPING_N_S_M)
    return args
