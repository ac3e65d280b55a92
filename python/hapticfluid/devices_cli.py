# SPDX-License-Identifier: GPL-3.0-or-later
"""``python3 -m hapticfluid devices``: the Novint Falcons plugged in, their state, and the
virtual device kinds this build offers.

Exit code 0 whether or not a Falcon is plugged in (none is an answer, not a failure); 1 when
USB itself cannot be queried.
"""

from __future__ import annotations

import argparse
from typing import Dict, List

import hapticfluid as hf

# kind, factory in the hapticfluid package, what it is. Only factories this build has are listed.
_VIRTUAL = (
    ("simulated_falcon", "open_simulated_falcon",
     "the whole Falcon driver on a simulated Falcon (firmware upload, homing, forces)"),
    ("scripted", "scripted_device", "a handle following timed waypoints"),
    ("host", "host_device", "a handle whose pose the host pushes each frame"),
    ("null", "null_device", "rests at the origin and discards forces"),
)


def add_devices(sub) -> None:
    p = sub.add_parser(
        "devices",
        help="list Novint Falcons (and permission/firmware problems) and the virtual devices",
        description="List the Novint Falcons plugged in (USB 0403:cb48) with their state: "
                    "bus/address, serial, whether their firmware is loaded, and permission "
                    "problems with the udev rule that fixes them. Then list the virtual device "
                    "kinds available without hardware.",
    )
    p.add_argument("--no-probe", action="store_true",
                   help="do not open the Falcons to check whether their firmware is loaded")
    p.set_defaults(func=cmd_devices)


def _firmware_text(loaded) -> str:
    if loaded is None:
        return "firmware: not checked"
    if loaded:
        return "firmware: loaded"
    return "firmware: not loaded (open_falcon(firmware='nvent_firmware.bin') uploads it)"


def format_falcons(falcons: List[Dict[str, object]]) -> List[str]:
    """The report's lines for list_falcons()'s dicts."""
    lines = ["Novint Falcons (USB 0403:cb48):"]
    if not falcons:
        lines.append("  none plugged in (connect its USB cable and its power supply; "
                     "open_simulated_falcon() works without one)")
        return lines
    for f in falcons:
        serial = f["serial"] or "unknown"
        lines.append(f"  [{f['index']}] bus {f['bus']:03d} address {f['address']:03d}  serial {serial}  "
                     f"{_firmware_text(f['firmware_loaded'])}")
        if not f["permission_ok"]:
            lines.append("      no permission to open it (a udev rule is missing):")
            lines.extend("      " + line for line in hf.falcon_udev_rule().splitlines())
        elif f["problem"]:
            lines.extend("      problem: " + line if i == 0 else "      " + line
                         for i, line in enumerate(str(f["problem"]).splitlines()))
    return lines


def format_virtual() -> List[str]:
    lines = ["Virtual devices:"]
    for kind, factory, text in _VIRTUAL:
        lines.append(f"  {kind:<17} hapticfluid.{factory}()  {text}")
    return lines


def cmd_devices(args: argparse.Namespace) -> int:
    falcons = hf.list_falcons(probe_firmware=not args.no_probe)
    for line in format_falcons(falcons) + format_virtual():
        print(line)
    return 0
