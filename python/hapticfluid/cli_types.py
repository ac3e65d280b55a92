# SPDX-License-Identifier: GPL-3.0-or-later
"""argparse argument types shared by the command-line tools: each turns one word into a
checked value or raises ``argparse.ArgumentTypeError`` with what was expected, so a bad
argument is reported by argparse with the option's name and nothing runs."""

from __future__ import annotations

import argparse
import math

MAX_ITERATIONS = 100000  # the most pressure iterations a command accepts


def int_at_least(text: str, minimum: int, expected: str, too_small: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
    if value < minimum:
        raise argparse.ArgumentTypeError(f"{too_small}, got {value}")
    return value


def positive_int(text: str) -> int:
    return int_at_least(text, 1, "a positive integer", "must be a positive integer")


def cells(text: str) -> int:
    """Cells along one axis: at least 8."""
    return int_at_least(text, 8, "a cell count", "need at least 8 cells per axis")


def iterations(text: str) -> int:
    value = positive_int(text)
    if value > MAX_ITERATIONS:
        raise argparse.ArgumentTypeError(f"must be at most {MAX_ITERATIONS}, got {value}")
    return value


def finite_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text}")
    return value


def positive_float(text: str) -> float:
    value = finite_float(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text}")
    return value
