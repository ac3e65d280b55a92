# SPDX-License-Identifier: GPL-3.0-or-later
"""What a bake simulates and writes: the scene description (a JSON file or a dict).

Format (JSON; every length in metres, times in seconds or frames; keys marked * are required)::

    {
      "domain": {"origin": [0, 0, 0], "size": [1, 1, 1.5]},       * box, min corner + edges (m)
      "resolution": 64,                  * cells along the domain's longest edge; the other edges
                                           get round(edge / h) cells (at least 8) and the box
                                           keeps its origin, so its edges become whole cells
      "fluid": {                           Simulation settings (defaults in brackets)
        "fluid_density": 1.2, "gravity": [0, 0, -9.81], "open_top": false,
        "advection": "semi_lagrangian", "vorticity": 0.0, "smoke_weight": 0.0,
        "heat_buoyancy": 0.0, "smoke_dissipation": 0.0, "heat_dissipation": 0.0,
        "pressure_iterations": 40,       Jacobi sweeps, or multigrid-CG iterations (the cap
                                           when a tolerance is set)
        "pressure_solver": "jacobi",     "jacobi" | "multigrid"
        "pressure_tolerance": 0.0        stop at this relative residual (0: fixed count)
      },
      "source": {                          the smoke emitter, or null / absent
        "shape": "sphere", "centre": [0.5, 0.5, 0.1], "radius": 0.06,   a sphere (m) ["sphere"], or
        "shape": "mesh", "vertices": [[x, y, z], ...], "triangles": [[i, j, k], ...],
                                             a closed triangle mesh in its local frame (m),
                                             emitting from its volume, placed by
        "keys": [{"frame": 1, "matrix": ...}, ...],   keyed transforms as the probe's (mesh only)
        "density": 1.0, "temperature": 8.0,  concentration and K above ambient ("hold"), or
                                             per second ("rate")
        "emission": "hold"                   "hold" | "rate" (Simulation.set_smoke_source_mesh)
      },
      "probe": {                           the moving body, or null / absent
        "shape": "sphere", "radius": 0.08,   sphere radius (m) at scale 1 (scaled by the largest
                                             axis scale of the transform), or
        "shape": "mesh", "vertices": [[x, y, z], ...], "triangles": [[i, j, k], ...],
                                             a closed triangle mesh in its local frame (m), moved
                                             rigidly (and scaled) by the keyed transforms
        "keys": [                          * keyed transforms; linear/slerp between, held outside
          {"frame": 1, "location": [0.2, 0.5, 0.5],
           "rotation": [1, 0, 0, 0],         optional unit quaternion w, x, y, z
           "scale": 1.0},                    optional number or [sx, sy, sz]
          {"frame": 48, "matrix": [[1,0,0,0.8],[0,1,0,0.5],[0,0,1,0.5],[0,0,0,1]]}
        ]                                    (a key gives "location" (+rotation, scale) or "matrix")
      },
      "frames": {"start": 1, "end": 48, "fps": 24},                 * frame range (inclusive), fps
      "substeps": 2,                       fixed steps per frame, or "adaptive" [2]
      "cfl": 1.0, "max_substeps": 16,      adaptive: steps = ceil(max speed * frame time /
                                           (cfl * h)), at least 1, at most max_substeps
      "cache": {
        "directory": "cache",            * relative paths are relative to the scene file
        "grids": ["density", "velocity"],  any of density (always written), velocity, pressure
        "compression": "blosc",            blosc, zip or none
        "half_float": false,               16-bit floats in the files
        "tolerance": 0.0001,               |value| <= tolerance -> inactive voxel (sparse)
        "checkpoint_every": 10             keep the full state every N frames [10] (0: only the
                                           latest), so a changed passage re-bakes from the
                                           checkpoint before it (cache.py)
      },
      "backend": "",                       where it computes: 'auto', 'gpu', 'cpu' ['': HAPTICFLUID_BACKEND
                                           or auto]; `bake --backend` overrides it
      "device": ""                         GL device ('' auto, 'software', or an EGL index)
    }

Frame f's file holds the state at frame f: the fluid starts at rest at frame start - 1 and each
frame advances one frame time (1 / fps) in its substeps, the probe following the keys.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

import hapticfluid as hf
from hapticfluid import FluidSettings, InvalidArgumentError, assembly
from hapticfluid.bake.trajectory import Trajectory, quat_to_matrix

GRID_NAMES = ("density", "velocity", "pressure")
CHECKPOINT_EVERY = 10  # frames between kept checkpoints: at most 9 frames replayed before a change
COMPRESSIONS = ("blosc", "zip", "none")
# The fluid settings a scene file may set, with the engine's defaults (hapticfluid.FluidSettings):
# enums by their names, vectors as tuples, so the dict is what the JSON holds.
FLUID_KEYS = ("fluid_density", "gravity", "open_top", "advection", "vorticity", "smoke_weight", "heat_buoyancy",
              "smoke_dissipation", "heat_dissipation", "pressure_iterations", "pressure_solver", "pressure_tolerance")


def _json_value(value: Any) -> Any:
    """An engine setting as the JSON holds it: an enum by its name, a float32 by its shortest
    decimal (1.2, not 1.2000000476837158), a vector as a tuple of those."""
    if isinstance(value, tuple):
        return tuple(_json_value(v) for v in value)
    if isinstance(value, float):
        return float(f"{value:.7g}")
    return getattr(value, "name", value)


FLUID_DEFAULTS: Dict[str, Any] = {k: _json_value(getattr(FluidSettings(), k)) for k in FLUID_KEYS}

# What shapes the frames: the fingerprint's entries (BakeScene.fingerprint, which a resume must
# match; grid_resolution is derived from two of them), each with the scene key it comes from. The
# list of what makes a cache stale: the add-on reads it too (cache_inputs), so its "cache out of
# date" names what the re-bake plan compares. frames.end, cache.directory, cache.checkpoint_every
# backend and device shape no frame (the backends agree within float rounding).
CACHE_INPUTS: Dict[str, str] = {
    "domain_origin": "domain.origin", "domain_size": "domain.size", "resolution": "resolution",
    "frame_start": "frames.start", "fps": "frames.fps", "fluid": "fluid", "source": "source", "probe": "probe",
    "substeps": "substeps", "cfl": "cfl", "max_substeps": "max_substeps", "grids": "cache.grids",
    "compression": "cache.compression", "half_float": "cache.half_float", "tolerance": "cache.tolerance",
}


def cache_inputs(data: Dict[str, Any]) -> Dict[str, Any]:
    """The values of a scene dict (the JSON form, unchecked; it may stand in for the probe and
    the source with what a host can read at once) at CACHE_INPUTS' keys, by their fingerprint
    names; cache.settings_differences names what differs between two ('fluid.vorticity')."""
    out: Dict[str, Any] = {}
    for name, path in CACHE_INPUTS.items():
        value: Any = data
        for part in path.split("."):
            value = value.get(part) if isinstance(value, dict) else None
        out[name] = value
    return out


def _err(where: str, message: str) -> InvalidArgumentError:
    return InvalidArgumentError(f"scene {where}: {message}")


def _number(where: str, value: Any, positive: bool = False, minimum: Optional[float] = None) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _err(where, f"expected a number, got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise _err(where, f"must be finite, got {value!r}")
    if positive and v <= 0.0:
        raise _err(where, f"must be > 0, got {value!r}")
    if minimum is not None and v < minimum:
        raise _err(where, f"must be >= {minimum:g}, got {value!r}")
    return v


def _integer(where: str, value: Any, minimum: Optional[int] = None) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise _err(where, f"expected an integer, got {value!r}")
    if minimum is not None and value < minimum:
        raise _err(where, f"must be >= {minimum}, got {value}")
    return int(value)


def _resolution(where: str, value: Any) -> int:
    """Cells along the longest edge: an integer >= 8 that the engine's 32-bit cell counts hold
    (the engine itself refuses what a GPU cannot take, with its own message)."""
    n = _integer(where, value, 8)
    if n >= 2 ** 31:
        raise _err(where, f"must be less than 2^31 (the engine counts cells in 32-bit integers), got {n}")
    return n


def _vec(where: str, value: Any, n: int = 3) -> Tuple[float, ...]:
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence) or len(value) != n:
        raise _err(where, f"expected {n} numbers, got {value!r}")
    return tuple(_number(f"{where}[{i}]", v) for i, v in enumerate(value))


def _table(where: str, value: Any, allowed: Sequence[str]) -> Dict[str, Any]:
    if not isinstance(value, dict):
        raise _err(where, f"expected an object, got {value!r}")
    unknown = sorted(set(value) - set(allowed))
    if unknown:
        raise _err(where, f"unknown key(s) {unknown}; allowed: {sorted(allowed)}")
    return value


@dataclass(frozen=True)
class SmokeSource:
    centre: Optional[Tuple[float, float, float]] = None  # m (sphere)
    radius: Optional[float] = None  # m (sphere)
    density: float = 1.0  # concentration ("hold") or per second ("rate")
    temperature: float = 0.0  # K above ambient ("hold") or K/s ("rate")
    shape: str = "sphere"  # "sphere" or "mesh"
    emission: str = "hold"  # "hold" or "rate"
    trajectory: Optional[Trajectory] = None  # keyed transforms (mesh)
    vertices: Optional[np.ndarray] = None  # (N, 3) float64, local frame, m (mesh)
    triangles: Optional[np.ndarray] = None  # (M, 3) int64 (mesh)

    def fingerprint(self) -> Dict[str, Any]:
        """What the frames depend on; a sphere's has its original keys (old checkpoints resume)."""
        if self.shape == "sphere":
            d: Dict[str, Any] = {"centre": list(self.centre), "radius": self.radius}
        else:
            assert self.trajectory is not None
            d = {"shape": "mesh", "keys": [[f, m.tolist()] for f, m in self.trajectory.keys],
                 "vertex_count": len(self.vertices), "triangle_count": len(self.triangles),
                 "mesh_sha256": _mesh_digest(self.vertices, self.triangles)}
        d.update(density=self.density, temperature=self.temperature)
        if self.emission != "hold":
            d["emission"] = self.emission
        return d


def _mesh_digest(vertices: np.ndarray, triangles: np.ndarray) -> str:
    import hashlib

    h = hashlib.sha256(np.ascontiguousarray(vertices, dtype=np.float64).tobytes())
    h.update(np.ascontiguousarray(triangles, dtype=np.int64).tobytes())
    return h.hexdigest()


@dataclass(frozen=True)
class ProbeSpec:
    shape: str  # "sphere" or "mesh"
    radius: float  # m at scale 1 (sphere); the local bounding radius about the origin (mesh)
    trajectory: Trajectory
    vertices: Optional[np.ndarray] = None  # (N, 3) float64, local frame, m (mesh)
    triangles: Optional[np.ndarray] = None  # (M, 3) int64 (mesh)

    def mesh_digest(self) -> Optional[str]:
        if self.vertices is None:
            return None
        return _mesh_digest(self.vertices, self.triangles)


@dataclass(frozen=True)
class BakeScene:
    """A validated scene: see the module docstring for the JSON form."""

    domain_origin: Tuple[float, float, float]
    domain_size: Tuple[float, float, float]
    resolution: int  # cells along the longest edge
    frame_start: int
    frame_end: int
    fps: float
    cache_dir: Path
    fluid: Dict[str, Any] = field(default_factory=lambda: dict(FLUID_DEFAULTS))
    source: Optional[SmokeSource] = None
    probe: Optional[ProbeSpec] = None
    substeps: Any = 2  # int, or "adaptive"
    cfl: float = 1.0
    max_substeps: int = 16
    grids: Tuple[str, ...] = ("density",)
    compression: str = "blosc"
    half_float: bool = False
    tolerance: float = 1e-4
    backend: str = ""
    device: str = ""
    checkpoint_every: int = CHECKPOINT_EVERY  # frames between kept checkpoints (0: only the latest)

    # ---- derived grid ------------------------------------------------------------------
    @property
    def cell_size(self) -> float:
        return assembly.grid(self.domain_size, self.resolution).cell_size

    @property
    def grid_resolution(self) -> Tuple[int, int, int]:
        return assembly.grid(self.domain_size, self.resolution).cells

    @property
    def grid_size(self) -> Tuple[float, float, float]:
        """The simulated box's edges (m): whole cells, so possibly a hair off domain_size."""
        return assembly.grid(self.domain_size, self.resolution).size

    @property
    def checkpoint_bytes(self) -> int:
        """Bytes of one checkpoint at this resolution (cache.checkpoint_bytes)."""
        from hapticfluid.bake.cache import checkpoint_bytes

        return checkpoint_bytes(self.grid_resolution)

    @property
    def frame_count(self) -> int:
        return self.frame_end - self.frame_start + 1

    @property
    def frame_dt(self) -> float:
        return 1.0 / self.fps

    def with_resolution(self, resolution: int) -> "BakeScene":
        scene = replace(self, resolution=_resolution("resolution", resolution))
        scene.check_probe_path()
        return scene

    # ---- what a resume must match ------------------------------------------------------
    def fingerprint(self) -> Dict[str, Any]:
        """Everything that shapes the frames (not where they go), CACHE_INPUTS' entries: a resume
        must match it."""
        probe = None
        if self.probe is not None:
            probe = {"shape": self.probe.shape, "radius": self.probe.radius,
                     "keys": [[f, m.tolist()] for f, m in self.probe.trajectory.keys]}
            if self.probe.shape == "mesh":  # the mesh by its digest: the manifest stays small
                probe.update(vertex_count=len(self.probe.vertices), triangle_count=len(self.probe.triangles),
                             mesh_sha256=self.probe.mesh_digest())
        parts = {"fluid": {k: (list(v) if isinstance(v, tuple) else v) for k, v in self.fluid.items()},
                 "source": None if self.source is None else self.source.fingerprint(), "probe": probe}
        out = {name: parts[name] if name in parts else getattr(self, name) for name in CACHE_INPUTS}
        out["grid_resolution"] = self.grid_resolution
        return {k: list(v) if isinstance(v, tuple) else v for k, v in out.items()}

    def global_fingerprint(self) -> Dict[str, Any]:
        """The fingerprint without the keyed poses: what every frame depends on, so a change
        here invalidates every frame (the keys are compared frame by frame: frame_inputs)."""
        from hapticfluid.bake.cache import without_keys

        return without_keys(self.fingerprint())

    def frame_inputs(self, frame: int) -> Dict[str, str]:
        """What frame ``frame`` consumes beyond the global settings, as digests: the keys the
        probe's (and a mesh source's) poses during the frame (frames frame-1 .. frame) are
        interpolated from. Equal digests give the same substep poses to the bit."""
        out = {}
        for name, part in (("probe", self.probe), ("source", self.source)):
            trajectory = getattr(part, "trajectory", None) if part is not None else None
            if trajectory is not None:
                out[name] = trajectory.digest_between(frame - 1, frame)[:32]
        return out

    def to_dict(self) -> Dict[str, Any]:
        """The scene in its JSON form (keys as matrices), for the manifest."""
        d = self.fingerprint()
        d["frame_end"] = self.frame_end
        d["cache_dir"] = str(self.cache_dir)
        d["backend"] = self.backend
        d["device"] = self.device
        d["checkpoint_every"] = self.checkpoint_every
        return d

    # ---- checks ------------------------------------------------------------------------
    def probe_spheres(self) -> List[Tuple[float, np.ndarray, float]]:
        """(frame, centre m, radius m) of the sphere probe at each of its keys."""
        if self.probe is None or self.probe.shape != "sphere":
            return []
        return [(float(f), p.translation, self.probe.radius * float(np.max(np.abs(p.scale))))
                for f, p in zip(self.probe.trajectory.frames, self.probe.trajectory.poses)]

    def check_probe_path(self) -> None:
        """The engine's checks of the probe's place (hapticfluid.check_sphere_probe,
        check_mesh_probe: one cell of fluid from every wall, a sphere at least a cell wide) at
        every key, hence everywhere in between for a sphere (positions and radii interpolate
        linearly and the allowed set is convex); the bake hands the engine every substep's pose
        before its first step as well (driver.check_trajectory)."""
        if self.probe is None:
            return
        grid = assembly.fluid_settings(self.domain_origin, self.domain_size, self.resolution)
        # Coordinates near 1e308 overflow in float32 and in the scale (the engine refuses inf all
        # the same): no numpy RuntimeWarning on top of its error.
        if self.probe.shape == "mesh":
            with np.errstate(over="ignore", invalid="ignore"):
                vertices = np.asarray(self.probe.vertices, dtype=np.float32)
            triangles = np.asarray(self.probe.triangles, dtype=np.int32)
            checks = [(frame, lambda m=matrix: hf.check_mesh_probe(grid, vertices, triangles, m))
                      for frame, matrix in self.probe.trajectory.keys]
        else:
            with np.errstate(over="ignore", invalid="ignore"):
                spheres = self.probe_spheres()
            checks = [(frame, lambda c=centre, r=radius: hf.check_sphere_probe(grid, tuple(map(float, c)), r))
                      for frame, centre, radius in spheres]
        for frame, check in checks:
            try:
                check()
            except InvalidArgumentError as exc:
                raise InvalidArgumentError(f"the probe at frame {frame:g} (a key) at resolution {self.resolution}: "
                                           f"{exc}") from None


def _key_matrix(where: str, key: Dict[str, Any]) -> np.ndarray:
    _table(where, key, ("frame", "matrix", "location", "rotation", "scale"))
    if "matrix" in key:
        if any(k in key for k in ("location", "rotation", "scale")):
            raise _err(where, "give either 'matrix' or 'location' (+ 'rotation', 'scale'), not both")
        rows = key["matrix"]
        if not isinstance(rows, Sequence) or len(rows) != 4:
            raise _err(f"{where}.matrix", "expected 4 rows of 4 numbers")
        return np.array([_vec(f"{where}.matrix[{i}]", r, 4) for i, r in enumerate(rows)])
    if "location" not in key:
        raise _err(where, "needs 'location' (m) or 'matrix'")
    m = np.eye(4)
    m[:3, 3] = _vec(f"{where}.location", key["location"])
    q = np.array(_vec(f"{where}.rotation", key.get("rotation", (1.0, 0.0, 0.0, 0.0)), 4))
    norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > 1e-3:
        raise _err(f"{where}.rotation", f"must be a unit quaternion (w, x, y, z), its length is {norm:.6g}")
    scale = key.get("scale", 1.0)
    s = (np.full(3, _number(f"{where}.scale", scale, positive=True)) if not isinstance(scale, Sequence)
         else np.array(_vec(f"{where}.scale", scale)))
    if np.any(s <= 0):
        raise _err(f"{where}.scale", f"must be > 0, got {s.tolist()}")
    m[:3, :3] = quat_to_matrix(q / norm) * s[np.newaxis, :]
    return m


def _mesh_arrays(where: str, p: Dict[str, Any]) -> Tuple[np.ndarray, np.ndarray]:
    """A mesh's 'vertices' (m) and 'triangles' from table ``where`` (probe or source), checked
    for shape, finiteness and index range (the engine checks that it is closed)."""
    try:
        vertices = np.asarray(p.get("vertices"), dtype=np.float64)
        raw_triangles = np.asarray(p.get("triangles"))
    except (TypeError, ValueError):
        raise _err(where, "'vertices' must be [[x, y, z], ...] (m) and 'triangles' [[i, j, k], ...]") \
            from None
    listed_bool = isinstance(p.get("triangles"), (list, tuple)) and any(
        isinstance(i, bool) for row in p["triangles"] if isinstance(row, (list, tuple)) for i in row)
    if listed_bool or (raw_triangles.size and not np.issubdtype(raw_triangles.dtype, np.integer)):
        # a cast would truncate 2.5 to 2 (or true to 1) without a word
        raise _err(f"{where}.triangles", "vertex indices must be integers (no fractions, no true/false)")
    triangles = raw_triangles.astype(np.int64)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or len(vertices) < 4 or not np.all(np.isfinite(vertices)):
        raise _err(f"{where}.vertices", f"needs at least 4 finite [x, y, z] rows, got shape {vertices.shape}")
    if triangles.ndim != 2 or triangles.shape[1] != 3 or len(triangles) < 4:
        raise _err(f"{where}.triangles", f"needs at least 4 [i, j, k] rows, got shape {triangles.shape}")
    if triangles.min() < 0 or triangles.max() >= len(vertices):
        raise _err(f"{where}.triangles", f"indices must be in 0 .. {len(vertices) - 1}")
    return vertices, triangles


def _trajectory(where: str, keys: Any) -> Trajectory:
    if not isinstance(keys, list) or not keys:
        raise _err(where, "needs a non-empty list of {frame, location | matrix}")
    items = []
    for i, key in enumerate(keys):
        at = f"{where}[{i}]"
        if not isinstance(key, dict) or "frame" not in key:
            raise _err(at, "needs 'frame'")
        items.append((_number(f"{at}.frame", key["frame"]), _key_matrix(at, key)))
    return Trajectory(items)


def _source(value: Any) -> SmokeSource:
    s = _table("source", value, ("shape", "centre", "radius", "density", "temperature", "emission", "keys",
                                 "vertices", "triangles"))
    shape = s.get("shape", "sphere")
    if shape not in ("sphere", "mesh"):
        raise _err("source.shape", f"must be 'sphere' or 'mesh', got {shape!r}")
    ignored = {"sphere": ("vertices", "triangles", "keys"), "mesh": ("centre", "radius")}[shape]
    stray = sorted(k for k in ignored if k in s)
    if stray:  # it would be ignored: say so rather than bake something other than meant
        raise _err("source", f"a {shape} source takes no {stray}; remove {'them' if len(stray) > 1 else 'it'} "
                             f"or set 'shape' to {'mesh' if shape == 'sphere' else 'sphere'}")
    emission = s.get("emission", "hold")
    if emission not in ("hold", "rate"):
        raise _err("source.emission", f"must be 'hold' or 'rate', got {emission!r}")
    values = dict(density=_number("source.density", s.get("density", 1.0), minimum=0.0),
                  temperature=_number("source.temperature", s.get("temperature", 0.0), minimum=0.0),
                  emission=emission)
    if shape == "sphere":
        if "centre" not in s or "radius" not in s:
            raise _err("source", "needs 'centre' (m) and 'radius' (m)")
        return SmokeSource(centre=_vec("source.centre", s["centre"]),
                           radius=_number("source.radius", s["radius"], positive=True), **values)
    vertices, triangles = _mesh_arrays("source", s)
    return SmokeSource(shape="mesh", vertices=vertices, triangles=triangles,
                       trajectory=_trajectory("source.keys", s.get("keys")), **values)


def _fluid(value: Any) -> Dict[str, Any]:
    """The fluid's settings: FLUID_DEFAULTS with those given, each checked by the engine's
    FluidSettings (its types and ranges, FluidSettings.limits()) and refused with its message
    under the key's name. Kept as given (numbers as floats, vectors as tuples, enums by name)."""
    fluid = dict(FLUID_DEFAULTS)
    settings = FluidSettings()
    for k, v in _table("fluid", value, FLUID_KEYS).items():
        try:
            setattr(settings, k, v)
        except (TypeError, InvalidArgumentError) as exc:
            raise _err(f"fluid.{k}", str(exc)) from None
        default = FLUID_DEFAULTS[k]
        fluid[k] = (tuple(float(x) for x in v) if isinstance(default, tuple) else _json_value(v)
                    if isinstance(default, str) else type(default)(v))
    return fluid


def _check_step_range(fps: float, substeps: Any, max_substeps: int) -> None:
    """The simulation steps (frame time / substeps) must be ones the engine takes; found here,
    not at the first step of a bake that has already freed the old one."""
    import hapticfluid as hf

    lo_n, hi_n = (1, max_substeps) if substeps == "adaptive" else (substeps, substeps)
    longest, shortest = 1.0 / (fps * lo_n), 1.0 / (fps * hi_n)
    what = "adaptive substeps (1 .. max_substeps)" if substeps == "adaptive" else f"{substeps} substeps"
    if longest > hf.MAX_TIME_STEP_S:
        raise _err("frames.fps", f"{fps:g} fps with {what} gives steps of up to {longest:.4g} s; the engine "
                                 f"steps at most {hf.MAX_TIME_STEP_S:g} s: raise fps or the substeps")
    if shortest < hf.MIN_TIME_STEP_S:
        raise _err("frames.fps", f"{fps:g} fps with {what} gives steps of {shortest:.3g} s; the engine "
                                 f"steps at least {hf.MIN_TIME_STEP_S:g} s: lower fps, substeps or max_substeps")


def scene_from_dict(data: Dict[str, Any], base_dir: "str | os.PathLike" = ".") -> BakeScene:
    """Validate a scene dict (the JSON form) into a BakeScene; relative cache paths resolve
    against ``base_dir``. Raises InvalidArgumentError naming the key to fix."""
    top = _table("", data, ("domain", "resolution", "fluid", "source", "probe", "frames", "substeps",
                            "cfl", "max_substeps", "cache", "backend", "device", "comment"))
    for key in ("domain", "resolution", "frames", "cache"):
        if key not in top:
            raise _err(key, "is required")
    dom = _table("domain", top["domain"], ("origin", "size"))
    origin = _vec("domain.origin", dom.get("origin", (0.0, 0.0, 0.0)))
    size = _vec("domain.size", dom.get("size"))
    if min(size) <= 0:
        raise _err("domain.size", f"edges must be > 0 m, got {list(size)}")
    resolution = _resolution("resolution", top["resolution"])

    fluid = _fluid(top.get("fluid", {}))

    source = None if top.get("source") is None else _source(top["source"])

    probe = None
    if top.get("probe") is not None:
        p = _table("probe", top["probe"], ("shape", "radius", "keys", "vertices", "triangles"))
        shape = p.get("shape", "sphere")
        if shape not in ("sphere", "mesh"):  # before any use: a list or an object is no shape name
            raise _err("probe.shape", f"must be 'sphere' or 'mesh', got {shape!r}")
        vertices = triangles = None
        ignored = {"sphere": ("vertices", "triangles"), "mesh": ("radius",)}.get(shape, ())
        stray = sorted(k for k in ignored if k in p)
        if stray:  # it would be ignored: say so rather than bake something other than meant
            raise _err("probe", f"a {shape} probe takes no {stray}; remove {'them' if len(stray) > 1 else 'it'} "
                                f"or set 'shape' to {'mesh' if shape == 'sphere' else 'sphere'}")
        if shape == "sphere":
            radius = _number("probe.radius", p.get("radius"), positive=True)
        elif shape == "mesh":
            vertices, triangles = _mesh_arrays("probe", p)
            with np.errstate(over="ignore"):  # 1e308 coordinates: an inf radius, refused below
                radius = float(np.linalg.norm(vertices, axis=1).max())
        else:
            raise _err("probe.shape", f"must be 'sphere' or 'mesh', got {shape!r}")
        probe = ProbeSpec(shape=shape, radius=radius, trajectory=_trajectory("probe.keys", p.get("keys")),
                          vertices=vertices, triangles=triangles)

    fr = _table("frames", top["frames"], ("start", "end", "fps"))
    start = _integer("frames.start", fr.get("start", 1), 0)
    end = _integer("frames.end", fr.get("end"), start)
    if end > 9999:
        raise _err("frames.end", f"file names have 4 digits: at most 9999, got {end}")
    fps = _number("frames.fps", fr.get("fps", 24), positive=True)

    substeps = top.get("substeps", 2)
    if substeps != "adaptive":
        substeps = _integer("substeps", substeps, 1)
    cfl = _number("cfl", top.get("cfl", 1.0), positive=True)
    max_substeps = _integer("max_substeps", top.get("max_substeps", 16), 1)
    _check_step_range(fps, substeps, max_substeps)

    c = _table("cache", top["cache"], ("directory", "grids", "compression", "half_float", "tolerance",
                                       "checkpoint_every"))
    directory = c.get("directory")
    if not isinstance(directory, str) or not directory or "\0" in directory:
        raise _err("cache.directory", f"must be a folder path (no NUL character), got {directory!r}")
    try:
        cache_dir = Path(directory).expanduser()
    except RuntimeError:  # "~name" for a user this machine does not know (or no home at all)
        raise _err("cache.directory", f"starts with '~' but names no home folder on this machine, got {directory!r}; "
                                      "give the folder's full path") from None
    if not cache_dir.is_absolute():
        cache_dir = Path(base_dir) / cache_dir
    grids = c.get("grids", ["density"])
    if not isinstance(grids, list) or any(g not in GRID_NAMES for g in grids):
        raise _err("cache.grids", f"must be a list of {list(GRID_NAMES)}, got {grids!r}")
    grids = tuple(g for g in GRID_NAMES if g == "density" or g in grids)
    compression = c.get("compression", "blosc")
    if compression not in COMPRESSIONS:
        raise _err("cache.compression", f"must be one of {list(COMPRESSIONS)}, got {compression!r}")
    half = c.get("half_float", False)
    if not isinstance(half, bool):
        raise _err("cache.half_float", f"expected true or false, got {half!r}")
    tolerance = _number("cache.tolerance", c.get("tolerance", 1e-4), minimum=0.0)
    checkpoint_every = _integer("cache.checkpoint_every", c.get("checkpoint_every", CHECKPOINT_EVERY), 0)
    device = top.get("device", "")
    if not isinstance(device, str):
        raise _err("device", f"expected a string, got {device!r}")
    backend = top.get("backend", "")
    if not isinstance(backend, str) or backend not in ("",) + tuple(hf.BACKENDS):
        raise _err("backend", f"must be one of {['', *hf.BACKENDS]}, got {backend!r}")

    scene = BakeScene(domain_origin=origin, domain_size=size, resolution=resolution, frame_start=start,
                      frame_end=end, fps=fps, cache_dir=cache_dir, fluid=fluid, source=source, probe=probe,
                      substeps=substeps, cfl=cfl, max_substeps=max_substeps, grids=grids,
                      compression=compression, half_float=half, tolerance=tolerance, backend=backend, device=device,
                      checkpoint_every=checkpoint_every)
    scene.check_probe_path()
    return scene


def load_scene(path: "str | os.PathLike") -> BakeScene:
    """Read and validate a scene JSON file (relative cache paths are relative to its folder)."""
    p = Path(path)
    if "\0" in os.fspath(path):
        raise InvalidArgumentError(f"scene file path {os.fspath(path)!r} holds a NUL character; give a real path")
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise InvalidArgumentError(f"cannot read the scene file '{p}': {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise InvalidArgumentError(f"scene file '{p}' is not UTF-8 text (byte {exc.start}); save it as UTF-8 "
                                   "JSON") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InvalidArgumentError(f"scene file '{p}' is not valid JSON: {exc}") from None
    except RecursionError:
        raise InvalidArgumentError(f"scene file '{p}' nests JSON too deeply to read; a scene is a few levels "
                                   "deep") from None
    except ValueError as exc:  # e.g. an integer of more than 4300 digits
        raise InvalidArgumentError(f"scene file '{p}' cannot be read as JSON: {exc}") from None
    return scene_from_dict(data, base_dir=p.resolve().parent)
