# SPDX-License-Identifier: GPL-3.0-or-later
"""The benchmark scene: a hot smoke plume rising from a sphere source near the floor, vorticity
confinement on, and a sphere probe swinging along x through the plume at mid height. The
engine, read-back and Mantaflow sections all use it, so their figures describe the same work.

Positions and sizes are fractions of the domain (the scene scales with the box); the physics
settings are the demo's (:class:`hapticfluid.demo.DemoScene`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, Tuple

import hapticfluid as hf
from hapticfluid.demo import DemoScene

Vec3 = Tuple[float, float, float]

# The seed paper's grid (Yang et al. 2008, Table 1): 100 x 100 x 70 cells; with 1 cm cells the
# box is 1 x 1 x 0.7 m, the Mantaflow domain's size.
SEED_RESOLUTION = (100, 100, 70)
SEED_DOMAIN = (1.0, 1.0, 0.7)


@dataclass(frozen=True)
class BenchScene:
    resolution: Tuple[int, int, int]
    domain_size: Vec3  # m
    dt_s: float = 1.0 / 30.0  # s per step
    sweep_amplitude: float = 0.25  # fraction of the domain width
    sweep_period_s: float = 2.0  # s per there-and-back
    probe_height: float = 0.55  # fraction of the domain height
    physics: DemoScene = DemoScene()

    @property
    def cell_size(self) -> float:
        return self.domain_size[0] / self.resolution[0]

    @property
    def cells(self) -> int:
        nx, ny, nz = self.resolution
        return nx * ny * nz

    @property
    def label(self) -> str:
        nx, ny, nz = self.resolution
        return f"{nx}^3" if nx == ny == nz else f"{nx}x{ny}x{nz}"

    def _min_edge(self) -> float:
        return min(self.domain_size)

    @property
    def source_radius_m(self) -> float:
        return max(self.physics.source_radius * self._min_edge(), 1.5 * self.cell_size)

    @property
    def source_centre_m(self) -> Vec3:
        return tuple(f * l for f, l in zip(self.physics.source_centre, self.domain_size))  # type: ignore[return-value]

    @property
    def probe_radius_m(self) -> float:
        return max(self.physics.probe_radius * self._min_edge(), 1.5 * self.cell_size)

    def probe_pose(self, t_s: float) -> Tuple[Vec3, Vec3]:
        """Probe centre (m) and velocity (m/s) at time t: x = x_c + A sin(2 pi t / T)."""
        lx, ly, lz = self.domain_size
        amplitude = self.sweep_amplitude * lx
        omega = 2.0 * math.pi / self.sweep_period_s
        x = 0.5 * lx + amplitude * math.sin(omega * t_s)
        vx = amplitude * omega * math.cos(omega * t_s)
        return (x, 0.5 * ly, self.probe_height * lz), (vx, 0.0, 0.0)

    def simulation_kwargs(self) -> Dict[str, object]:
        p = self.physics
        return dict(resolution=self.resolution, domain_size=self.domain_size,
                    fluid_density=p.fluid_density, open_top=p.open_top, vorticity=p.vorticity,
                    heat_buoyancy=p.heat_buoyancy, smoke_weight=p.smoke_weight,
                    smoke_dissipation=p.smoke_dissipation, heat_dissipation=p.heat_dissipation)

    def make_simulation(self, **solver_kwargs) -> "hf.Simulation":
        """A Simulation of this scene; ``solver_kwargs`` pick the pressure solver."""
        kwargs = self.simulation_kwargs()
        kwargs.update(solver_kwargs)
        sim = hf.Simulation(**kwargs)
        p = self.physics
        sim.set_smoke_source(self.source_centre_m, self.source_radius_m, density=p.source_density,
                             temperature=p.source_temperature)
        self.place_probe(sim, 0.0)
        return sim

    def place_probe(self, sim: "hf.Simulation", t_s: float) -> None:
        centre, velocity = self.probe_pose(t_s)
        sim.set_probe(centre, self.probe_radius_m, velocity=velocity)

    def step(self, sim: "hf.Simulation", dt_s: float = 0.0) -> "hf.StepReport":
        """One step of ``dt_s`` (default: the scene's), the probe posed at the step's end."""
        dt = dt_s or self.dt_s
        self.place_probe(sim, sim.time + dt)
        return sim.step(dt)
