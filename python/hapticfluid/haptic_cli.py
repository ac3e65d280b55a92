# SPDX-License-Identifier: GPL-3.0-or-later
"""``python3 -m hapticfluid haptic``: a HapticSession run headless.

A simulation is touched through a device (by default a scripted handle sweeping a built-in path
through the domain) for ``--seconds``; every haptic period is recorded and written to
``haptic_force.csv`` (time, device position, simulation force, filtered force, commanded force)
with a plot ``haptic_force.png``, and the session's statistics are printed (the force gain in use
and how it was chosen, the passivity controller's state) with what the device did to the hand
(energy and mean power delivered to it, its swing).
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, Optional, Sequence, Tuple

import numpy as np

import hapticfluid as hf
from hapticfluid import assembly
from hapticfluid.cli_types import cells as _cells
from hapticfluid.cli_types import finite_float as _number
from hapticfluid.cli_types import positive_float as _positive
from hapticfluid.files import atomic_write

DEVICES = ("scripted", "null", "host", "falcon", "simulated-falcon")
SWEEP_PERIOD_S = 4.0
SWEEP_AMPLITUDE_M = (0.04, 0.0, 0.02)  # device frame: a figure-of-eight in x-z, Falcon-sized
HOST_PUSH_HZ = 60.0
# Jacobi by default here: the haptic loop wants the simulation's rate (assembly.ITERATIONS_PER_STEP).
DEFAULT_SOLVER = "jacobi"
DEFAULT_ITERATIONS = assembly.ITERATIONS_PER_STEP["interactive"]  # per solver, when none are given
CSV_NAME = "haptic_force.csv"
PNG_NAME = "haptic_force.png"
CSV_COLUMNS = ["time_s", "x_m", "y_m", "z_m",
               "sim_fx_n", "sim_fy_n", "sim_fz_n",
               "filtered_fx_n", "filtered_fy_n", "filtered_fz_n",
               "commanded_fx_n", "commanded_fy_n", "commanded_fz_n"]


def sweep_position(t: float, period: float = SWEEP_PERIOD_S) -> Tuple[float, float, float]:
    """The built-in path (m, device frame) at time t (s): x = A cos(wt), z = B cos(2wt).

    It starts at rest (every velocity component is zero at t = 0), so the probe does not appear
    in still fluid already moving: an impulsive start would give a physically right but large
    added-mass force of m_added * v / dt on the first step.
    """
    w = 2.0 * math.pi / period
    ax, ay, az = SWEEP_AMPLITUDE_M
    return (ax * math.cos(w * t), ay * math.cos(w * t), az * math.cos(2.0 * w * t))


def sweep_waypoints(samples: int = 200, period: float = SWEEP_PERIOD_S):
    """One lap of the built-in path as waypoints (times s, positions m) for scripted_device()."""
    times = np.linspace(0.0, period, samples + 1)
    return times, np.array([sweep_position(t, period) for t in times])


@dataclass
class HapticRun:
    csv_path: Path
    png_path: Optional[Path]
    stats: Dict[str, object]
    samples: int
    motion: Dict[str, object]


def open_device(kind: str, script: Optional[str] = None, loop: bool = True) -> hf.Device:
    """The device named on the command line (see DEVICES)."""
    if kind == "scripted":
        if script:
            return hf.scripted_device_from_csv(script, loop=loop)
        times, positions = sweep_waypoints()
        return hf.scripted_device(times, positions, loop=True)
    if script:
        raise hf.InvalidArgumentError("--script is for --device scripted only")
    if kind == "null":
        return hf.null_device()
    if kind == "host":
        return hf.host_device()
    if kind == "falcon":
        return hf.open_falcon()
    if kind == "simulated-falcon":
        return hf.open_simulated_falcon()
    raise hf.InvalidArgumentError(f"unknown device {kind!r}; choose one of {', '.join(DEVICES)}")


def run_haptic(
    device: hf.Device,
    seconds: float,
    out_dir: Path,
    resolution: Sequence[int] = (32, 32, 32),
    domain_size: Sequence[float] = (1.0, 1.0, 1.0),
    iterations: Optional[int] = None,
    fluid_density: float = 1000.0,
    gravity: Sequence[float] = (0.0, 0.0, 0.0),
    gl_device: str = "",
    plot: bool = True,
    log: Callable[[str], None] = print,
    solver: str = DEFAULT_SOLVER,
    **session_args,
) -> HapticRun:
    """Run a session over a new simulation for `seconds` (s); write CSV (+ PNG) into out_dir."""
    if not (math.isfinite(seconds) and seconds > 0):
        raise hf.InvalidArgumentError(f"seconds must be a positive number, got {seconds}")
    iterations = assembly.iterations_for(solver, "interactive", iterations)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    host = device if isinstance(device, hf.HostDevice) else None
    settings = hf.FluidSettings(resolution=tuple(resolution), domain_size=tuple(domain_size),
                                fluid_density=fluid_density, gravity=tuple(gravity),
                                pressure_iterations=iterations, pressure_solver=solver, device=gl_device)
    sim, session = assembly.build(assembly.SceneDescription(settings), device,
                                  hf.HapticSessionSettings(trace=True, trace_seconds=seconds + 5.0, **session_args))
    with sim:
        log(f"haptic session: device {device.info().name!r}, {seconds:g} s, "
            f"grid {sim.resolution}, GL {sim.device['renderer']}")
        log(session.stats()["force_gain_reason"])
        chunks = []
        with session:
            start = time.monotonic()
            next_push = start
            while True:
                now = time.monotonic()
                if now - start >= seconds or session.error is not None:
                    break
                if host is not None and now >= next_push:  # the host drives the handle
                    host.push_pose(sweep_position(now - start), now)
                    next_push += 1.0 / HOST_PUSH_HZ
                chunks.append(session.trace())
                time.sleep(0.005 if host is not None else 0.05)
            stats = session.stats()
        chunks.append(session.trace())
    trace = {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}
    csv_path = out_dir / CSV_NAME
    _write_csv(csv_path, trace)
    png_path = None
    if plot:
        png_path = out_dir / PNG_NAME
        _plot(png_path, trace, device.info().name)
    return HapticRun(csv_path, png_path, stats, len(trace["time"]), hand_motion(trace))


def _write_csv(path: Path, trace: Dict[str, np.ndarray]) -> None:
    t = trace["time"] - (trace["time"][0] if len(trace["time"]) else 0.0)
    table = np.column_stack([t, trace["position"], trace["sim_force"], trace["filtered_force"],
                             trace["commanded_force"]])

    def write(f):
        w = csv.writer(f, lineterminator="\n")
        w.writerow(CSV_COLUMNS)
        for row in table:
            w.writerow([f"{row[0]:.6f}"] + [f"{v:.6g}" for v in row[1:]])

    atomic_write(path, write)


def _plot(path: Path, trace: Dict[str, np.ndarray], device_name: str) -> None:
    # Imported here: matplotlib is only needed for the picture, and it is slow to import.
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    t = trace["time"] - (trace["time"][0] if len(trace["time"]) else 0.0)
    fig = Figure(figsize=(9, 7), dpi=100)
    FigureCanvasAgg(fig)
    pos_ax, *force_axes = fig.subplots(4, 1, sharex=True)
    for k, name in enumerate("xyz"):
        pos_ax.plot(t, 1e3 * trace["position"][:, k], label=name)
    pos_ax.set_ylabel("position (mm)")
    pos_ax.set_title(f"haptic session, device {device_name!r}")
    pos_ax.legend(loc="upper right", fontsize="small")
    for k, (ax, name) in enumerate(zip(force_axes, "xyz")):
        ax.plot(t, trace["sim_force"][:, k], lw=0.8, label="simulation (fluid N)")
        ax.plot(t, trace["filtered_force"][:, k], lw=0.8, label="filtered (device N)")
        ax.plot(t, trace["commanded_force"][:, k], lw=1.2, label="commanded (device N)")
        ax.set_ylabel(f"F{name} (N)")
    force_axes[0].legend(loc="upper right", fontsize="small")
    force_axes[-1].set_xlabel("time (s)")
    fig.tight_layout()
    atomic_write(path, lambda f: fig.savefig(f, format="png"), binary=True)


def hand_motion(trace: Dict[str, np.ndarray], last_seconds: float = 1.0) -> Dict[str, object]:
    """What the device did to the hand, from a session's trace (device frame).

    delivered_j: energy the commanded force delivered to the hand, sum of F(k-1) . (x(k) - x(k-1))
    (J; positive = into the hand: the force held over a period times the motion in it);
    mean_power_w: that over the traced time (W); peak_to_peak_mm and last_peak_to_peak_mm: the
    hand's swing per axis over the whole trace and over its last `last_seconds` (mm).
    """
    t = np.asarray(trace["time"], dtype=float)
    x = np.asarray(trace["position"], dtype=float)
    f = np.asarray(trace["commanded_force"], dtype=float)
    if len(t) < 2:
        raise hf.InvalidArgumentError("hand_motion needs a trace of at least two haptic periods")
    delivered = float(np.sum(f[:-1] * np.diff(x, axis=0)))
    duration = float(t[-1] - t[0])
    last = x[t >= t[-1] - last_seconds]
    return {
        "delivered_j": delivered,
        "mean_power_w": delivered / duration if duration > 0 else 0.0,
        "peak_to_peak_mm": tuple(float(v) for v in 1e3 * np.ptp(x, axis=0)),
        "last_peak_to_peak_mm": tuple(float(v) for v in 1e3 * np.ptp(last, axis=0)),
    }


def format_stats(stats: Dict[str, object]) -> str:
    """The statistics as aligned 'name  value' lines."""
    width = max(len(k) for k in stats)
    lines = []
    for key, value in stats.items():
        if isinstance(value, float):
            text = f"{value:.4g}"
        elif isinstance(value, tuple):
            text = "(" + ", ".join(f"{v:.4g}" for v in value) + ")"
        else:
            text = str(value)
        lines.append(f"  {key:<{width}}  {text}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------- argparse


def _add_haptic(sub) -> None:
    p = sub.add_parser(
        "haptic",
        help="touch a simulation through a haptic device headless; writes haptic_force.csv/.png",
        description="Run a HapticSession (1 kHz haptic thread + simulation thread) for --seconds "
                    "with the chosen device, record every haptic period and write "
                    f"{CSV_NAME} and {PNG_NAME} to --out, then print the statistics. The default "
                    "device is a scripted handle sweeping a figure-of-eight through the domain.")
    p.add_argument("--device", choices=DEVICES, default="scripted",
                   help="haptic device: scripted (built-in sweep or --script), host (this "
                        "program pushes the sweep at 60 Hz, as Blender would), null, falcon, "
                        "simulated-falcon (default: %(default)s)")
    p.add_argument("--script", metavar="CSV",
                   help="for --device scripted: t,x,y,z rows (s, m, device frame) to follow")
    p.add_argument("--no-loop", action="store_true", help="hold the script's last pose instead of looping")
    p.add_argument("--seconds", type=_positive, default=5.0, help="run time in s (default: %(default)s)")
    p.add_argument("--resolution", nargs=3, type=_cells, metavar=("NX", "NY", "NZ"),
                   default=[32, 32, 32], help="cells per axis (default: 32 32 32)")
    p.add_argument("--domain", nargs=3, type=_positive, metavar=("LX", "LY", "LZ"),
                   default=[1.0, 1.0, 1.0], help="box edges in m (default: 1 1 1)")
    p.add_argument("--solver", choices=tuple(DEFAULT_ITERATIONS), default=DEFAULT_SOLVER,
                   help="pressure solver (default: %(default)s)")
    p.add_argument("--iterations", type=int, default=None,
                   help="pressure iterations per step: Jacobi sweeps or multigrid-CG iterations (default: %s)"
                        % ", ".join(f"{v} for {k}" for k, v in DEFAULT_ITERATIONS.items()))
    p.add_argument("--fluid-density", type=_positive, default=1000.0,
                   help="kg/m^3 (default: %(default)s, water-like so the forces are felt)")
    p.add_argument("--gravity", nargs=3, type=_number, metavar=("GX", "GY", "GZ"),
                   default=[0.0, 0.0, 0.0],
                   help="m/s^2 (default: 0 0 0: no buoyancy, only the fluid's response to motion)")
    p.add_argument("--probe-radius", type=_positive, default=0.1, help="m (default: %(default)s)")
    p.add_argument("--workspace-scale", type=_number, default=6.0,
                   help="domain m per device m (default: %(default)s)")
    p.add_argument("--force-gain", type=_number, default=None,
                   help="device N per fluid N (default: the gain the device can render for this "
                        "probe, fluid and workspace scale, from its max damping and stiffness)")
    p.add_argument("--allow-unsafe-gain", action="store_true",
                   help="accept a --force-gain above what the device renders passively (refused otherwise): "
                        "the rendering may then put energy into the hand")
    p.add_argument("--no-passivity", action="store_true",
                   help="observe the energy delivered to the hand but do not damp it (the passivity "
                        "controller is on by default)")
    p.add_argument("--filter", choices=("lowpass", "none"), default="lowpass",
                   help="force smoothing (default: %(default)s)")
    p.add_argument("--bandwidth-ratio", type=_positive, default=0.5,
                   help="low-pass cutoff / simulation rate (default: %(default)s)")
    p.add_argument("--prediction", action="store_true",
                   help="update the force between frames from a fitted drag model")
    p.add_argument("--max-force", type=_positive, default=None,
                   help="N (default: the device's maximum)")
    p.add_argument("--ramp-time", type=_number, default=1.0, help="s (default: %(default)s)")
    p.add_argument("--no-realtime", action="store_true", help="do not ask for SCHED_FIFO priority")
    p.add_argument("--gl-device", default="",
                   help="GL device: 'software' or an EGL device number (default: auto)")
    p.add_argument("--out", default="haptic_out", metavar="DIR",
                   help="output directory (default: %(default)s)")
    p.add_argument("--no-plot", action="store_true", help=f"do not write {PNG_NAME}")
    p.set_defaults(func=cmd_haptic)


def cmd_haptic(args: argparse.Namespace) -> int:
    device = open_device(args.device, args.script, loop=not args.no_loop)
    try:
        result = run_haptic(
            device, args.seconds, Path(args.out),
            resolution=args.resolution, domain_size=args.domain, iterations=args.iterations,
            solver=args.solver,
            fluid_density=args.fluid_density, gravity=args.gravity, gl_device=args.gl_device,
            plot=not args.no_plot, log=lambda line: print(line, flush=True),
            workspace_scale=args.workspace_scale, force_gain=args.force_gain,
            allow_unsafe_gain=args.allow_unsafe_gain, probe_radius=args.probe_radius, filter=args.filter,
            bandwidth_ratio=args.bandwidth_ratio, prediction=args.prediction,
            max_force=args.max_force, ramp_time=args.ramp_time, realtime=not args.no_realtime,
            passivity=not args.no_passivity)
    finally:
        device.close()
    print("statistics:")
    print(format_stats(result.stats))
    print("the hand:")
    print(format_stats(result.motion))
    print(f"wrote {result.csv_path} ({result.samples} haptic periods)")
    if result.png_path is not None:
        print(f"wrote {result.png_path}")
    return 0
