# SPDX-License-Identifier: GPL-3.0-or-later
"""The CPU backend flushes denormal floats to zero (cpp/cpu/float_mode.h), as GLSL lets a shader do:
a decaying plume's tiny values would otherwise take the x86 cores' slow path (the live 32^3 step
7.8 ms against 6.2 on the Intel VM of 2026-12-07)."""

import numpy as np

from hapticfluid.bench.scene import BenchScene, DemoScene


def test_a_decaying_plume_on_the_cpu_backend_holds_no_denormal_floats():
    """40 steps of the live demo's 32^3 scene (smoke and heat dissipating, open top): with IEEE
    denormals kept, 8.8 % of the density and 9.2 % of the temperature cells are denormal by then
    (the GPU backend on llvmpipe, and the CPU backend before the flush); here none is, and every
    field is finite."""
    scene = BenchScene((32, 32, 32), (1.0, 1.0, 1.0), dt_s=1.0 / 30.0, physics=DemoScene(open_top=True))
    with scene.make_simulation(pressure_solver="multigrid", pressure_iterations=50, pressure_tolerance=1e-3,
                               compute_residual=False, backend="cpu") as sim:
        for _ in range(40):
            scene.step(sim)
        state = sim.state()
    tiny = np.finfo(np.float32).tiny
    checked = 0
    for name, field in state.items():
        if isinstance(field, np.ndarray) and field.dtype == np.float32:
            assert np.isfinite(field).all(), name
            magnitude = np.abs(field)
            denormal = int(((magnitude > 0) & (magnitude < tiny)).sum())
            assert denormal == 0, f"{name}: {denormal} denormal cells"
            checked += 1
    assert checked >= 5 and float(state["density"].max()) > 0.5  # the plume is there
