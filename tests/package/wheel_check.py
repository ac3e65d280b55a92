# SPDX-License-Identifier: GPL-3.0-or-later
"""Run by test_wheel_install.sh with `python -I` in an empty environment: the installed wheel
imports from the venv, steps a 16^3 simulation and writes a VDB; its module holds OpenVDB, TBB,
blosc, Imath and libusb inside itself, exports only its init function, and needs nothing of the
system beyond glibc 2.28 and libglvnd (read from its ELF tables with binutils)."""

import glob
import importlib.metadata
import os
import re
import subprocess

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
# Read back by the system's OpenVDB (vdb_print, Debian's libopenvdb-tools): the grid, its voxels and values.
# HF_VDB_READBACK=0 (test_old_glibc.sh: the bullseye tree checks the run on glibc 2.31 and has no
# OpenVDB of its own) leaves it to the host's run of this check, saying so.
if os.environ.get("HF_VDB_READBACK", "1") == "0":
    print("not here: the VDB's read-back by the system's OpenVDB (HF_VDB_READBACK=0: the host's run of this "
          "check reads it back)", flush=True)
    printed = None
else:
    try:
        printed = subprocess.run(["vdb_print", "-l", "-m", vdb], capture_output=True, text=True, check=True).stdout
    except FileNotFoundError:
        raise AssertionError("vdb_print is missing: it reads the wheel's VDB back (apt-get install libopenvdb-tools)")
field = dict(re.findall(r"^[ \t]*([A-Za-z_ ]+?):[ \t]+(\S.*?)[ \t]*$", printed or "", re.M))
active = density[density != 0.0]
check(printed is None or field.get("Name") == "density" and field.get("Type") == "Tree_float_5_4_3"
      and int(field.get("Number of active voxels", -1)) == active.size
      and abs(float(field.get("Min value", "nan")) - float(active.min())) <= 1e-5 * float(active.max())
      and abs(float(field.get("Max value", "nan")) - float(active.max())) <= 1e-5 * float(active.max())
      and abs(float(field.get("voxel size", "nan")) - 1.0 / 16) <= 1e-9,
      f"OpenVDB reads it back: grid {field.get('Name')} ({field.get('Type')}), {field.get('Number of active voxels')} "
      f"active voxels of {active.size}, values {field.get('Min value')} .. {field.get('Max value')}")

# The module's ELF tables (binutils' readelf and objdump, Debian's binutils).
core = glob.glob(os.path.join(os.path.dirname(hf.__file__), "_core.*.so"))[0]
dynamic = subprocess.run(["readelf", "-dW", core], capture_output=True, text=True, check=True).stdout
symbols = subprocess.run(["objdump", "-T", core], capture_output=True, text=True, check=True).stdout
needed = set(re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", dynamic))
SYSTEM = {"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "librt.so.1", "ld-linux-x86-64.so.2",
          "libEGL.so.1", "libOpenGL.so.0"}  # glibc's, and libglvnd's (left to the system on purpose)
check(needed and needed <= SYSTEM, f"_core needs only glibc and libglvnd: {sorted(needed)}")
glibc = sorted({tuple(map(int, v.split("."))) for v in re.findall(r"\bGLIBC_([0-9.]+)", symbols)})
check(glibc and glibc[-1] <= (2, 28), f"_core's newest glibc symbol version is {'.'.join(map(str, glibc[-1]))} (<= 2.28)")
cxx = sorted(set(re.findall(r"\b(GLIBCXX_[0-9.]+|CXXABI_[0-9.]+|GCC_[0-9.]+)", symbols)))
check(not cxx, f"_core needs no libstdc++ or libgcc_s versions (its C++ runtime is inside): {cxx}")
exported = [line.split()[-1] for line in symbols.splitlines()
            if " g " in line and "*UND*" not in line and re.match(r"^[0-9a-f]{8,}", line)]
check(exported == ["PyInit__core"], f"_core exports only its init function: {exported[:5]}")
undefined = [line.split()[-1] for line in symbols.splitlines() if "*UND*" in line]
foreign = [u for u in undefined if re.search(r"openvdb|tbb|blosc|Imath|libusb", u)]
check(undefined and not foreign, f"_core binds none of OpenVDB/TBB/blosc/Imath/libusb outside itself: {foreign[:5]}")
with open("/proc/self/maps") as f:
    mapped = sorted({line.split()[-1] for line in f if ".so" in line and "/" in line})
keys = ("openvdb", "tbb", "blosc", "boost", "imath", "usb")
native = [p for p in mapped if any(k in os.path.basename(p).lower() for k in keys)]
check(not native, f"no OpenVDB/TBB/blosc/boost/Imath/libusb library was loaded beside _core: {native}")
