"""Result containers shared by the rigid inverse dynamics and the simulation of the full model."""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from .io import atomic_write
from .series import RESPONSE_PEAKS

#: Time series every response carries, with units.
SERIES_UNITS = {
    "t": "s",
    "theta": "rad",
    "omega": "rad/s",
    "torque": "N m",
    "ram_height": "m",
    "ram_velocity": "m/s",
    "ram_acceleration": "m/s^2",
    "slider_normal_force": "N",
    "crank_pin_force": "N",
    "wrist_pin_force": "N",
    "crank_pin_eccentricity": "-",
    "wrist_pin_eccentricity": "-",
    "rod_midspan_deflection": "m",
}


@dataclass
class SimResult:
    """Time histories of a press response (rigid inverse dynamics or a simulation).

    Attributes
    ----------
    t : ndarray
        Time, s.
    theta, omega : ndarray
        Crank angle (rad, 0 at top dead centre) and speed (rad/s).
    torque : ndarray
        Motor torque, N m, positive when it drives the crank in its direction of rotation.
    ram_height, ram_velocity, ram_acceleration : ndarray
        h above bottom dead centre (m), dh/dt (m/s, negative on the downstroke), d2h/dt2 (m/s^2).
    slider_normal_force : ndarray
        Force of the guide on the slider across the slide (signed, +x), N.
    crank_pin_force, wrist_pin_force : ndarray
        Magnitudes of the joint forces, N.
    crank_pin_eccentricity, wrist_pin_eccentricity : ndarray
        Journal eccentricity over clearance |e|/c (zeros for an ideal joint).
    rod_midspan_deflection : ndarray
        Transverse deflection of the rod at midspan, m (zeros for a rigid rod).
    stats : dict
        Solver statistics (wall_time in s, steps, ...), empty for closed-form results.
    energy : dict
        Work and energy bookkeeping of a simulation, J (motor, contact and process work;
        kinetic and potential energy at start and end).
    states : ndarray
        Physical (unscaled) model states over time, shape (nx, len(t)).
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    torque: np.ndarray
    ram_height: np.ndarray
    ram_velocity: np.ndarray
    ram_acceleration: np.ndarray
    slider_normal_force: np.ndarray
    crank_pin_force: np.ndarray
    wrist_pin_force: np.ndarray
    crank_pin_eccentricity: np.ndarray
    wrist_pin_eccentricity: np.ndarray
    rod_midspan_deflection: np.ndarray
    stats: dict = field(default_factory=dict)
    energy: dict = field(default_factory=dict)
    states: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name in SERIES_UNITS:
                arr = np.asarray(getattr(self, f.name), dtype=float)
                if not np.all(np.isfinite(arr)):
                    raise FloatingPointError(f"non-finite values in {f.name}")
                setattr(self, f.name, arr)

    def peak(self, name: str) -> float:
        """Largest magnitude of a series, e.g. ``peak("torque")``."""
        return float(np.max(np.abs(getattr(self, name))))

    def peaks(self) -> dict[str, float]:
        """Peak magnitude of every load series (torque and forces)."""
        names = RESPONSE_PEAKS
        return {n: self.peak(n) for n in names}

    def min_eccentricities(self, joints) -> dict[str, float]:
        """Smallest eccentricity ratio |e|/c of each of the clearance `joints` ("crank_pin",
        "wrist_pin") over the response: below 1 the journal leaves its bearing wall."""
        return {j: float(np.min(getattr(self, f"{j}_eccentricity"))) for j in joints}

    def as_dict(self) -> dict[str, np.ndarray]:
        """The series as a dict of arrays."""
        return {n: getattr(self, n) for n in SERIES_UNITS}

    def to_csv(self, path: str | Path) -> Path:
        """Write the time series as CSV, one column per series, headers with units (``torque [N m]``).

        Written atomically (a temporary file, then renamed). Returns the path."""
        import pandas as pd

        frame = pd.DataFrame({f"{n} [{u}]": getattr(self, n) for n, u in SERIES_UNITS.items()})
        return atomic_write(path, frame.to_csv(index=False, float_format="%.10g"))
