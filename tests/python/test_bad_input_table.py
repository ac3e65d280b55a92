# SPDX-License-Identifier: GPL-3.0-or-later
"""The bad-input table: every public entry point gets every bad value of its argument's type.

Each row is (entry point, argument name, a call that passes the bad value there). Each bad value
must raise the documented error type (InvalidArgumentError, a ValueError, for a bad value;
TypeError or InvalidArgumentError for a wrong type; MemoryError for an allocation that cannot
be made) and the message must name the argument, so the user knows which one to fix.
Rows that the code does not meet yet are xfail(strict=True) with the reason (so a fix shows up).
"""

import json
import math

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid.bake.scene import load_scene, scene_from_dict
from hapticfluid.cli import build_parser

# ----------------------------------------------------------------------------- bad values per type

NAN, INF = math.nan, math.inf
BAD_POSITIVE_FLOAT = {"nan": NAN, "inf": INF, "-inf": -INF, "negative": -1.0, "zero": 0.0,
                      "str": "1.0", "none": None, "list": [1.0]}
BAD_NONNEG_FLOAT = {"nan": NAN, "inf": INF, "-inf": -INF, "negative": -1.0, "str": "1.0", "none": None}
BAD_FINITE_FLOAT = {"nan": NAN, "inf": INF, "-inf": -INF, "str": "x", "none": None}
BAD_VEC3 = {"nan": (NAN, 0.0, 0.0), "inf": (0.0, INF, 0.0), "short": (0.0, 0.0), "long": (0.0, 0.0, 0.0, 0.0),
            "str": "abc", "none": None, "nested": ((0.0,), (0.0,), (0.0,))}
BAD_MATRIX = {"nan": np.full((4, 4), NAN), "shape3x3": np.eye(3), "str": "eye", "flat": list(range(16)),
              "singular": np.zeros((4, 4))}
BAD_STRING_CHOICE = {"unknown": "no_such_choice", "empty": "", "nul": "jacobi\0", "int": 3, "none": None}

# Values that are bad for an argument that must be > 0 (every kind above).
SIM_POSITIVE = ["fluid_density"]
SIM_NONNEG = ["smoke_dissipation", "heat_dissipation", "pressure_tolerance", "vorticity"]
SIM_FINITE = ["smoke_weight", "heat_buoyancy"]
SIM_CHOICE = ["advection", "pressure_solver"]
HUGE = 1e300


# The engine's messages name an argument in words ("fluid density", "time step"), the bindings
# by keyword; either names it. The words each argument goes by, besides its keyword:
ALIASES = {"dt": ["time step"], "vertices": ["vertex"], "triangles": ["triangle"],
           "times": ["waypoint"], "positions": ["waypoint"]}

# Rows the code does not meet yet: test id -> why. Each is xfail(strict=True), so a fix shows.
KNOWN_GAPS: dict = {}


@pytest.fixture(autouse=True)
def _known_gap(request):
    reason = KNOWN_GAPS.get(request.node.name)
    if reason:
        request.applymarker(pytest.mark.xfail(strict=True, reason=reason))


def _expect(call, name, types=(ValueError, TypeError)):
    with pytest.raises(types) as info:
        call()
    text = str(info.value)
    words = [name, name.replace("_", " ")] + ALIASES.get(name, [])
    assert any(w in text for w in words), f"the message does not name {name!r}: {text}"
    return info.value


def _cases(names, table):
    return [pytest.param(n, k, v, id=f"{n}-{k}") for n in names for k, v in table.items()]


def _kinds(table):
    return [pytest.param(k, v, id=k) for k, v in table.items()]


# ----------------------------------------------------------------------------- Simulation constructor

@pytest.mark.parametrize("name,kind,value", _cases(SIM_POSITIVE, BAD_POSITIVE_FLOAT)
                         + _cases(SIM_NONNEG, BAD_NONNEG_FLOAT) + _cases(SIM_FINITE, BAD_FINITE_FLOAT)
                         + _cases(SIM_CHOICE, BAD_STRING_CHOICE)
                         + _cases(["gravity", "domain_size", "origin"], BAD_VEC3))
def test_simulation_constructor(name, kind, value):
    _expect(lambda: hf.Simulation(resolution=(8, 8, 8), **{name: value}), name)


@pytest.mark.parametrize("kind,value", [("zero", (0, 8, 8)), ("negative", (-8, 8, 8)), ("short", (8, 8)),
                                        ("float", (8.5, 8, 8)), ("str", "888"), ("none", None),
                                        ("huge", (1 << 20, 1 << 20, 1 << 20))])
def test_simulation_resolution(kind, value):
    _expect(lambda: hf.Simulation(resolution=value), "resolution", (ValueError, TypeError, MemoryError))


@pytest.mark.parametrize("value", [0, -1, 1 << 40, "many", None, 2.5])
def test_simulation_pressure_iterations(value):
    _expect(lambda: hf.Simulation(resolution=(8, 8, 8), pressure_iterations=value), "pressure_iterations")


# ----------------------------------------------------------------------------- setters and methods

@pytest.mark.parametrize("name,kind,value", _cases(SIM_POSITIVE, BAD_POSITIVE_FLOAT)
                         + _cases(SIM_NONNEG, BAD_NONNEG_FLOAT) + _cases(SIM_FINITE, BAD_FINITE_FLOAT)
                         + _cases(SIM_CHOICE, BAD_STRING_CHOICE) + _cases(["gravity"], BAD_VEC3))
def test_simulation_setters(small_sim, name, kind, value):
    before = getattr(small_sim, name)
    _expect(lambda: setattr(small_sim, name, value), name)
    assert getattr(small_sim, name) == before  # a refused value changes nothing


@pytest.mark.parametrize("kind,value", list(BAD_POSITIVE_FLOAT.items()) + [("huge", HUGE)])
def test_step_dt(small_sim, kind, value):
    _expect(lambda: small_sim.step(value), "dt")


@pytest.mark.parametrize("kind,value", _kinds(BAD_POSITIVE_FLOAT))
def test_set_probe_radius(small_sim, kind, value):
    _expect(lambda: small_sim.set_probe((0.5, 0.5, 0.5), value), "radius")


@pytest.mark.parametrize("arg,kind,value", [(a, k, v) for a in ("centre", "velocity", "angular_velocity")
                                            for k, v in BAD_VEC3.items()])
def test_set_probe_vectors(small_sim, arg, kind, value):
    kwargs = {"centre": (0.5, 0.5, 0.5), "radius": 0.1, arg: value}
    _expect(lambda: small_sim.set_probe(**kwargs), arg)


@pytest.mark.parametrize("kind,value", _kinds(BAD_POSITIVE_FLOAT))
def test_set_smoke_source_radius(small_sim, kind, value):
    _expect(lambda: small_sim.set_smoke_source((0.5, 0.5, 0.5), value), "radius")


@pytest.mark.parametrize("arg,kind,value", [("density", k, v) for k, v in BAD_FINITE_FLOAT.items()]
                         + [("temperature", k, v) for k, v in BAD_FINITE_FLOAT.items()]
                         + [("centre", k, v) for k, v in BAD_VEC3.items()])
def test_set_smoke_source_values(small_sim, arg, kind, value):
    kwargs = {"centre": (0.5, 0.5, 0.5), "radius": 0.1, arg: value}
    _expect(lambda: small_sim.set_smoke_source(**kwargs), arg)


def _tetra():
    v = np.array([[0.4, 0.4, 0.4], [0.6, 0.4, 0.4], [0.4, 0.6, 0.4], [0.4, 0.4, 0.6]])
    t = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    return v, t


BAD_VERTICES = {"nan": np.full((4, 3), NAN), "shape": np.zeros((4, 2)), "1d": np.zeros(12), "str": "verts",
                "none": None, "empty": np.zeros((0, 3)), "object": np.array([[object()] * 3] * 4, dtype=object)}
BAD_TRIANGLES = {"out_of_range": np.array([[0, 1, 9]] * 4), "negative": np.array([[0, 1, -1]] * 4),
                 "float": np.array([[0.0, 1.5, 2.0]] * 4), "shape": np.zeros((4, 2), int), "str": "tris",
                 "none": None, "empty": np.zeros((0, 3), int)}


# The two setters that take a closed mesh check vertices, triangles and transform alike, and
# each its own keyword arguments.
MESH_SETTER_ARGS = {
    "set_mesh_probe": [(a, k, v) for a in ("velocity", "angular_velocity", "torque_centre")
                       for k, v in BAD_VEC3.items() if k != "none"],
    "set_smoke_source_mesh": [(a, k, v) for a in ("density", "temperature") for k, v in BAD_NONNEG_FLOAT.items()]
                             + [("emission", k, v) for k, v in BAD_STRING_CHOICE.items()],
}
MESH_ARGS = ([("vertices", k, v) for k, v in BAD_VERTICES.items()]
             + [("triangles", k, v) for k, v in BAD_TRIANGLES.items()]
             + [("transform", k, v) for k, v in BAD_MATRIX.items()])


@pytest.mark.parametrize("setter,arg,kind,value", [pytest.param(s, a, k, v, id=f"{s}-{a}-{k}")
                                                   for s, extra in MESH_SETTER_ARGS.items()
                                                   for a, k, v in MESH_ARGS + extra])
def test_mesh_setters(small_sim, setter, arg, kind, value):
    v, t = _tetra()
    positional = {"vertices": v, "triangles": t}
    keywords = {}
    (positional if arg in positional else keywords)[arg] = value
    _expect(lambda: getattr(small_sim, setter)(positional["vertices"], positional["triangles"], **keywords), arg)


@pytest.mark.parametrize("kind,value", [(k, v) for k, v in BAD_MATRIX.items() if k != "singular"])
def test_set_probe_pose_transform(small_sim, kind, value):
    small_sim.set_probe((0.5, 0.5, 0.5), 0.1)
    try:
        _expect(lambda: small_sim.set_probe_pose(value), "transform")
    finally:
        small_sim.clear_probe()


@pytest.mark.parametrize("arg,kind,value", [(a, k, v) for a in ("velocity", "angular_velocity")
                                            for k, v in BAD_VEC3.items() if k != "none"])
def test_set_probe_pose_vectors(small_sim, arg, kind, value):
    small_sim.set_probe((0.5, 0.5, 0.5), 0.1)
    try:
        _expect(lambda: small_sim.set_probe_pose(np.eye(4), **{arg: value}), arg)
    finally:
        small_sim.clear_probe()


# ----------------------------------------------------------------------------- write_vdb

@pytest.mark.parametrize("kind,value", [("nul", "a\0b.vdb"), ("none", None), ("int", 3),
                                        ("missing_dir", "/nonexistent/dir/x.vdb")])
def test_write_vdb_path(kind, value):
    types = (ValueError, TypeError, hf.HapticFluidError)
    _expect(lambda: hf.write_vdb(value, np.zeros((4, 4, 4), np.float32), 0.1), "path" if kind != "missing_dir"
            else "/nonexistent/dir", types)


@pytest.mark.parametrize("kind,value", _kinds(BAD_POSITIVE_FLOAT))
def test_write_vdb_voxel_size(tmp_path, kind, value):
    _expect(lambda: hf.write_vdb(str(tmp_path / "x.vdb"), np.zeros((4, 4, 4), np.float32), value), "voxel_size")


@pytest.mark.parametrize("kind,value", [("2d", np.zeros((4, 4))), ("str", "dens"), ("none", None),
                                        ("nan", np.full((4, 4, 4), NAN)), ("empty", np.zeros((0, 4, 4)))],
                         ids=["2d", "str", "none", "nan", "empty"])
def test_write_vdb_density(tmp_path, kind, value):
    _expect(lambda: hf.write_vdb(str(tmp_path / "x.vdb"), value, 0.1), "density")


@pytest.mark.parametrize("kind,value", _kinds(BAD_STRING_CHOICE))
def test_write_vdb_compression(tmp_path, kind, value):
    _expect(lambda: hf.write_vdb(str(tmp_path / "x.vdb"), np.zeros((4, 4, 4), np.float32), 0.1,
                                 compression=value), "compression")


@pytest.mark.parametrize("kind,value", _kinds(BAD_NONNEG_FLOAT))
def test_write_vdb_tolerance(tmp_path, kind, value):
    _expect(lambda: hf.write_vdb(str(tmp_path / "x.vdb"), np.zeros((4, 4, 4), np.float32), 0.1,
                                 tolerance=value), "tolerance")


# ----------------------------------------------------------------------------- devices

BAD_MAX_FORCE = dict(BAD_POSITIVE_FLOAT, huge=HUGE)


@pytest.mark.parametrize("factory", ["null_device", "host_device"])
@pytest.mark.parametrize("kind,value", _kinds(BAD_MAX_FORCE))
def test_device_max_force(factory, kind, value):
    _expect(lambda: getattr(hf, factory)(max_force=value), "max_force")


@pytest.mark.parametrize("kind,times,positions,name", [
    ("nan_time", [0.0, NAN], [(0, 0, 0)] * 2, "times"),
    ("decreasing", [1.0, 0.0], [(0, 0, 0)] * 2, "times"),
    ("empty", [], [], "times"),
    ("count_mismatch", [0.0, 1.0], [(0, 0, 0)], "positions"),
    ("nan_position", [0.0, 1.0], [(0, 0, 0), (NAN, 0, 0)], "positions"),
    ("short_position", [0.0, 1.0], [(0, 0), (0, 0)], "positions"),
    ("times_str", "01", [(0, 0, 0)] * 2, "times"),
    ("positions_none", [0.0, 1.0], None, "positions"),
])
def test_scripted_device(kind, times, positions, name):
    _expect(lambda: hf.scripted_device(times, positions), name)


@pytest.mark.parametrize("kind,value", _kinds(BAD_MAX_FORCE))
def test_scripted_device_max_force(kind, value):
    _expect(lambda: hf.scripted_device([0.0, 1.0], [(0, 0, 0)] * 2, max_force=value), "max_force")


@pytest.mark.parametrize("kind,value", [(k, v) for k, v in BAD_VEC3.items()] + [("huge", (1e7, 0.0, 0.0))])
def test_host_device_push_pose(kind, value):
    dev = hf.host_device()
    _expect(lambda: dev.push_pose(value), "position")


@pytest.mark.parametrize("kind,value", [("nan", NAN), ("inf", INF), ("str", "now")])
def test_host_device_push_pose_time(kind, value):
    dev = hf.host_device()
    _expect(lambda: dev.push_pose((0.0, 0.0, 0.0), time=value), "time")


# ----------------------------------------------------------------------------- CSV reader

CSV_BAD = {
    "empty": ("", None),
    "header_only": ("t,x,y,z\n", None),
    "text_value": ("0,0,0,0\n1,abc,0,0\n", None),
    "nan": ("0,0,0,0\n1,nan,0,0\n", None),
    "short_row": ("0,0,0,0\n1,0,0\n", None),
    "decreasing": ("1,0,0,0\n0,0,0,0\n", None),
    "binary": (b"\xff\xfe\x00\x01garbage", None),
    "non_utf8_line": (b"0,0,0,0\r\n1,0.0\xeb\x94,0,0\r\n", None),  # once gave an error with no message
}


@pytest.mark.parametrize("kind", list(CSV_BAD))
def test_scripted_device_from_csv(tmp_path, kind):
    content, _ = CSV_BAD[kind]
    p = tmp_path / "pose.csv"
    p.write_bytes(content if isinstance(content, bytes) else content.encode())
    # The message names the file (the argument is its path).
    _expect(lambda: hf.scripted_device_from_csv(str(p)), "pose.csv")


@pytest.mark.parametrize("kind,value", [("nul", "a\0b.csv"), ("none", None), ("missing", "/nonexistent.csv")])
def test_scripted_device_from_csv_path(kind, value):
    _expect(lambda: hf.scripted_device_from_csv(value), "path" if kind != "missing" else "/nonexistent.csv",
            (ValueError, TypeError, OSError, hf.HapticFluidError))


# ----------------------------------------------------------------------------- HapticSession

SESSION_BAD = [
    # workspace_scale < 0 flips an axis (documented), so "negative" is not a bad value there.
    ("workspace_scale", {k: v for k, v in BAD_POSITIVE_FLOAT.items() if k != "negative"}), ("bandwidth_ratio", BAD_POSITIVE_FLOAT),
    ("slew_rate", BAD_POSITIVE_FLOAT), ("rate", BAD_POSITIVE_FLOAT), ("stale_after", BAD_POSITIVE_FLOAT),
    ("ramp_time", BAD_NONNEG_FLOAT), ("fade_time", BAD_NONNEG_FLOAT), ("sim_dt", BAD_NONNEG_FLOAT),
    ("min_sim_dt", BAD_POSITIVE_FLOAT), ("max_sim_dt", BAD_POSITIVE_FLOAT),
    ("trace_seconds", {k: v for k, v in BAD_POSITIVE_FLOAT.items() if k not in ("str", "none", "list")}), ("passivity_deadband", BAD_NONNEG_FLOAT),
    ("passivity_reserve", BAD_NONNEG_FLOAT), ("passivity_memory", BAD_POSITIVE_FLOAT),
    ("max_force", {k: v for k, v in BAD_POSITIVE_FLOAT.items() if k != "none"}),
    ("force_gain", {k: v for k, v in BAD_FINITE_FLOAT.items() if k != "none"}),
    ("probe_radius", {k: v for k, v in BAD_POSITIVE_FLOAT.items() if k != "none"}),
    ("filter", {k: v for k, v in BAD_STRING_CHOICE.items()}),
    ("workspace_offset", {k: v for k, v in BAD_VEC3.items() if k != "none"}),
    ("guide_stiffness", BAD_NONNEG_FLOAT), ("guide_damping", BAD_NONNEG_FLOAT), ("guide_max_force", BAD_NONNEG_FLOAT),
    ("guide_ramp", BAD_POSITIVE_FLOAT), ("guide_stale", BAD_POSITIVE_FLOAT),
]


@pytest.mark.parametrize("name,kind,value", [pytest.param(n, k, v, id=f"{n}-{k}")
                                             for n, table in SESSION_BAD for k, v in table.items()])
def test_haptic_session_kwargs(small_sim, name, kind, value):
    dev = hf.null_device()
    extra = {"trace": True} if name == "trace_seconds" else {}  # trace_seconds counts only with a trace
    _expect(lambda: hf.HapticSession(small_sim, dev, **extra, **{name: value}), name)


@pytest.mark.parametrize("name,kind,value", [pytest.param(n, k, v, id=f"{n}-{k}") for n in ("position", "velocity")
                                             for k, v in dict(BAD_VEC3, huge=(HUGE, 0.0, 0.0)).items()
                                             if not (n == "position" and k == "huge")])
def test_haptic_session_set_guide(small_sim, name, kind, value):
    session = hf.HapticSession(small_sim, hf.null_device())
    args = {"position": (0.5, 0.5, 0.5), "velocity": (0.0, 0.0, 0.0), name: value}
    _expect(lambda: session.set_guide(**args), name)


def test_haptic_session_simulation_and_device(small_sim):
    _expect(lambda: hf.HapticSession(None, hf.null_device()), "simulation", (TypeError, ValueError))
    _expect(lambda: hf.HapticSession(small_sim, "falcon"), "device", (TypeError, ValueError))


# ----------------------------------------------------------------------------- scene JSON

def _scene():
    return {"domain": {"origin": [0, 0, 0], "size": [1, 1, 1]}, "resolution": 16,
            "frames": {"start": 1, "end": 2, "fps": 24}, "cache": {"directory": "cache"}}


SCENE_BAD = [
    ("domain.size", ["domain", "size"], [[0, 1, 1], [NAN, 1, 1], "big", None, [1, 1]]),
    ("domain.origin", ["domain", "origin"], [[INF, 0, 0], "zero", [0, 0]]),
    ("resolution", ["resolution"], [0, -4, 2.5, "64", None, 1 << 40, True]),
    ("frames.fps", ["frames", "fps"], [0, -24, NAN, "24"]),
    ("frames.end", ["frames", "end"], [10000, "end", 1.5]),
    ("cache.directory", ["cache", "directory"], ["a\0b", 3, None]),
    ("cache.compression", ["cache", "compression"], ["lzma", 1]),
    ("cache.grids", ["cache", "grids"], [["smoke"], "density", 3]),
    ("fluid.advection", ["fluid", "advection"], ["upwind", 0]),
    ("fluid.fluid_density", ["fluid", "fluid_density"], [0, -1, NAN, "1.2"]),
    ("substeps", ["substeps"], [0, -1, "many", 2.5]),
    ("device", ["device"], [3, None]),
]


def _set(d, path, value):
    for key in path[:-1]:
        d = d.setdefault(key, {})
    d[path[-1]] = value


def _mesh_source_scene():
    data = _scene()
    v, t = _tetra()
    data["source"] = {"shape": "mesh", "vertices": v.tolist(), "triangles": t.tolist(),
                      "keys": [{"frame": 1, "location": [0.0, 0.0, 0.0]}], "density": 1.0, "emission": "hold"}
    return data


SOURCE_BAD = [
    ("source.shape", ["source", "shape"], ["cone", 3, None]),
    ("source.emission", ["source", "emission"], ["pulse", 1, None]),
    ("source.vertices", ["source", "vertices"], [[[0, 0, 0]], [[NAN, 0, 0]] * 4, [[0, 0]] * 4]),
    ("source.triangles", ["source", "triangles"], [[[0, 1, 9]] * 4, [[0, 1.5, 2]] * 4, [[0, 1]] * 4]),
    ("source.keys", ["source", "keys"], [[], "frame 1", [{"location": [0, 0, 0]}], None]),
    ("source.density", ["source", "density"], [-1, NAN, "1"]),
    ("source.temperature", ["source", "temperature"], [-1, INF, "hot"]),
    ("source", ["source", "centre"], [[0.5, 0.5, 0.5]]),  # a mesh source takes no centre
]


def test_the_mesh_source_scene_loads(tmp_path):
    assert scene_from_dict(_mesh_source_scene(), tmp_path).source.shape == "mesh"


@pytest.mark.parametrize("base,name,path,value", [pytest.param(base, n, p, v, id=f"{n}-{i}")
                                                  for base, table in ((_scene, SCENE_BAD), (_mesh_source_scene, SOURCE_BAD))
                                                  for n, p, vals in table for i, v in enumerate(vals)])
def test_scene_dict(tmp_path, base, name, path, value):
    data = base()
    _set(data, path, value)
    _expect(lambda: scene_from_dict(data, tmp_path), name, hf.InvalidArgumentError)


@pytest.mark.parametrize("kind,content", [("not_json", b"{"), ("not_utf8", b"\xff\xfe{}"),
                                          ("list", b"[]"), ("deep", b"[" * 100000),
                                          ("missing_key", json.dumps({"resolution": 16}).encode())])
def test_scene_file(tmp_path, kind, content):
    p = tmp_path / "scene.json"
    p.write_bytes(content)
    _expect(lambda: load_scene(p), "scene" if kind != "missing_key" else "domain", hf.InvalidArgumentError)


@pytest.mark.parametrize("kind,value", [("nul", "a\0b.json"), ("missing", "/nonexistent/scene.json")])
def test_scene_file_path(kind, value):
    _expect(lambda: load_scene(value), "scene file", hf.InvalidArgumentError)


# ----------------------------------------------------------------------------- CLIs (argument parsing)

CLI_BAD = [
    ("demo", "--steps", ["0", "-1", "x", "1e3"]),
    ("demo", "--dt", ["0", "-0.1", "nan", "inf", "x"]),
    ("demo", "--resolution", [["0", "8", "8"], ["8", "8", "x"]]),
    ("demo", "--domain", [["0", "1", "1"], ["nan", "1", "1"]]),
    ("demo", "--iterations", ["0", "x"]),
    ("demo", "--solver", ["sor"]),
    ("haptic", "--seconds", ["0", "-1", "nan", "inf", "x"]),
    ("haptic", "--probe-radius", ["0", "nan"]),
    ("haptic", "--fluid-density", ["-1", "inf"]),
    ("haptic", "--gravity", [["nan", "0", "0"]]),
    ("haptic", "--device", ["nothing"]),
    ("bake", "--resolution", ["0", "x", "-8"]),
]


@pytest.mark.parametrize("command,option,value", [pytest.param(c, o, v, id=f"{c}{o}-{i}")
                                                  for c, o, vals in CLI_BAD for i, v in enumerate(vals)])
def test_cli_arguments(capsys, command, option, value):
    argv = [command] + (["scene.json"] if command == "bake" else [])
    argv += [option] + (value if isinstance(value, list) else [value])
    with pytest.raises(SystemExit) as info:
        build_parser().parse_args(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert option in err, err


# ----------------------------------------------------------------------------- mesh smoke source

@pytest.mark.parametrize("kind,value", _kinds(BAD_MATRIX))
def test_set_smoke_source_pose_transform(small_sim, kind, value):
    v, t = _tetra()
    small_sim.set_smoke_source_mesh(v, t)
    try:
        _expect(lambda: small_sim.set_smoke_source_pose(value), "transform")
    finally:
        small_sim.clear_smoke_source()
