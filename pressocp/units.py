"""Display units: the unit a report or a figure shows a quantity in, and the factor from SI to it.
Files (``summary.json``, ``results.csv``, ``sweep.csv``) stay in SI; only what a person reads is
scaled, here and nowhere else.

Forces are shown in kN from `KILONEWTONS_FROM` on, in N below: the choice is made once per label
(a table row, an axis) by the largest magnitude it shows, so one label has one unit."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

#: Forces of this magnitude or more are shown in kN, N.
KILONEWTONS_FROM = 1e4


def force_unit(*values: float | Iterable[float]) -> tuple[str, float]:
    """The unit of forces and the factor from N to it: ``("kN", 1e-3)`` when the largest magnitude of
    `values` (N: numbers or arrays; NaN ignored) is at least `KILONEWTONS_FROM`, else ``("N", 1.0)``."""
    largest = max((float(np.nanmax(np.abs(np.asarray(v, dtype=float)), initial=0.0)) for v in values), default=0.0)
    return ("kN", 1e-3) if largest >= KILONEWTONS_FROM else ("N", 1.0)


def format_force(value: float, significant: int | None = None) -> str:
    """A force (N) with its unit: ``"584.2 N"``, ``"22.93 kN"`` (tables: fixed decimals), or with
    `significant` digits and no trailing zeros for a message (``"60 kN"``, ``"18.13 kN"``)."""
    unit, factor = force_unit(value)
    if significant is not None:
        return f"{value * factor:.{significant}g} {unit}"
    return f"{value * factor:,.1f} {unit}" if unit == "N" else f"{value * factor:,.2f} {unit}"


#: Display units of scenario keys by the end of their dotted name, first match: (ending, unit, factor
#: from SI). Lengths and clearances in mm; "force" is chosen by magnitude (`force_unit`).
KEY_UNITS: tuple[tuple[str, str, float], ...] = (
    ("_spm", "strokes/min", 1.0), ("speed_edge", "m/s", 1.0), ("ram_speed_tol", "m/s", 1.0), ("ram_speed", "m/s", 1.0),
    ("period_s", "s", 1.0), ("clearance", "mm", 1e3), ("radius", "mm", 1e3), ("length", "mm", 1e3),
    ("crank_com", "mm", 1e3), ("h_top", "mm", 1e3), ("h_bottom", "mm", 1e3), ("edge", "mm", 1e3),
    ("heights", "mm", 1e3), ("input_crank", "mm", 1e3), ("coupler", "mm", 1e3), ("upper_link", "mm", 1e3),
    ("lower_link", "mm", 1e3), ("mass", "kg", 1.0), ("inertia", "kg m²", 1.0), ("youngs_modulus", "GPa", 1e-9),
    ("area_moment", "mm⁴", 1e12), ("stiffness", "N/m^exponent", 1.0), ("tangential_damping", "N s/m", 1.0),
    ("damping", "s/m", 1.0), ("force", "force", 1.0), ("forces", "force", 1.0), ("torque", "N m", 1.0),
    ("power_limit", "kW", 1e-3), ("max_speed", "rad/s", 1.0), ("omega_min", "rad/s", 1.0),
    ("omega_max", "rad/s", 1.0), ("alpha_max", "rad/s²", 1.0), ("gravity", "m/s²", 1.0), ("drive_angle", "rad", 1.0),
)


def key_unit(key: str, values: Iterable[float] = ()) -> tuple[str | None, float]:
    """The display unit of a scenario key (``"crank_pin.clearance"`` -> ``("mm", 1e3)``) and the factor
    from its SI value; forces (keys ending in ``force``) by the magnitude of `values` (`force_unit`).
    ``(None, 1.0)`` for a key without a unit (a ratio, an exponent, an unknown key)."""
    unit, factor = next(((u, f) for end, u, f in KEY_UNITS if key.endswith(end)), (None, 1.0))
    if unit == "force":
        return force_unit(np.asarray(list(values), dtype=float))
    return unit, factor


__all__ = ["KEY_UNITS", "KILONEWTONS_FROM", "force_unit", "format_force", "key_unit"]
