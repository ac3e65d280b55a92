# SPDX-License-Identifier: GPL-3.0-or-later
"""Every public function and method of the native module, every typed argument, a value of the
wrong type: the error names the argument and what it must be ("centre must be 3 numbers"), never
pybind11's generic "incompatible function arguments". The bindings name the argument where they
convert it (cpp/python/named_args.h). The table is the shipped stub's signatures, so a new binding
is in it once the stub has it, and a binding the stub lacks fails test_the_table_covers_the_module."""

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import _core

# Native functions the stub leaves out (benchmarks only), in the stub's notation.
UNSTUBBED = {
    "gl_counters": "def gl_counters() -> Dict[str, int]: ...",
    "measure_dispatch_floor": "def measure_dispatch_floor(resolution: Sequence[int], repeats: int = 20, "
                              "device: str = '') -> Dict[str, object]: ...",
}
VEC3 = (0.5, 0.5, 0.5)
# A value of each annotation (Optional[...] stripped) and one of a wrong type.
VALID = {
    "float": 0.5, "int": 1, "bool": False, "str": "x", "bytes": b"x", "Vec3": VEC3, "Sequence[float]": [0.0, 1.0],
    "Sequence[int]": (16, 16, 16), "Sequence[Vec3]": [VEC3, VEC3], "Tuple[float, float, float, float]": (1.0, 0, 0, 0),
    "Sequence[Tuple[float, float, float, float]]": [(0.0, 0.0, 0.0, 0.0)], "Mapping[str, object]": {},
    "npt.ArrayLike": np.zeros((4, 3), dtype=np.float32), "Matrix4": np.eye(4),
}
VALID_BY_NAME = {"triangles": np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32),
                 "vertices": np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32) * 0.1 + 0.4,
                 "density": np.zeros((2, 2, 2), dtype=np.float32)}
WRONG = {"float": "x", "int": "x", "bool": "yes", "str": 3.5, "bytes": 3.5, "Vec3": "abc", "Sequence[float]": "abc",
         "Sequence[int]": "abc", "Sequence[Vec3]": "abc", "Tuple[float, float, float, float]": "abc",
         "Sequence[Tuple[float, float, float, float]]": "abc", "Mapping[str, object]": 3, "npt.ArrayLike": "abc",
         "Mapping[str, Union[bool, int, float, str, Sequence[float]]]": 3}
# Arguments the function converts itself (a py::object in the binding): a value of the wrong
# type is an InvalidArgumentError naming them, as a wrong value of the right type is.
SELF_CONVERTED = {"Matrix4": "abc", "Union[SourceEmission, str]": 3,
                  "Tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike]": "abc"}
OWNERS = ("Simulation", "Device", "ScriptedDevice", "HostDevice", "HapticSession", "FalconDevice", "FluidSettings",
          "HapticSessionSettings")
# Typed arguments of every function the table cannot call, with the reason: none.
EXPECTED_LEFT_OUT = {}


def _plain(annotation):
    return annotation[len("Optional["):-1] if annotation.startswith("Optional[") else annotation


def _signatures():
    """(qualified name, owner class or None, [(name, annotation, has default)]) of every function and
    method in the stub (and UNSTUBBED), properties left out, self and **keywords dropped."""
    path = Path(hf.__file__).with_name("_core.pyi")
    tree = ast.parse(path.read_text() + "\n" + "\n".join(UNSTUBBED.values()))
    out = []

    def add(func, owner):
        if any(ast.unparse(d) == "property" for d in func.decorator_list):
            return
        if func.name.startswith("_") and func.name != "__init__":
            return
        a = func.args
        positional = a.args[1:] if owner and not any(ast.unparse(d) == "staticmethod" for d in func.decorator_list) \
            else a.args
        first_default = len(positional) - len(a.defaults)
        params = [(p.arg, ast.unparse(p.annotation) if p.annotation else "", i >= first_default)
                  for i, p in enumerate(positional)]
        name = f"{owner}.{func.name}" if owner else func.name
        out.append((name, owner, params))

    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            add(node, None)
        elif isinstance(node, ast.ClassDef):
            for member in node.body:
                if isinstance(member, ast.FunctionDef):
                    add(member, node.name)
    return out


SIGNATURES = _signatures()


def _rows():
    """One row per typed argument: (function, owner, argument, wrong value); and the ones left
    out {function.argument: why}."""
    rows, left_out = [], {}
    for qualname, owner, params in SIGNATURES:
        for name, annotation, _ in params:
            plain = _plain(annotation)
            wrong = 3 if plain in OWNERS else WRONG.get(plain, SELF_CONVERTED.get(plain))
            if plain in WRONG or plain in SELF_CONVERTED or plain in OWNERS:
                missing = [f"{p}: {a}" for p, a, has_default in params
                           if p != name and not has_default and _plain(a) not in VALID and _plain(a) not in OWNERS]
                if missing:
                    left_out[f"{qualname}.{name}"] = f"no value for {missing}"
                elif owner is not None and owner not in OWNERS:
                    left_out[f"{qualname}.{name}"] = f"no {owner} to call it on"
                else:
                    rows.append(pytest.param(qualname, owner, name, wrong, id=f"{qualname}:{name}"))
            elif plain not in ("Any", "object", ""):
                left_out[f"{qualname}.{name}"] = f"no wrong value for {annotation}"
    return rows, left_out


ROWS, LEFT_OUT = _rows()


@pytest.fixture(scope="module")
def instances():
    sim = hf.Simulation(hf.FluidSettings(resolution=(16, 16, 16)))  # cells under the session's probe
    device = hf.null_device()
    out = {"Simulation": sim, "Device": device, "HostDevice": hf.host_device(),
           "ScriptedDevice": hf.scripted_device([0.0, 1.0], [(0.0, 0.0, 0.0), (0.0, 0.0, 0.0)]),
           "HapticSession": hf.HapticSession(sim, device, hf.HapticSessionSettings()),
           "FalconDevice": hf.open_simulated_falcon(home=False), "FluidSettings": hf.FluidSettings(),
           "HapticSessionSettings": hf.HapticSessionSettings()}
    yield out
    out["FalconDevice"].close()
    sim.close()


def _function(qualname):
    owner, _, name = qualname.rpartition(".")
    return getattr(getattr(_core, owner), name if name != "__init__" else "__call__") if owner else \
        getattr(_core, name)


def test_the_table_covers_the_module():
    """Every public native function and method is in the stub (or UNSTUBBED), every typed argument
    of them is a row, and none is left out: a stub or table regression cannot shrink it quietly."""
    stubbed = {q for q, _, _ in SIGNATURES}
    native = set()
    for name, obj in vars(_core).items():
        if name.startswith("_"):
            continue
        if inspect.isbuiltin(obj):
            native.add(name)
        elif isinstance(obj, type) and not issubclass(obj, BaseException) and not hasattr(obj, "__members__"):
            native |= {f"{name}.{attr}" for attr, member in vars(obj).items()
                       if not attr.startswith("_") and type(member).__name__ == "instancemethod"}
    assert native <= stubbed, sorted(native - stubbed)
    assert LEFT_OUT == EXPECTED_LEFT_OUT
    names = {r.values[0] for r in ROWS}
    assert len(ROWS) >= 70 and {"Simulation.set_probe", "Simulation.step", "write_vdb", "scripted_device",
                                "HapticSession.probe_origin", "HapticSession.__init__", "check_sphere_probe",
                                "check_mesh_probe", "measure_dispatch_floor"} <= names, sorted(names)


@pytest.mark.parametrize("qualname,owner,param,wrong", ROWS)
def test_a_wrong_type_names_the_argument(qualname, owner, param, wrong, instances):
    params = next(p for q, _, p in SIGNATURES if q == qualname)
    kwargs = {}
    for name, annotation, has_default in params:
        if name == param:
            kwargs[name] = wrong
        elif not has_default:
            plain = _plain(annotation)
            kwargs[name] = instances[plain] if plain in OWNERS else VALID_BY_NAME.get(name, VALID[plain])
    if qualname.endswith(".__init__"):
        call = getattr(_core, owner)
    elif owner:
        call = getattr(instances[owner], qualname.rpartition(".")[2])
    else:
        call = getattr(_core, qualname)
    annotation = _plain(dict((p, a) for p, a, _ in params)[param])
    # (an array the function reads itself, such as write_vdb's density, is refused as a bad value)
    expected = hf.InvalidArgumentError if annotation in SELF_CONVERTED else \
        (TypeError, hf.InvalidArgumentError) if "ArrayLike" in annotation else TypeError
    with pytest.raises(expected) as info:
        call(**kwargs)
    message = str(info.value)
    assert f"{param} must" in message and "incompatible" not in message, message


def test_the_named_type_error_says_what_was_given():
    """The whole message: the function, the argument, what it must be and what it got."""
    sim = hf.Simulation(hf.FluidSettings(resolution=(8, 8, 8)))
    try:
        with pytest.raises(TypeError) as info:
            sim.set_probe("abc", 0.1)
        assert str(info.value) == "Simulation.set_probe(): centre must be 3 numbers (x, y, z), got str 'abc'"
        with pytest.raises(TypeError, match=r"^Simulation.set_probe\(\): radius must be a number, got NoneType None$"):
            sim.set_probe(VEC3, None)
        with pytest.raises(TypeError, match=r"^HapticSession\(\): device must be a hapticfluid.Device, got NoneType"):
            hf.HapticSession(sim, None)
    finally:
        sim.close()


def test_other_errors_pass_through_unchanged():
    """A bad value of the right type is the engine's InvalidArgumentError, as before; a call
    that matches returns the native result."""
    sim = hf.Simulation(hf.FluidSettings(resolution=(8, 8, 8)))
    try:
        with pytest.raises(hf.InvalidArgumentError, match="time step"):
            sim.step(-1.0)
        assert isinstance(sim.step(0.01), hf.StepReport)
    finally:
        sim.close()
