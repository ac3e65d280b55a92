# SPDX-License-Identifier: GPL-3.0-or-later
"""Name the argument a call got wrong.

pybind11 answers a call whose arguments match none of a function's signatures with
"incompatible function arguments" and the signatures, naming no argument, so a user cannot tell
which one to fix (a tuple of two numbers for a point, a string for a number). install() wraps
each public function and method of the native module so that such a TypeError is raised again
naming the argument, what it must be and what it got::

    Simulation.set_probe(): centre must be 3 numbers (x, y, z), got str 'abc'

Only that error is touched: every other exception (the engine's InvalidArgumentError naming a
bad value, TypeErrors the bindings raise themselves) passes through as it was, and a call that
matches costs one Python frame. The signatures are read from pybind11's docstrings, so there is
nothing to restate here when a binding changes.
"""

from __future__ import annotations

import functools
import inspect
import numbers
import re
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

_GENERIC = ("incompatible function arguments", "incompatible constructor arguments")
_SIGNATURE = re.compile(r"^(?:\d+\. )?(\w+)\((.*)\)(?: -> .*)?$")


def _split_top_level(text: str, sep: str = ",") -> List[str]:
    """Split at the seps outside brackets: the commas of List[float[3]], Dict[str, int]; the bars
    of ``A | B[C | D]``."""
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        elif ch == sep and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    if text[start:].strip():
        parts.append(text[start:])
    return [p.strip() for p in parts]


def canonical(annotation: str) -> str:
    """An annotation in pybind11 2.10's notation, whichever pybind11 wrote it: Debian's 2.10 (the
    source build) writes ``List[float[3]]``, 2.13 (the wheels) ``Annotated[list[float],
    FixedSize(3)]``, and 3.x ``typing.SupportsFloat | typing.SupportsIndex`` for ``float``,
    ``collections.abc.Sequence[...]`` for an argument's list and ``X | None`` for ``Optional[X]``."""
    a = re.sub(r"\b(?:typing|collections\.abc)\.", "", annotation.strip())
    union = _split_top_level(a, "|")
    if len(union) > 1:
        if "None" in union:
            return f"Optional[{canonical(' | '.join(u for u in union if u != 'None'))}]"
        kinds = set(union)
        if kinds == {"SupportsFloat", "SupportsIndex"} or kinds == {"float", "int"}:
            return "float"
        if kinds == {"SupportsInt", "SupportsIndex"}:
            return "int"
        return a
    m = re.fullmatch(r"Annotated\[(.*), [\"']?FixedSize\((\d+)\)[\"']?\]", a)
    if m:
        inner = canonical(m.group(1))
        return f"List[{inner[5:-1]}[{m.group(2)}]]" if inner.startswith("List[") else a
    m = re.fullmatch(r"(list|List|Sequence|Optional)\[(.*)\]", a)
    if m:
        return f"{'Optional' if m.group(1) == 'Optional' else 'List'}[{canonical(m.group(2))}]"
    return a


class Param:
    """One parameter of a signature: name, annotation (canonical()), whether it has a default."""

    def __init__(self, text: str):
        name, _, rest = text.partition(":")
        annotation, _, default = rest.partition("=")
        self.name = name.strip()
        self.annotation = canonical(annotation)
        self.has_default = bool(_.strip() or default.strip())
        self.star = self.name.startswith("*")


def signatures(doc: Optional[str]) -> List[List[Param]]:
    """The signatures in a pybind11 docstring (one per overload), without ``self``."""
    out = []
    for line in (doc or "").splitlines():
        m = _SIGNATURE.match(line.strip())
        if not m:
            continue
        params = [Param(p) for p in _split_top_level(m.group(2))]
        out.append([p for p in params if p.name != "self"])
    return out


def _is_number(v: Any) -> bool:
    return isinstance(v, (numbers.Real, np.number)) and not isinstance(v, (bool, np.bool_))


def _is_seq(v: Any) -> bool:
    return isinstance(v, (list, tuple, np.ndarray)) and not isinstance(v, (str, bytes))


def _numbers(n: Optional[int]) -> Callable[[Any], bool]:
    def check(v: Any) -> bool:
        return _is_seq(v) and (n is None or len(v) == n) and all(_is_number(x) for x in v)

    return check


def _rows_of_3(v: Any) -> bool:
    return _is_seq(v) and all(_numbers(3)(row) for row in v)


def _array(v: Any) -> bool:
    try:
        a = np.asarray(v)
    except Exception:  # a ragged list, an object that refuses
        return False
    return a.dtype.kind in "biuf"


def _checker(annotation: str, core: Any) -> Tuple[Optional[Callable[[Any], bool]], str]:
    """(a test a value of that annotation passes, what it must be); (None, '') when unknown."""
    if annotation.startswith("Optional[") and annotation.endswith("]"):
        inner, what = _checker(annotation[len("Optional["):-1], core)
        if inner is None:
            return None, ""
        return (lambda v: v is None or inner(v)), f"{what} or None"
    table = {
        "float": (_is_number, "a number"),
        "int": (lambda v: isinstance(v, (numbers.Integral, np.integer)) and not isinstance(v, (bool, np.bool_)),
                "an integer"),
        "bool": (lambda v: isinstance(v, (bool, np.bool_)), "True or False"),
        "str": (lambda v: isinstance(v, str), "a string"),
        "dict": (lambda v: isinstance(v, dict), "a dict"),
        "List[float[3]]": (_numbers(3), "3 numbers (x, y, z)"),
        "List[float[4]]": (_numbers(4), "4 numbers (w, x, y, z)"),
        "List[float]": (_numbers(None), "a list of numbers"),
        "List[List[float[3]]]": (_rows_of_3, "a list of [x, y, z] rows"),
        "List[List[float[4]]]": (lambda v: _is_seq(v) and all(_numbers(4)(row) for row in v),
                                 "a list of [t, x, y, z] rows"),
        "List[int[3]]": (lambda v: _is_seq(v) and len(v) == 3 and all(
            isinstance(x, (numbers.Integral, np.integer)) and not isinstance(x, bool) for x in v), "3 integers"),
        "bytes": (lambda v: isinstance(v, (bytes, bytearray)), "bytes"),
    }
    if annotation in table:
        return table[annotation]
    if annotation.startswith("numpy.ndarray"):
        return _array, "an array of numbers"
    if annotation.startswith("hapticfluid._core."):
        cls = getattr(core, annotation.rsplit(".", 1)[1], None)
        if isinstance(cls, type):
            return (lambda v: isinstance(v, cls)), f"a hapticfluid.{cls.__name__}"
    return None, ""


def _shown(v: Any) -> str:
    text = repr(v)
    return f"{type(v).__name__} {text if len(text) <= 60 else text[:57] + '...'}"


def explain(qualname: str, doc: Optional[str], args: Sequence[Any], kwargs: Dict[str, Any], core: Any) -> Optional[str]:
    """What is wrong with a call pybind11 refused, naming the argument; None if it cannot tell."""
    found = []
    for params in signatures(doc):
        named = [p for p in params if not p.star]
        takes_kwargs = any(p.name.startswith("**") for p in params)
        if len(args) > len(named):
            found.append(f"takes at most {len(named)} argument(s) ({', '.join(p.name for p in named)}), "
                         f"got {len(args)}")
            continue
        given = {p.name: a for p, a in zip(named, args)}
        unknown = [k for k in kwargs if k not in {p.name for p in named}]
        if unknown and not takes_kwargs:
            found.append(f"no argument named {unknown[0]!r}; its arguments are: "
                         f"{', '.join(p.name for p in named)}")
            continue
        given.update({k: v for k, v in kwargs.items() if k not in unknown})
        missing = [p.name for p in named if p.name not in given and not p.has_default]
        if missing:
            found.append(f"missing argument {missing[0]!r}")
            continue
        for p in named:
            if p.name not in given:
                continue
            check, what = _checker(p.annotation, core)
            if check is not None and not check(given[p.name]):
                found.append(f"{p.name} must be {what}, got {_shown(given[p.name])}")
                break
    return f"{qualname}(): {found[0]}" if found else None


def _wrap(func: Callable, qualname: str, core: Any) -> Callable:
    @functools.wraps(func)
    def call(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except TypeError as exc:
            if not any(g in str(exc) for g in _GENERIC):
                raise
            is_method = "." in qualname
            message = explain(qualname, func.__doc__, args[1:] if is_method else args, kwargs, core)
            if message is None:
                raise
            raise TypeError(message) from None

    call.__wrapped_native__ = func  # type: ignore[attr-defined]
    return call


def install(core: Any) -> int:
    """Wrap the native module's public functions and the methods of its classes (once);
    returns how many were wrapped."""
    if getattr(core, "_argument_names_installed", False):
        return 0
    count = 0
    for name, obj in list(vars(core).items()):
        if name.startswith("_"):
            continue
        if inspect.isbuiltin(obj) and signatures(obj.__doc__):
            setattr(core, name, _wrap(obj, name, core))
            count += 1
        elif isinstance(obj, type) and not issubclass(obj, BaseException):
            for attr, member in list(vars(obj).items()):
                if attr.startswith("_") or not callable(member) or isinstance(member, (property, type)):
                    continue
                if type(member).__name__ != "instancemethod" or not signatures(member.__doc__):
                    continue
                setattr(obj, attr, _wrap(member, f"{name}.{attr}", core))
                count += 1
    core._argument_names_installed = True
    return count
