# SPDX-License-Identifier: GPL-3.0-or-later
"""The built-in demo scene: a rising smoke plume that a spherical probe sweeps through.

A hot smoke source sits near the bottom centre of the box; heat buoyancy lifts the smoke into a
plume and vorticity confinement keeps it curly. For the first quarter of the run the probe waits,
parked off to the -x side, while the plume develops; then it swings back and forth along x at
mid height (x = x_c - A cos(w (t - t0)), so it starts from rest), crossing the plume three times
and ending just after the last crossing. Every frame records the fluid force on the probe; at the
end ``force.csv`` and ``density.png`` are written.

Every row of ``force.csv`` describes the state at the end of one step: ``time_s`` is the simulated
time after the step, the probe pose and velocity are the ones imposed during that step (the
analytic position and its derivative at ``time_s``), ``force_*_n`` is the fluid force on the probe
(newtons; ``force_z_n`` includes the hydrostatic buoyancy rho*V*g of the displaced air),
``residual`` the pressure solve's relative residual and ``step_ms`` the step's host time.

Use it from the command line (``python3 -m hapticfluid demo --help``) or from Python::

    from hapticfluid.demo import run_demo
    result = run_demo(resolution=(32, 32, 32), steps=45, out_dir="out/demo32")
    print(result.steps_per_s, result.forces.max(axis=0))
"""

from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Optional, Sequence, Tuple

import numpy as np

import hapticfluid as hf
from hapticfluid import assembly
from hapticfluid.files import atomic_write

DEFAULT_RESOLUTION = (64, 64, 64)
DEFAULT_DOMAIN = (1.0, 1.0, 1.0)
DEFAULT_STEPS = 90
DEFAULT_DT = 1.0 / 30.0
DEFAULT_SOLVER = "multigrid"
DEFAULT_ITERATIONS = assembly.ITERATIONS_PER_STEP["offline"]  # per solver, when none are given
DEFAULT_ADVECTION = hf.FluidSettings().advection.name
DEFAULT_OUT_DIR = os.path.join("out", "demo")

CSV_COLUMNS = (
    "frame",
    "time_s",
    "probe_x_m",
    "probe_y_m",
    "probe_z_m",
    "probe_vx_m_s",
    "force_x_n",
    "force_y_n",
    "force_z_n",
    "residual",
    "step_ms",
)

Vec3 = Tuple[float, float, float]


@dataclass(frozen=True)
class DemoScene:
    """Physical parameters of the demo scene.

    Positions and sizes are fractions of the domain (so the scene scales with ``--domain``);
    the rest are the engine's SI settings.
    """

    fluid_density: float = 1.2  # kg/m^3 (air)
    open_top: bool = True  # smoke leaves through the top instead of piling up under a lid
    vorticity: float = 0.4  # vorticity confinement epsilon
    heat_buoyancy: float = 1.0  # m/s^2 per kelvin above ambient
    smoke_weight: float = 0.0  # m/s^2 per unit concentration
    smoke_dissipation: float = 0.05  # 1/s
    heat_dissipation: float = 0.4  # 1/s
    source_centre: Vec3 = (0.5, 0.5, 0.1)  # fraction of the domain
    source_radius: float = 0.06  # fraction of the smallest domain edge (at least 1.5 cells)
    source_density: float = 1.0  # concentration held in the source
    source_temperature: float = 8.0  # K above ambient
    probe_radius: float = 0.08  # fraction of the smallest domain edge (at least 1.5 cells)
    probe_height: float = 0.55  # probe centre z, fraction of the domain height
    sweep_amplitude: float = 0.3  # half the sweep's x range, fraction of the domain width
    max_speed: float = 1.5  # m/s; short runs or wide boxes get a smaller sweep instead
    warmup_fraction: float = 0.25  # share of the steps the probe waits parked
    # There-and-back cycles in the rest of the run: 1.375 crosses the plume three times and ends
    # just after the last crossing, so the final picture shows the plume cut and pushed aside.
    sweep_cycles: float = 1.375


@dataclass(frozen=True)
class DemoResult:
    """What :func:`run_demo` produced."""

    out_dir: Path
    csv_path: Path
    png_path: Optional[Path]
    steps_per_s: float  # mean over all steps but the first (it may include shader compilation); nan if steps == 1
    first_step_ms: float
    times: np.ndarray  # (steps,) s
    probe_positions: np.ndarray  # (steps, 3) m
    probe_velocities: np.ndarray  # (steps, 3) m/s
    forces: np.ndarray  # (steps, 3) N
    residuals: np.ndarray  # (steps,)
    step_ms: np.ndarray  # (steps,)
    sweep_start_frame: int  # first frame (1-based) in which the probe moves
    device: dict

    @property
    def paths(self) -> list:
        return [p for p in (self.csv_path, self.png_path) if p is not None]


def _translation(position: Sequence[float]) -> np.ndarray:
    """The 4x4 transform that moves the origin to ``position`` (m)."""
    m = np.eye(4)
    m[:3, 3] = position
    return m


class _Sweep:
    """The probe's path: parked at x_c - A until t0, then x_c - A cos(w (t - t0))."""

    def __init__(self, centre: Vec3, amplitude: float, t0: float, period: float):
        self.centre = centre
        self.amplitude = amplitude
        self.t0 = t0
        self.omega = 2.0 * math.pi / period

    def pose(self, t: float) -> Tuple[Vec3, Vec3]:
        cx, cy, cz = self.centre
        if t <= self.t0:
            return (cx - self.amplitude, cy, cz), (0.0, 0.0, 0.0)
        phase = self.omega * (t - self.t0)
        x = cx - self.amplitude * math.cos(phase)
        vx = self.amplitude * self.omega * math.sin(phase)
        return (x, cy, cz), (vx, 0.0, 0.0)


def _check_positive(name: str, value: float) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = float("nan")
    if isinstance(value, bool) or not (math.isfinite(number) and number > 0.0):
        raise hf.InvalidArgumentError(f"{name} must be a positive finite number, got {value!r}")
    return number


def _write_csv(path: Path, rows: Sequence[Sequence]) -> None:
    def write(f):
        w = csv.writer(f, lineterminator="\n")
        w.writerow(CSV_COLUMNS)
        w.writerows(rows)

    atomic_write(path, write)


def _plot(
    path: Path,
    sim: "hf.Simulation",
    result_arrays: dict,
    probe_radius: float,
    sweep_z: float,
    sweep_x: Tuple[float, float],
    sweep_start_time: float,
    buoyancy_n: float,
    title: str,
) -> None:
    # Imported here: matplotlib is only needed for the picture, and it is slow to import.
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    density = sim.density()
    ox, _, oz = sim.origin
    lx, _, lz = sim.domain_size
    projection = density.max(axis=1)  # (nx, nz): max along y

    fig = Figure(figsize=(12.0, 5.4), layout="constrained")
    FigureCanvasAgg(fig)
    ax_img, ax_f = fig.subplots(1, 2, width_ratios=(1.0, 1.25))

    vmax = max(float(projection.max()), 1e-6)
    image = ax_img.imshow(
        projection.T,
        origin="lower",
        extent=(ox, ox + lx, oz, oz + lz),
        cmap="inferno",
        vmin=0.0,
        vmax=vmax,
        interpolation="bilinear",
    )
    # A colorbar in axes coordinates keeps the image's height whatever the domain's aspect.
    cax = ax_img.inset_axes((1.04, 0.0, 0.045, 1.0))
    fig.colorbar(image, cax=cax, label="smoke density")
    ax_img.plot(sweep_x, (sweep_z, sweep_z), color="0.75", lw=0.8, ls=":", label="probe path")
    px, _, pz = result_arrays["positions"][-1]
    ax_img.add_patch(
        Circle((px, pz), probe_radius, fill=False, edgecolor="cyan", lw=1.8, label="probe (final)")
    )
    vx = float(result_arrays["velocities"][-1][0])
    if abs(vx) > 1e-6:  # an arrow for the final velocity, 0.1 s of travel long
        ax_img.annotate("", xy=(px + 0.1 * vx, pz), xytext=(px, pz),
                        arrowprops={"arrowstyle": "->", "color": "cyan", "lw": 1.5})
        ax_img.annotate(f"{vx:+.2f} m/s", xy=(px, pz - probe_radius), xytext=(0, -12),
                        textcoords="offset points", ha="center", color="cyan", fontsize=8)
    ax_img.set_xlim(ox, ox + lx)
    ax_img.set_ylim(oz, oz + lz)
    ax_img.set_xlabel("x (m)")
    ax_img.set_ylabel("z (m)")
    ax_img.set_title(f"density, max along y, t = {sim.time:.2f} s", fontsize=10)
    ax_img.legend(loc="lower right", fontsize=8, framealpha=0.6)

    t = result_arrays["times"]
    f = result_arrays["forces"]
    ax_f.axvspan(0.0, sweep_start_time, color="0.9", label="probe parked, plume develops")
    ax_f.axhline(buoyancy_n, color="0.5", lw=0.9, ls="--", label="ρ·V·g (hydrostatic buoyancy)")
    ax_f.axhline(0.0, color="0.2", lw=0.6)
    ax_f.plot(t, f[:, 0], color="tab:blue", lw=1.6, label="force x")
    ax_f.plot(t, f[:, 2], color="tab:red", lw=1.6, label="force z")
    ax_f.set_xlim(0.0, max(float(t[-1]), 1e-9))
    ax_f.set_xlabel("time (s)")
    ax_f.set_ylabel("force on probe (N)")
    ax_f.set_title("fluid force on the probe", fontsize=10)
    ax_f.grid(True, lw=0.4, alpha=0.6)

    ax_v = ax_f.twinx()
    ax_v.plot(t, result_arrays["positions"][:, 0], color="tab:green", lw=1.0, ls="-.",
              label="probe x")
    ax_v.set_ylabel("probe x (m)", color="tab:green")
    ax_v.tick_params(axis="y", colors="tab:green")
    ax_v.set_ylim(ox, ox + lx)

    handles, labels = ax_f.get_legend_handles_labels()
    h2, l2 = ax_v.get_legend_handles_labels()
    ax_f.legend(handles + h2, labels + l2, loc="upper left", fontsize=8, framealpha=0.8)

    fig.suptitle(title, fontsize=11)
    atomic_write(path, lambda fh: fig.savefig(fh, format="png", dpi=110), binary=True)


def run_demo(
    resolution: Sequence[int] = DEFAULT_RESOLUTION,
    domain_size: Sequence[float] = DEFAULT_DOMAIN,
    steps: int = DEFAULT_STEPS,
    dt: float = DEFAULT_DT,
    iterations: Optional[int] = None,
    device: str = "",
    out_dir: "str | os.PathLike" = DEFAULT_OUT_DIR,
    advection: str = DEFAULT_ADVECTION,
    solver: str = DEFAULT_SOLVER,
    scene: Optional[DemoScene] = None,
    plot: bool = True,
    log: Optional[Callable[[str], None]] = print,
) -> DemoResult:
    """Run the demo scene and write ``force.csv`` (and ``density.png`` if ``plot``) to ``out_dir``.

    ``log`` receives the progress lines (``print`` by default; ``None`` for silence).
    Raises :class:`hapticfluid.InvalidArgumentError` for bad arguments and
    :class:`hapticfluid.HapticFluidError` for engine failures.
    """
    scene = scene or DemoScene()
    iterations = assembly.iterations_for(solver, "offline", iterations)
    say = log if log is not None else (lambda _line: None)

    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
        raise hf.InvalidArgumentError(f"steps must be a positive integer, got {steps!r}")
    steps = int(steps)
    dt = _check_positive("dt", dt)
    resolution = tuple(int(n) for n in resolution)
    if len(resolution) != 3 or len(domain_size) != 3:
        raise hf.InvalidArgumentError("resolution and domain_size need three values each")
    domain_size = tuple(_check_positive(f"domain size along {name}", value)
                        for name, value in zip("xyz", domain_size))

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)  # fail on an unwritable directory before simulating

    settings = hf.FluidSettings(
        resolution=resolution,
        domain_size=domain_size,
        origin=(0.0, 0.0, 0.0),
        fluid_density=scene.fluid_density,
        gravity=(0.0, 0.0, -9.81),
        open_top=scene.open_top,
        advection=advection,
        vorticity=scene.vorticity,
        smoke_weight=scene.smoke_weight,
        heat_buoyancy=scene.heat_buoyancy,
        smoke_dissipation=scene.smoke_dissipation,
        heat_dissipation=scene.heat_dissipation,
        pressure_iterations=iterations,
        pressure_solver=solver,
        compute_residual=True,
        device=device,
    )
    sim, _ = assembly.build(assembly.SceneDescription(settings))
    # The source and the probe are placed in the engine's grid (its cells, origin and size).
    h = sim.cell_size
    origin = np.asarray(sim.origin, dtype=float)
    size = np.asarray(sim.domain_size, dtype=float)
    smallest = float(size.min())

    src_centre = tuple(origin + size * np.asarray(scene.source_centre))
    src_radius = max(scene.source_radius * smallest, 1.5 * h)
    assembly.place_source(sim, assembly.Source(centre=src_centre, radius=src_radius, density=scene.source_density,
                                               temperature=scene.source_temperature))

    radius = max(scene.probe_radius * smallest, 1.5 * h)
    centre = (
        float(origin[0] + 0.5 * size[0]),
        float(origin[1] + 0.5 * size[1]),
        float(origin[2] + scene.probe_height * size[2]),
    )
    # Keep the sphere at least radius + one cell (plus a hair for rounding) from the x walls.
    max_amplitude = 0.5 * size[0] - radius - 1.05 * h
    if max_amplitude <= 0.0 or not (radius + h < centre[2] - origin[2] < size[2] - radius - h) \
            or 2.0 * (radius + h) > size[1]:
        raise hf.InvalidArgumentError(
            f"domain {tuple(size)} m is too small for the probe (radius {radius:.4g} m) to sweep "
            f"with a margin of a radius plus one cell ({h:.4g} m) from the walls")
    warmup_steps = min(int(round(scene.warmup_fraction * steps)), steps - 1)
    t_start = warmup_steps * dt
    period = max(steps - warmup_steps, 1) * dt / scene.sweep_cycles
    amplitude = min(scene.sweep_amplitude * size[0], max_amplitude,
                    scene.max_speed * period / (2.0 * math.pi))
    sweep = _Sweep(centre, amplitude, t_start, period)

    info = sim.device
    say(f"hapticfluid {hf.__version__} demo: smoke plume + probe sweep")
    say(f"device:   {info.get('renderer', '?')} | {info.get('vendor', '?')} | "
        f"OpenGL {info.get('version', '?')}" + (" (software)" if info.get("software") else ""))
    say(f"grid:     {resolution[0]}x{resolution[1]}x{resolution[2]} cells of {h * 1000:.4g} mm, "
        f"domain {size[0]:g} x {size[1]:g} x {size[2]:g} m, {advection}, "
        f"{iterations} {'Jacobi sweeps' if solver == 'jacobi' else 'multigrid-CG iterations'}")
    say(f"scene:    source r={src_radius:.3g} m at ({', '.join(f'{c:.3g}' for c in src_centre)}) m "
        f"({scene.source_temperature:g} K, heat buoyancy {scene.heat_buoyancy:g} m/s^2/K), "
        f"probe r={radius:.3g} m at z={centre[2]:.3g} m sweeps x {centre[0] - amplitude:.3g}.."
        f"{centre[0] + amplitude:.3g} m from t={t_start:.3g} s, peak speed "
        f"{amplitude * sweep.omega:.3g} m/s")
    say(f"run:      {steps} steps of {dt:.4g} s")
    say(f"{'frame':>5} {'t (s)':>7} {'probe x (m)':>11} "
        f"{'Fx (N)':>11} {'Fy (N)':>11} {'Fz (N)':>11} {'residual':>9} {'ms/step':>8}")

    times = np.empty(steps)
    positions = np.empty((steps, 3))
    velocities = np.empty((steps, 3))
    forces = np.empty((steps, 3))
    residuals = np.empty(steps)
    step_ms = np.empty(steps)
    rows = []
    for i in range(steps):
        t_end = (i + 1) * dt
        pos, vel = sweep.pose(t_end)
        assembly.place_probe(sim, assembly.Probe("sphere", _translation(pos), radius=radius, velocity=vel))
        rep = sim.step(dt)
        force = np.asarray(rep.force, dtype=float)
        times[i], positions[i], velocities[i], forces[i] = t_end, pos, vel, force
        residuals[i], step_ms[i] = rep.relative_residual, rep.wall_ms
        rows.append([i + 1, f"{t_end:.6f}", f"{pos[0]:.6f}", f"{pos[1]:.6f}", f"{pos[2]:.6f}",
                     f"{vel[0]:.6f}", f"{force[0]:.7g}", f"{force[1]:.7g}", f"{force[2]:.7g}",
                     f"{rep.relative_residual:.5g}", f"{rep.wall_ms:.3f}"])
        say(f"{i + 1:5d} {t_end:7.3f} {pos[0]:11.4f} {force[0]:+11.4e} {force[1]:+11.4e} "
            f"{force[2]:+11.4e} {rep.relative_residual:9.2e} {rep.wall_ms:8.1f}"
            + ("  (first step: may include shader compilation)" if i == 0 else "")
            + ("  <- probe starts moving" if i == warmup_steps else ""))

    steps_per_s = 1000.0 / float(step_ms[1:].mean()) if steps > 1 else float("nan")

    csv_path = out / "force.csv"
    _write_csv(csv_path, rows)
    png_path = None
    if plot:
        png_path = out / "density.png"
        buoyancy_n = scene.fluid_density * 9.81 * 4.0 / 3.0 * math.pi * radius ** 3
        title = (f"hapticfluid demo: {resolution[0]}x{resolution[1]}x{resolution[2]} cells, "
                 f"{steps} steps of {dt:.4g} s, on {info.get('renderer', '?')}")
        _plot(png_path, sim,
              {"times": times, "positions": positions, "velocities": velocities,
               "forces": forces},
              radius, centre[2], (centre[0] - amplitude, centre[0] + amplitude), t_start,
              buoyancy_n, title)

    if steps > 1:
        say(f"mean speed: {steps_per_s:.2f} steps/s ({1000.0 / steps_per_s:.1f} ms/step) over "
            f"steps 2..{steps}; the first step ({step_ms[0]:.0f} ms, which may include the "
            "driver's shader compilation) is excluded")
    else:
        say(f"one step: {step_ms[0]:.0f} ms (may include the driver's shader compilation; no mean speed)")
    moving = forces[warmup_steps:]
    say(f"force range while sweeping: x {moving[:, 0].min():+.4g}..{moving[:, 0].max():+.4g} N, "
        f"z {moving[:, 2].min():+.4g}..{moving[:, 2].max():+.4g} N")
    say(f"wrote {csv_path}")
    if png_path is not None:
        say(f"wrote {png_path}")

    return DemoResult(
        out_dir=out,
        csv_path=csv_path,
        png_path=png_path,
        steps_per_s=steps_per_s,
        first_step_ms=float(step_ms[0]),
        times=times,
        probe_positions=positions,
        probe_velocities=velocities,
        forces=forces,
        residuals=residuals,
        step_ms=step_ms,
        sweep_start_frame=warmup_steps + 1,
        device=dict(info),
    )
