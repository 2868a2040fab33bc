"""Input validation helpers: every message names the parameter and the allowed range."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np


class PlausibilityWarning(UserWarning):
    """A value inside its range that is implausible against the rest of the press (a mass in grams
    among masses in kilograms, a speed limit in rpm): most likely a unit slip. The command line's
    ``--strict`` makes it an error."""


def suspect(message: str) -> None:
    """Warn (`PlausibilityWarning`) about a value that is probably in the wrong unit."""
    warnings.warn(message, PlausibilityWarning, stacklevel=4)


class WrongType(TypeError, ValueError):
    """An argument of the wrong kind. A TypeError, and a ValueError too, so that every handler of
    bad input (the command line's among them) reports it as such."""


#: What to do instead, by (expected class, given class) names.
TYPE_HINTS = {
    ("SpeedProblem", "PressParams"): "wrap the press in a problem, SpeedProblem(press, period=..., ram_speed=...)",
    ("PressParams", "SpeedProblem"): "pass the problem's press, problem.press",
    ("PressParams", "Scenario"): "pass the scenario's press, scenario.press",
    ("SpeedProblem", "Scenario"): "pass the scenario's problem, scenario.problem",
    ("PressModel", "PressParams"): "build the model first, build_model(press)",
    ("FourierSpeed", "SpeedDesign"): "pass the design's speed, design.speed",
    ("FourierSpeed", "OcpResult"): "pass the result's speed, result.speed",
}


def instance(name: str, value: Any, cls: type) -> Any:
    """`value` when it is a `cls`, else `WrongType` naming the argument, both classes and, for the
    usual mix-ups (`TYPE_HINTS`), what to pass instead."""
    if isinstance(value, cls):
        return value
    got = type(value).__name__
    hint = TYPE_HINTS.get((cls.__name__, got))
    raise WrongType(f"{name} must be a {cls.__name__}, got {got}" + (f": {hint}" if hint else ""))


def finite(name: str, value: Any) -> float:
    """Return ``value`` as a float, raising ``ValueError`` unless it is a finite real number (a bool is
    not one: ``gravity=True`` is a slip, not 1 m/s^2)."""
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be a finite real number, got the bool {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite real number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite (not NaN or inf), got {value!r}")
    return x


def positive(name: str, value: Any, unit: str = "") -> float:
    """Finite and strictly positive: allowed range (0, inf)."""
    x = finite(name, value)
    if x <= 0.0:
        raise ValueError(f"{name} must be in (0, inf){' ' + unit if unit else ''}, got {x!r}")
    return x


def nonnegative(name: str, value: Any, unit: str = "") -> float:
    """Finite and >= 0: allowed range [0, inf)."""
    x = finite(name, value)
    if x < 0.0:
        raise ValueError(f"{name} must be in [0, inf){' ' + unit if unit else ''}, got {x!r}")
    return x


def in_open_interval(name: str, value: Any, lo: float, hi: float, unit: str = "") -> float:
    """Finite and inside the open interval (lo, hi)."""
    x = finite(name, value)
    if not lo < x < hi:
        raise ValueError(f"{name} must be in ({lo:g}, {hi:g}){' ' + unit if unit else ''}, got {x!r}")
    return x


def in_closed_interval(name: str, value: Any, lo: float, hi: float, unit: str = "") -> float:
    """Finite and inside [lo, hi]."""
    x = finite(name, value)
    if not lo <= x <= hi:
        raise ValueError(f"{name} must be in [{lo:g}, {hi:g}]{' ' + unit if unit else ''}, got {x!r}")
    return x


def in_half_open_interval(name: str, value: Any, lo: float, hi: float, unit: str = "") -> float:
    """Finite and inside [lo, hi)."""
    x = finite(name, value)
    if not lo <= x < hi:
        raise ValueError(f"{name} must be in [{lo:g}, {hi:g}){' ' + unit if unit else ''}, got {x!r}")
    return x


def finite_array(name: str, value: Any, ndim: int | None = 1) -> np.ndarray:
    """Return ``value`` as a float array, raising ``ValueError`` on NaN/inf or a wrong dimension."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of finite real numbers") from None
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite values (no NaN or inf)")
    return arr


def point_table(obj: Any, x_name: str, y_name: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The frozen dataclass `obj`'s two fields `x_name` and `y_name`, a table of points, stored as
    tuples of finite floats; ValueError unless both have the same length. Returns them."""
    x = tuple(float(v) for v in finite_array(x_name, getattr(obj, x_name)))
    y = tuple(float(v) for v in finite_array(y_name, getattr(obj, y_name)))
    object.__setattr__(obj, x_name, x)
    object.__setattr__(obj, y_name, y)
    if len(x) != len(y):
        raise ValueError(f"{x_name} and {y_name} must have the same length, got {len(x)} and {len(y)}")
    return x, y


def integer(name: str, value: Any, lo: int, hi: int) -> int:
    """An integer in the closed range [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {value!r}")
    if not lo <= int(value) <= hi:
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {value!r}")
    return int(value)


def choice(name: str, value: Any, allowed: tuple[str, ...]) -> str:
    """One of a fixed set of strings."""
    if value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, allowed))}; got {value!r}")
    return value


#: Field annotations (as strings, under ``from __future__ import annotations``, spaces removed) of
#: real numbers.
REAL_ANNOTATIONS = frozenset({"float", "float|None", "Optional[float]"})


def convert_reals(obj: Any) -> None:
    """Store every real-number field of the frozen dataclass `obj` (annotated ``float`` or
    ``float | None``, and not None) as a float: ``"1e11"``, ``7`` or ``np.float32(0.5)`` become
    floats, so later arithmetic is arithmetic. A value that is not a finite real number (a bool, a
    word, NaN) raises ValueError naming the field. Call it first in ``__post_init__``."""
    import dataclasses

    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if value is not None and str(f.type).replace(" ", "") in REAL_ANNOTATIONS:
            object.__setattr__(obj, f.name, finite(f.name, value))
