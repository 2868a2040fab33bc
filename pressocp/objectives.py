"""Objectives of the speed problem, in one registry.

An objective names the response outputs it needs and gives its *terms*: expressions of those
outputs that work on numpy arrays and on CasADi symbols alike. A ``peak`` objective is the largest
|term| over the cycle (solved as an epigraph: -s <= term <= s at every sample); an ``rms``
objective is the root mean square of its term; an ``integral`` one the integral of its term over
the period (an energy per stroke, from a power); a ``swing`` one the range of the integral of its
term minus its mean (the energy a store must buffer for the supply to deliver the mean power
only). The same definition gives the value on a simulated response, the scale of the NLP and its
constraints, so adding an objective is one `register` call.

A drive objective (``drive=True``) reads the motor's figures, which `motor_entries` adds to the
outputs from the problem's `pressocp.drive.Drive`: ``motor_torque`` (the torque that acts, driving
or regenerating, N m), ``motor_power`` (W) and ``supply_power`` (W: the motor's power while it
drives, minus `Drive.regeneration_efficiency` of it while it regenerates).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .series import PIN_FORCES

KINDS = ("peak", "rms", "integral", "swing")


def trapezoid_weights(t: np.ndarray, period: float | None = None) -> np.ndarray:
    """Integration weights (s) of samples at times `t`: ``weights @ f(t)`` is the integral of f.
    Without `period` the samples span the interval they cover (sorted, both ends included); with
    it they are samples of a periodic function, one period, in any order (the weights sum to the
    period)."""
    t = np.asarray(t, float).ravel()
    if period is None:
        gaps = np.diff(t)
        return 0.5 * (np.concatenate([gaps, [0.0]]) + np.concatenate([[0.0], gaps]))
    order = np.argsort(t)
    ts = t[order]
    gaps = np.diff(np.concatenate([ts, [ts[0] + period]]))
    w = np.empty_like(t)
    w[order] = 0.5 * (gaps + np.roll(gaps, 1))
    return w


def motor_entries(drive: Any, torque, omega, alpha) -> dict[str, Any]:
    """The motor's figures the drive objectives read, from the crank torque (N m), speed (rad/s,
    > 0) and acceleration (rad/s^2), numpy arrays: the acting torque
    (`pressocp.drive.Drive.acting_torque`), its power and the power drawn from the supply
    (`pressocp.drive.Drive.supply_power`)."""
    motor = drive.acting_torque(torque, alpha)
    power = motor * drive.gear_ratio * np.asarray(omega, float)
    return {"motor_torque": motor, "motor_power": power, "supply_power": drive.supply_power(power)}


@dataclass(frozen=True)
class Objective:
    """A load to minimise.

    Attributes
    ----------
    name : str
        Registry key (e.g. ``"peak_torque"``).
    outputs : tuple of str
        Response outputs the terms use (names of `pressocp.model.OUTPUT_NAMES` /
        `pressocp.SimResult` fields); a drive objective lists the crank's torque and speed.
    terms : callable
        ``terms(y) -> list`` of expressions of ``y[name]`` (numpy arrays or CasADi rows).
    unit : str
        Unit of the value, e.g. ``"N m"``.
    kind : {"peak", "rms", "integral", "swing"}
        Largest |term| over all terms and samples, the RMS of the (single) term, its integral over
        the period, or the range of the integral of (term - its mean).
    description : str
        One line for tables and plots.
    drive : bool
        The terms read `motor_entries` (the problem needs a drive).
    """

    name: str
    outputs: tuple[str, ...]
    terms: Callable[[Mapping[str, Any]], list]
    unit: str
    kind: str = "peak"
    description: str = ""
    drive: bool = False

    def value(self, response: Any, drive: Any = None, *, period: float | None = None, alpha: Any = None) -> float:
        """The objective on a response: a `SimResult` or a mapping of output arrays (with ``t``, s,
        for the integral and swing kinds and the drive objectives).

        Parameters
        ----------
        drive : pressocp.drive.Drive, optional
            The problem's drive; a drive objective needs it.
        period : float, optional
            The samples are one period of a periodic response, in any order (s); otherwise they
            span the interval they cover, sorted, both ends included.
        alpha : array, optional
            The crank acceleration at the samples, rad/s^2 (drive objectives); default: the
            derivative of the crank speed over the samples.
        """
        terms = self.sample_terms(response, drive, alpha=alpha)
        if self.kind == "rms":
            return float(np.sqrt(np.mean(terms[0] ** 2)))
        if self.kind == "peak":
            return float(max(np.max(np.abs(t)) for t in terms))
        t = np.asarray(response["t"] if isinstance(response, Mapping) else response.t, float).ravel()
        w = trapezoid_weights(t, period)
        total = float(w @ terms[0])
        if self.kind == "integral":
            return total
        span = float(np.sum(w))
        if period is None:
            from scipy.integrate import cumulative_trapezoid  # scipy.integrate: 1 s to import, seldom needed

            stored = cumulative_trapezoid(terms[0] - total / span, t, initial=0.0)
        else:
            order = np.argsort(t)
            stored = np.cumsum((w * (terms[0] - total / span))[order])
        return float(np.max(stored) - np.min(stored))

    def sample_terms(self, response: Any, drive: Any = None, *, alpha: Any = None) -> list[np.ndarray]:
        """The objective's terms at each sample of a response (as `value` reads it: a `SimResult` or
        a mapping of output arrays, with ``t`` where the kind or the drive needs it)."""
        names = self.outputs + (("t",) if self.kind in ("integral", "swing") or self.drive else ())
        y = dict(response) if isinstance(response, Mapping) else {n: getattr(response, n) for n in names}
        if self.drive:
            if drive is None:
                raise ValueError(f"objective {self.name!r} reads the motor: the problem needs a drive (SpeedProblem.drive)")
            t, omega = np.asarray(y["t"], float).ravel(), np.asarray(y["omega"], float).ravel()
            if alpha is None:
                order = np.argsort(t)
                alpha = np.empty_like(t)
                alpha[order] = np.gradient(omega[order], t[order], edge_order=2)
            y.update(motor_entries(drive, np.ravel(y["torque"]), omega, np.ravel(alpha)))
        return [np.asarray(t, float).ravel() for t in self.terms(y)]


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
register(Objective("rms_motor_torque", ("torque", "omega"), lambda y: [y["motor_torque"]], "N m", kind="rms",
                   description="RMS motor torque behind the gear (heat: the continuous rating)", drive=True))
register(Objective("energy_per_stroke", ("torque", "omega"), lambda y: [y["supply_power"]], "J", kind="integral",
                   description="energy drawn from the supply per stroke, less what regeneration gives back",
                   drive=True))
register(Objective("bus_energy_swing", ("torque", "omega"), lambda y: [y["motor_power"]], "J", kind="swing",
                   description="DC-bus energy swing: the range of the motor's energy about its mean power",
                   drive=True))
