"""Objectives of the speed problem, in one registry.

An objective names the response outputs it needs and gives its *terms*: expressions of those
outputs that work on numpy arrays and on CasADi symbols alike. A ``peak`` objective is the largest
|term| over the cycle (solved as an epigraph: -s <= term <= s at every sample); an ``rms``
objective is the root mean square of its term. The same definition gives the value on a
simulated response, the scale of the NLP and its constraints, so adding an objective is one
`register` call.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .series import PIN_FORCES

KINDS = ("peak", "rms")


@dataclass(frozen=True)
class Objective:
    """A load to minimise.

    Attributes
    ----------
    name : str
        Registry key (e.g. ``"peak_torque"``).
    outputs : tuple of str
        Response outputs the terms use (names of `pressocp.model.OUTPUT_NAMES` /
        `pressocp.SimResult` fields).
    terms : callable
        ``terms(y) -> list`` of expressions of ``y[name]`` (numpy arrays or CasADi rows).
    unit : str
        Unit of the value, e.g. ``"N m"``.
    kind : {"peak", "rms"}
        Largest |term| over all terms and samples, or the RMS of the (single) term.
    description : str
        One line for tables and plots.
    """

    name: str
    outputs: tuple[str, ...]
    terms: Callable[[Mapping[str, Any]], list]
    unit: str
    kind: str = "peak"
    description: str = ""

    def value(self, response: Any) -> float:
        """The objective on a response: a `SimResult` or a mapping of output arrays."""
        y = response if isinstance(response, Mapping) else {n: getattr(response, n) for n in self.outputs}
        terms = [np.asarray(t, float) for t in self.terms(y)]
        if self.kind == "rms":
            return float(np.sqrt(np.mean(terms[0] ** 2)))
        return float(max(np.max(np.abs(t)) for t in terms))


OBJECTIVES: dict[str, Objective] = {}


def register(objective: Objective) -> Objective:
    """Add an objective to `OBJECTIVES` (its name must be new and its kind known)."""
    if objective.name in OBJECTIVES:
        raise ValueError(f"objective {objective.name!r} is registered already")
    if objective.kind not in KINDS:
        raise ValueError(f"objective kind must be one of {KINDS}, got {objective.kind!r}")
    OBJECTIVES[objective.name] = objective
    return objective


def get(name: str) -> Objective:
    """The registered objective `name` (ValueError naming the registered ones otherwise)."""
    if name not in OBJECTIVES:
        raise ValueError(f"objective must be one of {', '.join(map(repr, OBJECTIVES))}; got {name!r}")
    return OBJECTIVES[name]


register(Objective("peak_torque", ("torque",), lambda y: [y["torque"]], "N m",
                   description="peak |motor torque|"))
register(Objective("peak_slider_normal_force", ("slider_normal_force",), lambda y: [y["slider_normal_force"]], "N",
                   description="peak |slider normal force|"))
register(Objective("peak_pin_force", PIN_FORCES,
                   lambda y: [y["crank_pin_force"], y["wrist_pin_force"]], "N",
                   description="peak pin force (the larger of the two joints)"))
register(Objective("rms_torque", ("torque",), lambda y: [y["torque"]], "N m", kind="rms",
                   description="RMS motor torque"))
register(Objective("peak_power", ("torque", "omega"), lambda y: [y["torque"] * y["omega"]], "W",
                   description="peak |motor power| = peak |torque x crank speed| (the motor's power rating)"))
