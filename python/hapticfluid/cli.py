# SPDX-License-Identifier: GPL-3.0-or-later
"""Command line of hapticfluid: ``python3 -m hapticfluid <command> ...``.

Each subcommand is a pair of functions: ``_add_<name>(subparsers)`` declares its arguments and
``cmd_<name>(args) -> int`` runs it. To add a command, write the pair and list the adder in
``_COMMANDS``.

Exit codes: 0 success, 1 engine or I/O failure, 2 bad arguments (argparse's usage errors and the
engine's InvalidArgumentError), 130 interrupted.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Callable, List, Optional, Sequence

import hapticfluid as hf
from hapticfluid import assembly
from hapticfluid import demo as _demo
from hapticfluid.cli_types import cells as _cells
from hapticfluid.cli_types import iterations as _iterations
from hapticfluid.cli_types import positive_float as _positive_float
from hapticfluid.cli_types import positive_int as _positive_int
from hapticfluid import devices_cli as _devices_cli
from hapticfluid import haptic_cli as _haptic_cli


# ---------------------------------------------------------------------------- info


def _add_info(sub) -> None:
    p = sub.add_parser("info", help="describe the GL device the engine would use",
                       description="Print the GL device a Simulation would use "
                                   "(hapticfluid.probe_device) and the EGL devices found "
                                   "(hapticfluid.list_egl_devices).")
    p.add_argument("--device", default="",
                   help="GL device: 'hardware' (a GPU or an error), 'software' or an EGL device number; by default "
                        "HAPTICFLUID_EGL_DEVICE or auto (hardware GPU first)")
    p.set_defaults(func=cmd_info)


def cmd_info(args: argparse.Namespace) -> int:
    print(f"hapticfluid {hf.__version__}")
    info = hf.probe_device(args.device)
    print("device:")
    width = max((len(k) for k in info), default=0)
    for key, value in info.items():
        print(f"  {key:<{width}}  {value}")
    print("EGL devices:")
    listing = hf.list_egl_devices().rstrip("\n")
    print(listing if listing else "  (none)")
    return 0


# ---------------------------------------------------------------------------- demo


def _add_demo(sub) -> None:
    p = sub.add_parser(
        "demo",
        help="run the smoke plume + probe sweep demo; writes force.csv and density.png",
        description="Run the built-in scene: a hot smoke source at the bottom centre makes a "
                    "rising plume; after it has developed for the first quarter of the steps, a "
                    "sphere probe swings back and forth along x through it. Prints the force on "
                    "the probe every frame and writes force.csv and density.png to --out.",
    )
    p.add_argument("--resolution", nargs=3, type=_cells, metavar=("NX", "NY", "NZ"),
                   default=list(_demo.DEFAULT_RESOLUTION),
                   help="cells per axis, at least 8; cells must be cubic with --domain "
                        "(default: %s)" % " ".join(map(str, _demo.DEFAULT_RESOLUTION)))
    p.add_argument("--domain", nargs=3, type=_positive_float, metavar=("LX", "LY", "LZ"),
                   default=list(_demo.DEFAULT_DOMAIN),
                   help="box edges in metres (default: %s)"
                        % " ".join(f"{x:g}" for x in _demo.DEFAULT_DOMAIN))
    p.add_argument("--steps", type=_positive_int, default=_demo.DEFAULT_STEPS,
                   help="number of frames, one simulation step each (default: %(default)s)")
    p.add_argument("--dt", type=_positive_float, default=_demo.DEFAULT_DT,
                   help="time step in seconds (default: 1/30)")
    p.add_argument("--solver", choices=tuple(_demo.DEFAULT_ITERATIONS), default=_demo.DEFAULT_SOLVER,
                   help="pressure solver (default: %(default)s)")
    p.add_argument("--iterations", type=_iterations, default=None,
                   help="pressure iterations per step: Jacobi sweeps or multigrid-CG iterations "
                        "(default: %s)" % ", ".join(f"{v} for {k}" for k, v in _demo.DEFAULT_ITERATIONS.items()))
    p.add_argument("--advection", choices=assembly.ADVECTIONS,
                   default=_demo.DEFAULT_ADVECTION,
                   help="advection scheme (default: %(default)s)")
    p.add_argument("--device", default="",
                   help="GL device: 'hardware' (a GPU or an error), 'software' or an EGL device number; by default "
                        "HAPTICFLUID_EGL_DEVICE or auto (hardware GPU first)")
    p.add_argument("--out", default=_demo.DEFAULT_OUT_DIR, metavar="DIR",
                   help="output directory (default: %(default)s)")
    p.add_argument("--no-plot", action="store_true",
                   help="do not write density.png (no matplotlib needed)")
    p.set_defaults(func=cmd_demo)


def cmd_demo(args: argparse.Namespace) -> int:
    _demo.run_demo(
        resolution=tuple(args.resolution),
        domain_size=tuple(args.domain),
        steps=args.steps,
        dt=args.dt,
        iterations=args.iterations,
        solver=args.solver,
        device=args.device,
        out_dir=args.out,
        advection=args.advection,
        plot=not args.no_plot,
        log=lambda line: print(line, flush=True),
    )
    return 0


# ---------------------------------------------------------------------------- bake


def _add_bake(sub) -> None:
    from hapticfluid.bake import command as _bake_command

    _bake_command.add_parser(sub, _cells)


# ---------------------------------------------------------------------------- bench


def _add_bench(sub) -> None:
    try:
        from hapticfluid.bench.runner import add_parser
    except ImportError:  # the wheel leaves the benchmarks out: they run from a source build
        return
    add_parser(sub)


# ---------------------------------------------------------------------------- main

# Add a new subcommand by appending its _add_<name> function.
_COMMANDS: List[Callable] = [_add_demo, _add_info, _devices_cli.add_devices, _add_bake,
                             _haptic_cli._add_haptic, _add_bench]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python3 -m hapticfluid",
        description="hapticfluid: GPU smoke simulation with a probe you can feel.",
    )
    parser.add_argument("--version", action="version", version=f"hapticfluid {hf.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for add in _COMMANDS:
        add(sub)
    return parser


def _error(prog: str, command: str, message: object) -> None:
    print(f"{prog} {command}: error: {str(message).rstrip()}", file=sys.stderr)


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    prog = parser.prog
    try:
        return args.func(args)
    except hf.InvalidArgumentError as exc:  # before HapticFluidError: it is a subclass
        _error(prog, args.command, exc)
        return 2
    except hf.HapticFluidError as exc:
        _error(prog, args.command, exc)
        return 1
    except BrokenPipeError:  # e.g. piped into `head`: stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
    except OSError as exc:
        _error(prog, args.command, exc)
        return 1
    except ImportError as exc:
        _error(prog, args.command, f"{exc} (try --no-plot)")
        return 1
    except KeyboardInterrupt:
        print(f"{prog} {args.command}: interrupted", file=sys.stderr)
        return 130
