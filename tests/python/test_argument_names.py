# SPDX-License-Identifier: GPL-3.0-or-later
"""Every public function and method of the native module, every typed argument, a value of the
wrong type: the TypeError names the argument and what it must be, never pybind11's generic
"incompatible function arguments" (hapticfluid._arguments). The table is built from the
bindings' own signatures, so a new binding is in it without a line here."""

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import _arguments, _core

VALID = {
    "float": 0.5, "int": 1, "bool": False, "str": "x", "dict": {},
    "List[float[3]]": (0.5, 0.5, 0.5), "List[float[4]]": (1.0, 0.0, 0.0, 0.0), "List[float]": [0.0, 1.0],
    "List[List[float[3]]]": [(0.0, 0.0, 0.0), (0.0, 0.0, 0.0)], "List[List[float[4]]]": [(0.0, 0.0, 0.0, 0.0)],
    "List[int[3]]": (16, 16, 16), "bytes": b"",
    "object": np.zeros((2, 2, 2), dtype=np.float32), "handle": np.zeros((2, 2, 2), dtype=np.float32),
}
WRONG = {"float": "x", "int": "x", "bool": "yes", "str": 3.5, "dict": 3, "List[float[3]]": "abc",
         "List[float[4]]": "abc", "List[float]": "abc", "List[List[float[3]]]": "abc", "List[List[float[4]]]": "abc",
         "List[int[3]]": "abc", "bytes": 3.5}


def _plain(annotation):
    return annotation[len("Optional["):-1] if annotation.startswith("Optional[") else annotation


def _wrong(annotation):
    a = _plain(annotation)
    if a in WRONG:
        return WRONG[a]
    if a.startswith("numpy.ndarray"):
        return "abc"
    if a.startswith("hapticfluid._core."):
        return 3
    return None


def _valid(annotation, instances):
    a = _plain(annotation)
    if a in VALID:
        return VALID[a]
    if a.startswith("numpy.ndarray"):
        return np.zeros((2, 3), dtype=np.float32)
    if a.startswith("hapticfluid._core."):
        return instances.get(a.rsplit(".", 1)[1])
    return None


@pytest.fixture(scope="module")
def instances():
    sim = hf.Simulation(hf.FluidSettings(resolution=(16, 16, 16)))  # cells under the session's probe
    device = hf.null_device()
    out = {"Simulation": sim, "Device": device, "HostDevice": hf.host_device(),
           "ScriptedDevice": hf.scripted_device([0.0, 1.0], [(0.0, 0.0, 0.0), (0.0, 0.0, 0.0)]),
           "HapticSession": hf.HapticSession(sim, device, hf.HapticSessionSettings()),
           "FalconDevice": hf.open_simulated_falcon(home=False)}
    yield out
    out["FalconDevice"].close()
    sim.close()


def _callables():
    """(qualified name, wrapped callable, owner class name or None) of every wrapped binding."""
    out = []
    for name, obj in sorted(vars(_core).items()):
        if callable(obj) and hasattr(obj, "__wrapped_native__"):
            out.append((name, obj, None))
        elif isinstance(obj, type):
            for attr, member in sorted(vars(obj).items()):
                if hasattr(member, "__wrapped_native__"):
                    out.append((f"{name}.{attr}", member, name))
    return out


def _rows():
    rows = []
    for qualname, func, owner in _callables():
        for params in _arguments.signatures(func.__doc__)[:1]:
            for p in params:
                if not p.star and _wrong(p.annotation) is not None:
                    rows.append(pytest.param(qualname, owner, p.name, id=f"{qualname}:{p.name}"))
    return rows


ROWS = _rows()


def test_the_table_covers_the_bindings():
    """Most of the API is in the table (a parsing regression would empty it)."""
    names = {r.values[0] for r in ROWS}
    assert len(ROWS) >= 60 and {"Simulation.set_probe", "Simulation.step", "write_vdb", "scripted_device",
                                "HapticSession.probe_origin"} <= names, sorted(names)


@pytest.mark.parametrize("qualname,owner,param", ROWS)
def test_a_wrong_type_names_the_argument(qualname, owner, param, instances):
    func = dict((q, f) for q, f, _ in _callables())[qualname]
    params = _arguments.signatures(func.__doc__)[0]
    kwargs = {}
    for p in params:
        if p.star:
            continue
        if p.name == param:
            kwargs[p.name] = _wrong(p.annotation)
        elif not p.has_default:
            value = _valid(p.annotation, instances)
            if value is None:
                pytest.skip(f"no valid value for {p.name}: {p.annotation}")
            kwargs[p.name] = value
    if owner and owner not in instances:
        pytest.skip(f"no {owner} instance here")
    args = (instances[owner],) if owner else ()
    with pytest.raises(TypeError) as info:
        func(*args, **kwargs)
    message = str(info.value)
    assert param in message and "incompatible" not in message, message


def test_other_errors_pass_through_unchanged():
    """A bad value of the right type is the engine's InvalidArgumentError, as before; a call
    that matches is not slowed by more than one Python frame (the result is the native one)."""
    sim = hf.Simulation(hf.FluidSettings(resolution=(8, 8, 8)))
    try:
        with pytest.raises(hf.InvalidArgumentError, match="time step"):
            sim.step(-1.0)
        assert isinstance(sim.step(0.01), hf.StepReport)
    finally:
        sim.close()


@pytest.mark.parametrize("written,meant", [
    # Debian's pybind11 2.10 (the source build), 2.13 (the wheels) and 3.x write the same types so
    ("List[float[3]]", "List[float[3]]"),
    ("Annotated[list[float], FixedSize(3)]", "List[float[3]]"),
    ('typing.Annotated[collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], "FixedSize(3)"]',
     "List[float[3]]"),
    ("list[Annotated[list[float], FixedSize(4)]]", "List[List[float[4]]]"),
    ("Optional[Annotated[list[int], FixedSize(3)]]", "Optional[List[int[3]]]"),
    ("typing.SupportsFloat | typing.SupportsIndex", "float"),
    ("typing.SupportsInt | typing.SupportsIndex", "int"),
    ("collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex] | None", "Optional[List[float]]"),
    ("hapticfluid._core.Simulation", "hapticfluid._core.Simulation"),
])
def test_annotations_read_alike_from_every_pybind11(written, meant):
    assert _arguments.canonical(written) == meant
