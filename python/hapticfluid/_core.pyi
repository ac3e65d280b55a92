"""Type stub of the native module hapticfluid._core (SI units throughout)."""

import enum
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

CELL_OUTSIDE: int
CELL_SURROUNDING: int
CELL_BOUNDARY: int
CELL_INSIDE: int
STEP_READBACK_BYTES: int  # bytes of the result read-back ending every step (+ residual checks if pressure_tolerance > 0)
MIN_TIME_STEP_S: float  # smallest dt Simulation.step() takes, s
MAX_TIME_STEP_S: float  # largest dt Simulation.step() takes, s
SOURCE_EMISSIONS: Tuple[str, ...]  # smoke source emission modes: 'hold', 'rate'
MAX_SOURCE_DENSITY: float  # largest source density (concentration, or per second with 'rate')
MAX_SOURCE_TEMPERATURE_K: float  # largest source temperature (K above ambient, or K/s with 'rate')
SOURCE_SUBSAMPLES: int  # a mesh source's coverage: vertical sample lines per cell along x and along y

Vec3 = Sequence[float]
Matrix4 = Union[npt.ArrayLike, Sequence[Sequence[float]]]  # 4x4, rows; translation in the last column

class HapticFluidError(RuntimeError): ...
class InvalidArgumentError(HapticFluidError, ValueError): ...
class MeshNotClosedError(InvalidArgumentError): ...
class GlError(HapticFluidError): ...
class DeviceError(HapticFluidError): ...
class DeviceNotFoundError(DeviceError): ...
class DeviceAccessDeniedError(DeviceError): ...
class DeviceUnpluggedError(DeviceError): ...
class VdbError(HapticFluidError): ...

def list_egl_devices() -> str: ...
def probe_device(device: str = "", backend: str = "") -> Dict[str, object]: ...
BACKENDS: Tuple[str, ...]
def estimate_bytes(resolution: Sequence[int]) -> int: ...
def write_vdb(
    path: str,
    density: npt.ArrayLike,  # (nx, ny, nz) concentration
    voxel_size: float,  # m
    origin: Vec3 = (0.0, 0.0, 0.0),  # m, the domain's minimum corner
    velocity: Optional[Tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike]] = None,  # m/s, MAC faces
    pressure: Optional[npt.ArrayLike] = None,  # Pa
    compression: str = "blosc",
    half_float: bool = False,
    tolerance: float = 0.0,
    metadata: Mapping[str, Union[bool, int, float, str, Sequence[float]]] = ...,
) -> None: ...
def vdb_compressions() -> list[str]: ...
def flush_log() -> None: ...  # the engine's queued messages -> logging (hapticfluid.gl, .fluid, .haptics, .session)
def openvdb_version() -> str: ...

class StepReport:
    @property
    def force(self) -> npt.NDArray[np.float32]: ...  # N, shape (3,)
    @property
    def torque(self) -> npt.NDArray[np.float32]: ...  # N m about torque_centre, shape (3,)
    @property
    def torque_centre(self) -> npt.NDArray[np.float32]: ...  # m, shape (3,)
    @property
    def exposed_faces(self) -> int: ...
    @property
    def solid_cells(self) -> int: ...
    @property
    def pressure_iterations(self) -> int: ...
    @property
    def relative_residual(self) -> float: ...
    @property
    def initial_relative_residual(self) -> float: ...
    @property
    def converged(self) -> bool: ...
    @property
    def warning(self) -> str: ...
    @property
    def wall_ms(self) -> float: ...
    @property
    def gpu_ms(self) -> Dict[str, float]: ...

class Advection(enum.Enum):
    semi_lagrangian = 0
    maccormack = 1

class PressureSolver(enum.Enum):
    jacobi = 0
    multigrid = 1

class SourceEmission(enum.Enum):
    hold = 0
    rate = 1

class ForceFilter(enum.Enum):
    lowpass = 0
    none = 1

class Feel(enum.Enum):
    amplified = 0
    physical = 1

class FluidSettings:
    """The grid, the fluid and its solver, the device (SI units); defaults are the engine's."""
    def __init__(self, **settings: Any) -> None: ...
    resolution: Tuple[int, int, int]
    domain_size: Tuple[float, float, float]  # m
    origin: Tuple[float, float, float]  # m
    backend: str  # 'auto', 'gpu', 'cpu' ('' = HAPTICFLUID_BACKEND or auto)
    cpu_threads: int  # 0 = one per core
    device: str
    fluid_density: float  # kg/m^3
    gravity: Tuple[float, float, float]  # m/s^2
    open_top: bool
    advection: Advection  # or its name
    vorticity: float
    smoke_weight: float  # m/s^2 per unit concentration
    heat_buoyancy: float  # m/s^2/K
    smoke_dissipation: float  # 1/s
    heat_dissipation: float  # 1/s
    conserve_smoke: bool
    pressure_solver: PressureSolver  # or its name
    pressure_iterations: int
    pressure_tolerance: float  # relative residual; 0 = fixed iteration count
    compute_residual: bool
    cut_cells: bool
    @staticmethod
    def fields() -> List[str]: ...
    @staticmethod
    def limits() -> Dict[str, Dict[str, Union[float, bool]]]: ...  # name -> min, max, max_exclusive
    def to_dict(self) -> Dict[str, object]: ...
    def copy(self) -> "FluidSettings": ...

class HapticSessionSettings:
    """Everything a HapticSession is made with (SI units); defaults are the engine's."""
    def __init__(self, **settings: Any) -> None: ...
    workspace_scale: Union[float, Tuple[float, float, float]]  # domain m per device m
    fit_workspace: bool  # the largest uniform scale at which the device's workspace fits the domain
    workspace_offset: Optional[Tuple[float, float, float]]  # m; None = workspace middle at domain centre
    force_gain: Optional[float]  # device N per fluid N; None = what the device can render
    probe_radius: Optional[float]  # m; None = keep the simulation's probe
    filter: ForceFilter  # or its name
    bandwidth_ratio: float
    max_cutoff_per_rate: float
    prediction: bool
    max_force: Optional[float]  # N; None = the device's maximum
    slew_rate: float  # N/s
    ramp_time: float  # s
    stale_after: float  # s
    stale_periods: float
    stale_after_max: float  # s
    fade_time: float  # s
    passivity: bool
    passivity_max_damping: Optional[float]  # N s/m; None = the device's max_damping
    passivity_deadband: float  # m/s
    passivity_reserve: float  # J
    passivity_memory: float  # s
    rate: float  # Hz
    sim_dt: float  # s; 0 = real time
    min_sim_dt: float  # s
    max_sim_dt: float  # s
    realtime: bool
    trace: bool
    trace_seconds: float  # s
    snapshot: Optional[float]  # s between field snapshots; 0 = every step; None = off
    snapshot_temperature: bool
    allow_unsafe_gain: bool  # a given force_gain above the passive one is refused without it
    feel: Feel  # or its name: amplified (the derived gain) or physical (1:1), with force_gain None
    coupling: bool  # render at 1 kHz through a virtual coupling (False: the low-passed step force)
    coupling_stiffness: float  # N/m; 0 = a quarter of the device's max_stiffness
    coupling_damping: float  # N s/m; 0 = half the device's max_damping
    guide_stiffness: float  # N/m, haptic playback (set_guide); 0 = a quarter of the device's max_stiffness
    guide_damping: float  # N s/m; 0 = a quarter of the device's max_damping
    guide_max_force: float  # N; 0 = half of max_force
    guide_ramp: float  # s, fade in and out (0.01 .. 5)
    guide_stale: float  # s, a played pose not renewed within it is let go (0.05 .. 10)
    @staticmethod
    def fields() -> List[str]: ...
    @staticmethod
    def limits() -> Dict[str, Dict[str, Union[float, bool]]]: ...
    def to_dict(self) -> Dict[str, object]: ...
    def copy(self) -> "HapticSessionSettings": ...

class Simulation:
    def __init__(self, settings: Optional[FluidSettings] = None, **settings_by_name: Any) -> None: ...
    @property
    def settings(self) -> FluidSettings: ...
    @property
    def device(self) -> Dict[str, object]: ...
    @property
    def resolution(self) -> Tuple[int, int, int]: ...
    @property
    def cell_size(self) -> float: ...
    @property
    def pressure_tolerance_floor(self) -> float: ...
    @property
    def domain_size(self) -> npt.NDArray[np.float32]: ...
    @property
    def origin(self) -> npt.NDArray[np.float32]: ...
    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> int: ...
    fluid_density: float
    gravity: Tuple[float, float, float]
    open_top: bool
    advection: Advection
    vorticity: float
    smoke_weight: float
    heat_buoyancy: float
    smoke_dissipation: float
    heat_dissipation: float
    conserve_smoke: bool
    pressure_iterations: int
    compute_residual: bool
    pressure_solver: PressureSolver
    pressure_tolerance: float
    cut_cells: bool
    def set_probe(self, centre: Vec3, radius: float, velocity: Vec3 = ..., angular_velocity: Vec3 = ...) -> None: ...
    def set_mesh_probe(
        self,
        vertices: npt.ArrayLike,  # (N, 3) m, local frame
        triangles: npt.ArrayLike,  # (M, 3) int vertex indices
        transform: Optional[Matrix4] = None,  # local -> world (matrix_world), m
        velocity: Vec3 = (0.0, 0.0, 0.0),  # m/s, of the origin
        angular_velocity: Vec3 = (0.0, 0.0, 0.0),  # rad/s, world frame
        torque_centre: Optional[Vec3] = None,  # m, world; None = voxelized centroid
    ) -> None: ...
    def set_probe_pose(
        self,
        transform: Optional[Matrix4],  # local -> world, m (sphere: translation = centre)
        velocity: Vec3 = (0.0, 0.0, 0.0),  # m/s
        angular_velocity: Vec3 = (0.0, 0.0, 0.0),  # rad/s
    ) -> None: ...
    def clear_probe(self) -> None: ...
    @property
    def probe(self) -> Optional[Dict[str, object]]: ...
    def set_smoke_source(
        self,
        centre: Vec3,  # m
        radius: float,  # m
        density: float = 1.0,  # concentration ('hold') or per second ('rate')
        temperature: float = 0.0,  # K above ambient ('hold') or K/s ('rate')
        emission: Union[SourceEmission, str] = "hold",  # SourceEmission or its name
    ) -> None: ...
    def set_smoke_source_mesh(
        self,
        vertices: npt.ArrayLike,  # (N, 3) m, local frame
        triangles: npt.ArrayLike,  # (M, 3) int vertex indices, closed mesh
        transform: Optional[Matrix4] = None,  # local -> world (matrix_world), m
        density: float = 1.0,  # concentration ('hold') or per second ('rate')
        temperature: float = 0.0,  # K above ambient ('hold') or K/s ('rate')
        emission: Union[SourceEmission, str] = "hold",  # SourceEmission or its name
    ) -> None: ...
    def set_smoke_source_pose(self, transform: Optional[Matrix4]) -> None: ...  # local -> world, m
    @property
    def smoke_source(self) -> Optional[Dict[str, object]]: ...
    def clear_smoke_source(self) -> None: ...
    def step(self, dt: float) -> StepReport: ...
    @property
    def last_report(self) -> StepReport: ...
    def reset(self) -> None: ...
    def close(self) -> None: ...
    @property
    def closed(self) -> bool: ...
    def __enter__(self) -> "Simulation": ...
    def __exit__(self, *args: object) -> None: ...
    def density(self) -> npt.NDArray[np.float32]: ...
    def temperature(self) -> npt.NDArray[np.float32]: ...
    def pressure(self, hydrostatic: bool = True) -> npt.NDArray[np.float32]: ...
    def velocity(self) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32], npt.NDArray[np.float32]]: ...
    def cell_classes(self) -> npt.NDArray[np.uint8]: ...
    def state(self) -> Dict[str, object]: ...  # float32 arrays + 'time' (s), 'steps'
    def set_state(self, state: Mapping[str, object]) -> None: ...

def check_sphere_probe(settings: FluidSettings, centre: Vec3, radius: float) -> None: ...  # m; as set_probe checks
def check_mesh_probe(
    settings: FluidSettings,
    vertices: npt.ArrayLike,  # (N, 3) m, local frame
    triangles: npt.ArrayLike,  # (M, 3) int vertex indices
    transform: Optional[Matrix4] = None,  # local -> world, m
) -> None: ...  # as set_mesh_probe checks the pose

# ---- haptics (device frame and SI units: m, m/s, N; times on time.monotonic()) ----

class DeviceInfo:
    @property
    def name(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @property
    def serial(self) -> str: ...
    @property
    def workspace_min(self) -> npt.NDArray[np.float32]: ...  # m, device frame
    @property
    def workspace_max(self) -> npt.NDArray[np.float32]: ...  # m
    @property
    def max_force(self) -> float: ...  # N
    @property
    def max_stiffness(self) -> float: ...  # N/m; 0 = not reported
    @property
    def max_damping(self) -> float: ...  # N s/m; 0 = not reported
    @property
    def position_resolution(self) -> float: ...  # m; 0 = exact or not reported

class DeviceState:
    @property
    def position(self) -> npt.NDArray[np.float32]: ...  # m, device frame
    @property
    def velocity(self) -> npt.NDArray[np.float32]: ...  # m/s
    @property
    def buttons(self) -> int: ...
    @property
    def homed(self) -> bool: ...
    @property
    def time(self) -> float: ...  # s
    @property
    def orientation(self) -> Optional[Tuple[float, float, float, float]]: ...  # (w, x, y, z); None: 3-DoF
    @property
    def angular_velocity(self) -> npt.NDArray[np.float32]: ...  # rad/s, device frame

class Device:
    def info(self) -> DeviceInfo: ...
    def read(self) -> DeviceState: ...
    def write_force(self, force: Vec3) -> None: ...  # N, device frame
    def close(self) -> None: ...
    def __enter__(self) -> "Device": ...
    def __exit__(self, *args: object) -> None: ...

class ScriptedDevice(Device):
    @property
    def duration(self) -> float: ...  # s
    @property
    def loops(self) -> bool: ...
    def state_at(self, t: float) -> DeviceState: ...  # t finite (s)
    @property
    def last_force(self) -> npt.NDArray[np.float32]: ...  # N

class HostDevice(Device):
    def push_pose(
        self,
        position: Vec3,  # m, |coordinate| <= 1e6
        time: Optional[float] = None,  # s, increasing
        orientation: Optional[Tuple[float, float, float, float]] = None,  # quaternion (w, x, y, z)
    ) -> None: ...
    @property
    def pushes(self) -> int: ...
    def state_after(self, elapsed: float) -> DeviceState: ...  # elapsed not NaN (s)
    @property
    def last_force(self) -> npt.NDArray[np.float32]: ...  # N

def null_device(max_force: float = 10.0) -> Device: ...  # max_force in (0, 1000] N, as for every virtual device
def scripted_device(
    times: Sequence[float], positions: Sequence[Vec3], loop: bool = False, max_force: float = 10.0
) -> ScriptedDevice: ...
def scripted_device_from_csv(path: str, loop: bool = False, max_force: float = 10.0) -> ScriptedDevice: ...
def host_device(max_force: float = 10.0, extrapolate: bool = True) -> HostDevice: ...

def haptic_session_defaults() -> Dict[str, object]: ...

class HapticSession:
    def __init__(
        self,
        simulation: Simulation,
        device: Device,
        settings: Optional[HapticSessionSettings] = None,
        **settings_by_name: Any,
    ) -> None: ...
    def probe_origin(self, positions: npt.ArrayLike) -> npt.NDArray[np.float32]: ...  # device m -> world m
    @staticmethod
    def probe_rotation(transform: Any) -> Tuple[float, float, float, float]: ...  # 4x4 -> (w, x, y, z)
    @property
    def workspace_box(self) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]: ...  # world m (lo, hi)
    @property
    def settings(self) -> HapticSessionSettings: ...
    def start(self) -> None: ...
    def pause(self) -> None: ...
    def resume(self) -> None: ...
    def stop(self, timeout: float = 10.0) -> None: ...  # s
    def set_guide(self, position: Vec3, velocity: Vec3 = (0.0, 0.0, 0.0)) -> None: ...  # world m, m/s
    def release_guide(self) -> None: ...
    @property
    def state(self) -> str: ...
    @property
    def error(self) -> Optional[str]: ...
    def stats(self) -> Dict[str, object]: ...
    @property
    def latest_force(self) -> npt.NDArray[np.float32]: ...  # N, device frame
    def latest(self) -> Dict[str, object]: ...  # commanded_force (device axes), commanded_force_world (world axes), ...
    def trace(self) -> Dict[str, npt.NDArray[np.float64]]: ...
    @property
    def device(self) -> Device: ...
    def snapshot(self) -> Optional[Dict[str, object]]: ...  # sequence, time (s), steps, resolution, density, temperature
    @property
    def workspace_offset(self) -> npt.NDArray[np.float32]: ...  # m
    @property
    def workspace_scale(self) -> npt.NDArray[np.float32]: ...  # domain m per device m
    def __enter__(self) -> "HapticSession": ...
    def __exit__(self, *args: object) -> None: ...

class FalconDevice(Device):
    def stats(self) -> Dict[str, object]: ...
    def home(self, timeout: float = 60.0) -> None: ...  # s

def list_falcons(probe_firmware: bool = True) -> List[Dict[str, object]]: ...
def falcon_udev_rule() -> str: ...
def open_falcon(
    firmware: Optional[str] = None,
    index: int = 0,
    home: bool = True,
    homing_timeout: float = 60.0,  # s
    max_force: float = 8.0,  # N
) -> FalconDevice: ...
def open_simulated_falcon(
    firmware_bytes: Optional[bytes] = None,
    home: bool = True,
    homing_timeout: float = 10.0,  # s
    max_force: float = 8.0,  # N
    hand_mass: float = 0.15,  # kg
    hand_stiffness: float = 300.0,  # N/m
    hand_damping: float = 12.0,  # N s/m
    unplug_after: Optional[int] = None,  # packets
    hand_path: Optional[Sequence[Tuple[float, float, float, float]]] = None,  # (t s, x, y, z m) after homing
    hand_loop: bool = False,
    hand_stiffness_homed: Optional[float] = None,  # N/m once homed (a hand resting on the grip)
) -> FalconDevice: ...
