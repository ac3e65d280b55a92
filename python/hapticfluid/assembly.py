# SPDX-License-Identifier: GPL-3.0-or-later
"""One place that turns a scene description into engine objects, for the bake, the Blender add-on's
live session, the demo and the command lines alike:

- ``build(SceneDescription(settings, source, probe), device, session_settings)``: the one place a
  Simulation (and a HapticSession) is made: the Simulation of a FluidSettings, its smoke source
  and its probe at their first poses, and, given a device, the session over them;
- ``grid(domain_size, resolution)``: the cubic cells of a domain (cells along its longest edge);
- ``fluid_settings(...)``: a FluidSettings from the domain, the resolution and the fluid's settings
  by name (the engine's defaults for the rest);
- ``place_probe(sim, Probe(...))`` and ``place_source(sim, Source(...))``: how the engine takes a
  probe and a smoke source (a sphere placed whole, its radius following the transform's largest
  scale; a mesh uploaded once, then only its pose changes), at the start and at every later pose;
- ``session_settings(...)``: a HapticSessionSettings from settings by name, the device's workspace
  fitted to the domain by the engine (``fit_workspace``) unless asked not to.

No bpy here: the add-on reads Blender into plain values and calls these.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Optional, Sequence, Tuple

import numpy as np

import hapticfluid as hf

Vec3 = Tuple[float, float, float]

# Pressure iterations per step when a caller gives none, per solver and use: Jacobi sweeps, or
# multigrid-preconditioned CG iterations (four reach a relative residual near 1e-4 for about the
# cost of 40 sweeps). Interactive runs (a haptic session on a small grid) want the simulation's
# rate: there 20 sweeps cost less than multigrid's 4 while the force's cell-crossing impulses, not
# the residual, dominate its error.
ITERATIONS_PER_STEP = {"offline": {"jacobi": 40, "multigrid": 4}, "interactive": {"jacobi": 20, "multigrid": 4}}
SOLVERS = tuple(hf.PressureSolver.__members__)  # the pressure solvers' names ('jacobi', 'multigrid')
ADVECTIONS = tuple(hf.Advection.__members__)  # the advection schemes' names


def iterations_for(solver: str, use: str = "offline", iterations: Optional[int] = None) -> int:
    """``iterations`` if given, else ITERATIONS_PER_STEP's for the solver ('jacobi' or 'multigrid')
    and use ('offline' or 'interactive'). An unknown solver is an InvalidArgumentError naming it."""
    if solver not in SOLVERS:
        raise hf.InvalidArgumentError(f"solver must be one of {', '.join(map(repr, SOLVERS))}, got {solver!r}")
    return ITERATIONS_PER_STEP[use][solver] if iterations is None else iterations


@dataclass(frozen=True)
class Grid:
    cells: Tuple[int, int, int]  # cells per axis, each >= 8
    cell_size: float  # m, the same on every axis
    size: Vec3  # m: whole cells, so possibly a hair off the domain's size


def grid(domain_size: Sequence[float], resolution: int) -> Grid:
    """The grid of a box of ``domain_size`` (m) with ``resolution`` cells along its longest edge:
    cubic cells, at least 8 per axis."""
    h = max(domain_size) / resolution
    cells = tuple(max(8, int(round(s / h))) for s in domain_size)
    return Grid(cells, h, tuple(n * h for n in cells))


# A live session's simulation beside Blender's drawing on the CPU (the CPU backend, or llvmpipe):
# with the viewport first its threads run this much nicer, so the viewport's threads go first
# when both want the cores (CFS weights 1024 : 110 at niceness 0 : 10), and it steps at most
# VIEWPORT_FIRST_STEP_RATE_HZ times a second (HapticSessionSettings.min_sim_dt, its inverse): a
# nicer thread still runs in every gap the drawing's threads leave, and each step beyond what the
# user follows took those gaps from the drawing. Window pace test, 2 cores, 32^3, the CPU backend
# (docs/BENCHMARKS.md, 2026-12-07): uncapped the simulation kept 0.23-0.25 cores at 34-35 steps/s
# (p50 19-23 ms) and the viewport 72.6 % and 78.5 % of its no-session redraws; capped at 30, 0.14-0.16
# cores at 19.7-21.1 steps/s (p50 41-43 ms) and 73-85 % over 7 runs: the runs' spread is larger than
# the cap's effect, the cores it gives back are not. Measured by blender_tests/window_test_live_pace.py.
VIEWPORT_FIRST_NICENESS = 10
VIEWPORT_FIRST_STEP_RATE_HZ = 30.0


def computes_on_cpu(device: Mapping[str, Any]) -> bool:
    """Whether a device (Simulation.device, hf.probe_device()) computes on the CPU's cores: the CPU
    backend, or the GPU backend on a software renderer (llvmpipe)."""
    return device.get("backend") == "cpu" or bool(device.get("software", True))


@dataclass(frozen=True)
class LiveShare:
    """How a live session's simulation shares the machine with Blender's drawing."""
    thread_niceness: int  # FluidSettings.thread_niceness, 0..19
    min_sim_dt: Optional[float]  # s, HapticSessionSettings.min_sim_dt; None: the engine's default


def live_share(on_cpu: bool, viewport_first: bool) -> LiveShare:
    """A live session's share when it computes on the CPU (computes_on_cpu: the same cores Blender
    draws with) and the user wants the viewport first: VIEWPORT_FIRST_NICENESS, and at most
    VIEWPORT_FIRST_STEP_RATE_HZ steps a second. Else niceness 0 and the engine's step rate: on a
    GPU the simulation's threads mostly wait for the GPU (a nicer one would only wait longer for a
    busy main thread), and with Equal (a Falcon) the hand's force wants every step it can get."""
    if on_cpu and viewport_first:
        return LiveShare(VIEWPORT_FIRST_NICENESS, 1.0 / VIEWPORT_FIRST_STEP_RATE_HZ)
    return LiveShare(0, None)


def fluid_settings(origin: Sequence[float], domain_size: Sequence[float], resolution: int,
                   fluid: Optional[Mapping[str, Any]] = None, device: str = "",
                   thread_niceness: int = 0, backend: str = "") -> "hf.FluidSettings":
    """A FluidSettings for a domain box (minimum corner ``origin``, edges ``domain_size``, m) with
    ``resolution`` cells along its longest edge, the fluid's settings by FluidSettings' names
    (the engine's defaults for the rest), the backend ('auto', 'gpu', 'cpu'; '' for
    HAPTICFLUID_BACKEND or auto) and GL device requests, and how much nicer the simulation's
    threads run (``thread_niceness``, 0..19). The residual is not measured (the bake and the live
    session never read it)."""
    g = grid(domain_size, resolution)
    s = hf.FluidSettings(resolution=g.cells, domain_size=g.size, origin=tuple(float(x) for x in origin),
                         backend=backend, device=device, compute_residual=False, thread_niceness=thread_niceness)
    for name, value in (fluid or {}).items():
        setattr(s, name, tuple(value) if isinstance(value, list) else value)
    return s


def sphere_radius(radius: float, matrix: Any) -> float:
    """A sphere probe's radius (m) under a transform: ``radius`` times the transform's largest axis
    scale (the length of its longest column), so a scaled Empty or sphere stays inside its box."""
    m = np.asarray(matrix, dtype=np.float64)
    return float(radius * np.max(np.linalg.norm(m[:3, :3], axis=0)))


@dataclass(frozen=True)
class Probe:
    """The probe at one pose: a sphere (``radius``, m at scale 1) or a closed mesh (``vertices``,
    ``triangles``: its local frame, m) at ``matrix`` (4x4 local -> world, rows, m), moving with
    ``velocity`` (m/s) and ``angular_velocity`` (rad/s, world axes)."""

    shape: str  # "sphere" or "mesh"
    matrix: Any
    radius: Optional[float] = None
    vertices: Any = None
    triangles: Any = None
    velocity: Sequence[float] = (0.0, 0.0, 0.0)
    angular_velocity: Sequence[float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Source:
    """The smoke source at one pose: a sphere (``centre``, ``radius``, m) or a closed mesh
    (``vertices``, ``triangles``: its local frame, m) at ``matrix`` (4x4 local -> world, rows, m),
    emitting ``density`` (concentration) and ``temperature`` (K above ambient), held in its cells or,
    with ``emission`` 'rate', per second. The keys are those of a scene's source (the bake's JSON,
    the add-on's source_dict): ``Source(**source_dict)``."""

    shape: str = "sphere"  # "sphere" or "mesh"
    density: float = 1.0
    temperature: float = 0.0
    emission: Any = "hold"
    centre: Optional[Sequence[float]] = None
    radius: Optional[float] = None
    matrix: Any = None
    vertices: Any = None
    triangles: Any = None


def place_probe(sim: "hf.Simulation", probe: Probe) -> None:
    """Put the probe in place: a sphere placed whole, its radius following the transform's largest
    scale; a mesh uploaded the first time, then only moved (set_probe_pose: host side, cheap)."""
    m = np.asarray(probe.matrix, dtype=np.float64)
    v = tuple(float(x) for x in probe.velocity)
    w = tuple(float(x) for x in probe.angular_velocity)
    if probe.shape == "sphere":
        sim.set_probe(tuple(m[:3, 3]), sphere_radius(probe.radius, m), velocity=v, angular_velocity=w)
    elif (sim.probe or {}).get("kind") != "mesh":  # (Simulation.probe builds its dict on each read)
        sim.set_mesh_probe(np.asarray(probe.vertices, dtype=np.float32), np.asarray(probe.triangles, dtype=np.int32),
                           m, velocity=v, angular_velocity=w)
    else:
        sim.set_probe_pose(m, velocity=v, angular_velocity=w)


def place_source(sim: "hf.Simulation", source: Source) -> None:
    """Put the smoke source in place: a sphere set once; a mesh uploaded the first time, then only
    moved."""
    current = sim.smoke_source
    if source.shape == "sphere":
        if current is None:
            sim.set_smoke_source(tuple(float(x) for x in source.centre), float(source.radius), density=source.density,
                                 temperature=source.temperature, emission=source.emission)
        return
    m = np.asarray(source.matrix, dtype=np.float64)
    if current is None or current.get("kind") != "mesh":
        sim.set_smoke_source_mesh(np.asarray(source.vertices, dtype=np.float32),
                                  np.asarray(source.triangles, dtype=np.int32), m, density=source.density,
                                  temperature=source.temperature, emission=source.emission)
    else:
        sim.set_smoke_source_pose(m)


def session_settings(values: Optional[Mapping[str, Any]] = None,
                     fit_workspace: bool = True) -> "hf.HapticSessionSettings":
    """A HapticSessionSettings with ``values`` by name; with ``fit_workspace`` the engine fits the
    device's workspace to the domain (the largest uniform scale, its middle at the domain's centre
    unless an offset is given), else ``values``' workspace_scale is used."""
    return hf.HapticSessionSettings(**{"fit_workspace": fit_workspace, **dict(values or {})})


@dataclass(frozen=True)
class SceneDescription:
    """What a simulation is made from: its FluidSettings (grid, fluid, solver, GL device), and the
    smoke source and the probe at their first poses (None: none yet)."""

    settings: "hf.FluidSettings"
    source: Optional[Source] = None
    probe: Optional[Probe] = None


def build(scene: SceneDescription, device: Optional["hf.Device"] = None,
          session_settings: Optional["hf.HapticSessionSettings"] = None
          ) -> Tuple["hf.Simulation", Optional["hf.HapticSession"]]:
    """The one place engine objects are made: the Simulation of ``scene.settings``, its smoke
    source, then its probe put in place, then, given a ``device``, a HapticSession over them with
    ``session_settings`` (the engine's defaults when None; see session_settings()), not started.
    Returns (simulation, session or None); the caller owns both (close the simulation, stop the
    session). Raises the engine's own error unchanged (InvalidArgumentError naming what it refuses,
    MeshNotClosedError for the probe's mesh, GlError when no GL context can be made), after closing
    the simulation it made."""
    sim = hf.Simulation(scene.settings)
    try:
        if scene.source is not None:
            place_source(sim, scene.source)
        if scene.probe is not None:
            place_probe(sim, scene.probe)
        session = None
        if device is not None:
            session = hf.HapticSession(sim, device, session_settings)
    except BaseException:
        sim.close()
        raise
    return sim, session
