"""Hunt-Crossley: F = K delta^n pos(1 + chi delta_dot), chi the hysteresis factor (s/m)."""

from __future__ import annotations

from typing import Any

from .base import ContactLaw, softplus

#: Default hysteresis factor, s/m: restitution 0.9 at a 0.05 m/s reference impact speed.
DEFAULT_HYSTERESIS = 3.0


class HuntCrossley(ContactLaw):
    """F = K delta^n pos(1 + chi delta_dot): the damping grows with the penetration, so the force
    starts and ends at zero (Hunt and Crossley, J. Appl. Mech. 42, 1975)."""

    name = "hunt-crossley"
    damping_unit = "s/m"

    def default_damping(self, stiffness: float, exponent: float) -> float:
        return DEFAULT_HYSTERESIS

    def normal_force(self, elastic: Any, delta: Any, delta_dot: Any, damping: Any, eps: float,
                     stiffness: Any, exponent: Any) -> Any:
        return elastic * softplus(1 + damping * delta_dot, 1e-3)
