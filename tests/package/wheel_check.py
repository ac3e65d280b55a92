# SPDX-License-Identifier: GPL-3.0-or-later
"""Run by test_wheel_install.sh with `python -I` in an empty environment: the installed wheel
imports from the venv, steps a 16^3 simulation, writes a VDB, and uses its vendored libraries."""

import importlib.metadata
import os

import numpy as np

import hapticfluid as hf

VENV, RUN_DIR = os.environ["HF_VENV"], os.environ["HF_RUN_DIR"]


def check(condition, message):
    if not condition:
        raise AssertionError(message)
    print("ok:", message, flush=True)


check(hf.__file__.startswith(VENV), f"hapticfluid imported from the venv: {hf.__file__}")
check(hf.__version__ == importlib.metadata.version("hapticfluid"),
      f"__version__ {hf.__version__} is the wheel's version")
sim = hf.Simulation(resolution=(16, 16, 16), domain_size=(1.0, 1.0, 1.0))
sim.set_smoke_source(centre=(0.5, 0.5, 0.15), radius=0.15, density=1.0, temperature=1.0)
sim.set_probe(centre=(0.3, 0.5, 0.5), radius=0.12, velocity=(0.5, 0.0, 0.0))
for _ in range(3):
    report = sim.step(1 / 30)
density = sim.density()
check(density.shape == (16, 16, 16) and np.isfinite(density).all() and density.max() > 0
      and np.isfinite(report.force).all(),
      f"3 steps of 16^3: max density {density.max():.3f}, force {report.force.tolist()} N")
vdb = os.path.join(RUN_DIR, "density.vdb")
hf.write_vdb(vdb, density, voxel_size=1.0 / 16)
check(os.path.getsize(vdb) > 0, f"wrote a VDB with OpenVDB {hf.openvdb_version()}")

with open("/proc/self/maps") as f:
    mapped = sorted({line.split()[-1] for line in f if ".so" in line and "/" in line})
keys = ("openvdb", "tbb", "blosc", "boost", "imath", "usb")
native = [p for p in mapped if any(k in os.path.basename(p).lower() for k in keys)]
print("vendored libraries in use:\n  " + "\n  ".join(native), flush=True)
outside = [p for p in native if not p.startswith(os.path.join(VENV, ""))]
check(native and not outside, f"all of OpenVDB/TBB/blosc/boost/Imath/libusb come from the venv (outside: {outside})")
