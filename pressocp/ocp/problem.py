"""The speed-design optimal control problem, independent of any transcription."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _checks as chk
from ..design import check_ram_speed, check_window
from ..params import PressParams
from ..speed import DEFAULT_HARMONICS

OBJECTIVES = ("peak_torque", "peak_slider_normal_force", "peak_pin_force", "rms_torque")


@dataclass(frozen=True)
class SpeedProblem:
    """Minimise a peak load (epigraph) over a Fourier crank speed with a constant ram speed window.

    Parameters
    ----------
    params : PressParams
        The press.
    period : float
        Cycle time T, s.
    ram_speed : float
        Ram velocity in the window, m/s, negative and within `pressocp.design.ram_speed_range`.
    window : (float, float)
        (h1/H, h2/H) on the downstroke, 0 < h2 < h1 < 1; h(t1) = h1 H, t2 = t1 + (h1 - h2) H/|v|.
    objective : str
        One of `OBJECTIVES`: peak |torque|, peak |slider normal force|, peak pin force (the larger
        of the two joints), or the RMS torque.
    n_harmonics : int
        Harmonics of the speed, 1..50.
    ram_speed_tol : float or None
        Allowed |v - ram_speed| in the window, m/s; default 1 % of |ram_speed|.
    omega_min : float or None
        Lower bound on the crank speed, rad/s, in (0, 2 pi/T); default 5 % of the mean speed.
    omega_max, alpha_max : float or None
        Optional motor limits |omega| <= omega_max (rad/s), |alpha| <= alpha_max (rad/s^2).
    min_tension : float or None
        Lower bound on the rod's axial tension at both pins in the rigid model, N, below the
        weight of rod and slider. The slider hangs from the rod; a bound >= 0 forbids the
        joint-force reversal (tension to compression, the ram falling faster than g) that makes the
        journals cross their clearance and impact. A negative bound allows a shallow reversal, at
        most -min_tension of compression (at 75 spm 30 N of it already impacts: README,
        `benchmarks/bench_reversal.py`). Needs a press without process force (the forming load
        compresses the rod). None: no bound.
    """

    params: PressParams
    period: float = 1.0
    ram_speed: float = -0.1
    window: tuple[float, float] = (0.7, 0.3)
    objective: str = "peak_torque"
    n_harmonics: int = DEFAULT_HARMONICS
    ram_speed_tol: float | None = None
    omega_min: float | None = None
    omega_max: float | None = None
    alpha_max: float | None = None
    min_tension: float | None = None

    def __post_init__(self) -> None:
        T = chk.positive("period", self.period, "s")
        v = chk.finite("ram_speed", self.ram_speed)
        w0, w1 = check_window(self.window)
        object.__setattr__(self, "window", (w0, w1))
        chk.choice("objective", self.objective, OBJECTIVES)
        chk.integer("n_harmonics", self.n_harmonics, 1, 50)
        check_ram_speed(self.params, T, v, (w0, w1))
        if self.ram_speed_tol is not None:
            chk.in_open_interval("ram_speed_tol", self.ram_speed_tol, 0.0, abs(v), "m/s")
        wbar = 2 * np.pi / T
        if self.omega_min is not None:
            chk.in_open_interval("omega_min", self.omega_min, 0.0, wbar, "rad/s")
        if self.omega_max is not None:
            chk.in_open_interval("omega_max", self.omega_max, wbar, np.inf, "rad/s")
        if self.alpha_max is not None:
            chk.positive("alpha_max", self.alpha_max, "rad/s^2")
        if self.min_tension is not None:
            chk.in_open_interval("min_tension", self.min_tension, -np.inf, self.hanging_weight, "N")
            if self.params.process_force.force != 0.0:
                raise ValueError("min_tension needs process_force.force == 0: the forming load compresses the rod, "
                                 "so its axial force must change sign")

    @property
    def hanging_weight(self) -> float:
        """Weight of rod and slider, N: the static rod tension is about this."""
        return (self.params.slider_mass + self.params.rod_mass) * self.params.gravity

    @property
    def tol(self) -> float:
        """Allowed ram speed deviation, m/s."""
        return 0.01 * abs(self.ram_speed) if self.ram_speed_tol is None else float(self.ram_speed_tol)

    @property
    def omega_lower(self) -> float:
        """Lower crank speed bound, rad/s."""
        return 0.05 * 2 * np.pi / self.period if self.omega_min is None else float(self.omega_min)

    @property
    def window_duration(self) -> float:
        """t2 - t1, s."""
        return (self.window[0] - self.window[1]) * self.params.stroke / abs(self.ram_speed)
