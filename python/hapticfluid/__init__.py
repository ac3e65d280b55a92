# SPDX-License-Identifier: GPL-3.0-or-later
"""Touchable GPU fluids: a 3D smoke/fluid simulation on the GPU with a probe you can feel.

The native engine lives in the private module ``hapticfluid._core``; this package re-exports
its public API. All quantities are SI (metres, seconds, kilograms, newtons, pascals), z is up.

Example::

    import hapticfluid as hf
    sim = hf.Simulation(resolution=(64, 64, 64), domain_size=(1.0, 1.0, 1.0))
    sim.set_probe(centre=(0.5, 0.5, 0.5), radius=0.1, velocity=(0.2, 0.0, 0.0))
    report = sim.step(1 / 60)
    print(report.force)   # newtons on the probe
"""

import numpy as _numpy

from hapticfluid import _core
from hapticfluid._compat import check_numpy as _check_numpy

_check_numpy(_numpy.__version__, _core._PYBIND11_VERSION)  # wrong arrays otherwise: refused, said why

from hapticfluid._lifetime import install as _stop_sessions_at_exit  # noqa: E402

_stop_sessions_at_exit(_core)  # no session thread outlives the interpreter

from hapticfluid._core import (  # noqa: E402  (after _lifetime's wrapping of HapticSession)
    CELL_BOUNDARY,
    CELL_INSIDE,
    BACKENDS,
    STEP_READBACK_BYTES,
    MIN_TIME_STEP_S,
    MAX_TIME_STEP_S,
    MAX_SOURCE_DENSITY,
    MAX_SOURCE_TEMPERATURE_K,
    SOURCE_EMISSIONS,
    SOURCE_SUBSAMPLES,
    CELL_OUTSIDE,
    CELL_SURROUNDING,
    Advection,
    FluidSettings,
    ForceFilter,
    HapticSessionSettings,
    PressureSolver,
    SourceEmission,
    Device,
    DeviceInfo,
    DeviceState,
    FalconDevice,
    Feel,
    HapticFluidError,
    VdbError,
    MeshNotClosedError,
    GlError,
    DeviceUnpluggedError,
    DeviceNotFoundError,
    DeviceError,
    DeviceAccessDeniedError,
    HapticSession,
    HostDevice,
    InvalidArgumentError,
    ScriptedDevice,
    Simulation,
    StepReport,
    check_mesh_probe,
    check_sphere_probe,
    estimate_bytes,
    falcon_udev_rule,
    flush_log,
    haptic_session_defaults,
    host_device,
    list_egl_devices,
    list_falcons,
    null_device,
    open_falcon,
    open_simulated_falcon,
    openvdb_version,
    probe_device,
    scripted_device,
    scripted_device_from_csv,
    vdb_compressions,
    write_vdb,
)

# The project's one version is project(VERSION) in CMakeLists.txt; the wheel build and the
# package_versions test refuse a different one here.
__version__ = "0.1.0"

__all__ = [
    "CELL_BOUNDARY",
    "CELL_INSIDE",
    "BACKENDS",
    "STEP_READBACK_BYTES",
    "MIN_TIME_STEP_S",
    "MAX_TIME_STEP_S",
    "MAX_SOURCE_DENSITY",
    "MAX_SOURCE_TEMPERATURE_K",
    "SOURCE_EMISSIONS",
    "SOURCE_SUBSAMPLES",
    "CELL_OUTSIDE",
    "CELL_SURROUNDING",
    "Advection",
    "FluidSettings",
    "ForceFilter",
    "HapticSessionSettings",
    "PressureSolver",
    "SourceEmission",
    "Device",
    "DeviceInfo",
    "DeviceState",
    "FalconDevice",
    "Feel",
    "HapticFluidError",
    "VdbError",
    "MeshNotClosedError",
    "GlError",
    "DeviceUnpluggedError",
    "DeviceNotFoundError",
    "DeviceError",
    "DeviceAccessDeniedError",
    "HapticSession",
    "HostDevice",
    "InvalidArgumentError",
    "ScriptedDevice",
    "Simulation",
    "StepReport",
    "check_mesh_probe",
    "check_sphere_probe",
    "estimate_bytes",
    "falcon_udev_rule",
    "flush_log",
    "haptic_session_defaults",
    "host_device",
    "list_egl_devices",
    "list_falcons",
    "null_device",
    "open_falcon",
    "open_simulated_falcon",
    "openvdb_version",
    "probe_device",
    "scripted_device",
    "scripted_device_from_csv",
    "vdb_compressions",
    "write_vdb",
]
