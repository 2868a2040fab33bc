"""The speed-design problem: what is asked of the crank speed, independent of how it is solved.

`SpeedProblem` is the one statement of the request (press, cycle time, ram speed and working
window, objective, harmonics, tolerances and limits). `pressocp.design.design_speed` (the
kinematic design) and `pressocp.ocp.optimize_speed` (the optimal speed) both take it.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from . import checks as chk
from .objectives import OBJECTIVES
from .drive import Drive
from .mechanism import SLIDER_CRANK, Mechanism, mechanism_from_dict, mechanism_to_dict
from .mechanism.ideal import ideal_kinematics
from .params import PressParams
from .units import format_force
from .speed import DEFAULT_HARMONICS

#: The working window may take at most this share of the period.
MAX_WINDOW_SHARE = 0.8
#: The mean crank speed in the window may be at most this multiple of the mean speed 2 pi / T.
MAX_WINDOW_SPEED_RATIO = 3.0
#: An omega_max above this many times the mean crank speed is suspected of being in rpm.
MAX_OMEGA_RATIO = 20.0
#: A stroke rate below this many strokes per minute is suspected of being a crank speed in rad/s (75 spm
#: is 7.85 rad/s), or a period given in strokes per minute.
MIN_PLAUSIBLE_SPM = 15.0


def check_window(window: Any) -> tuple[float, float]:
    """Validate a working window (h1/H, h2/H) on the downstroke: 0 < h2 < h1 < 1."""
    try:
        w0, w1 = (float(x) for x in window)
    except (TypeError, ValueError):
        raise ValueError(f"window must be a pair (h1/H, h2/H), got {window!r}") from None
    chk.in_open_interval("window[0] (h1/H)", w0, 0.0, 1.0)
    chk.in_open_interval("window[1] (h2/H)", w1, 0.0, 1.0)
    if not w1 < w0:
        raise ValueError(f"window must be (h1/H, h2/H) with h2/H < h1/H on the downstroke, got {window!r}")
    return w0, w1


def ram_speed_range(press: PressParams, period: float, window: tuple[float, float],
                    mechanism: Mechanism = SLIDER_CRANK) -> tuple[float, float]:
    """Reachable ram speeds (m/s, negative) for a window and a period.

    The window must take at most `MAX_WINDOW_SHARE` of the period (slow limit) and the crank may
    turn through it at most `MAX_WINDOW_SPEED_RATIO` times faster than its mean speed (fast limit).

    Returns
    -------
    (fastest, slowest) : tuple of float
        The allowed range is fastest <= ram_speed <= slowest < 0.
    """
    w0, w1 = window
    H = mechanism.stroke(press)
    dh = (w0 - w1) * H
    th0, th1 = mechanism.input_angle_at_height(press, np.array([w0, w1]) * H, "down")
    fastest = MAX_WINDOW_SPEED_RATIO * (2 * np.pi / period) * dh / (th1 - th0)
    slowest = dh / (MAX_WINDOW_SHARE * period)
    return -fastest, -slowest


#: Margin on the window's crank speed and acceleration needs before a speed limit is refused: the
#: needs are those of the ideal press, and clearances or a flexible rod shift them slightly.
LIMIT_MARGIN = 0.01


def window_crank_speeds(press: PressParams, ram_speed: float, tol: float, window: tuple[float, float],
                        n: int = 201, mechanism: Mechanism = SLIDER_CRANK) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Crank speeds the window needs on the ideal press: at each crank angle theta of the window, the
    ram speed |dh/dt| = omega |dh/dtheta| within ``|ram_speed| -+ tol`` needs omega in
    [(|v| - tol) / |dh/dtheta|, (|v| + tol) / |dh/dtheta|].

    Returns
    -------
    theta, lowest, highest : ndarray
        Crank angles across the window (rad) and the least and greatest crank speed there (rad/s).
    """
    th0, th1 = mechanism.input_angle_at_height(press, np.array(window) * mechanism.stroke(press), "down")
    theta = np.linspace(th0, th1, n)
    slope = np.abs(ideal_kinematics(press, mechanism, theta, 1.0)["ram_velocity"])  # |dh/dtheta|, m/rad
    v = abs(ram_speed)
    return theta, (v - tol) / slope, (v + tol) / slope


def check_speed_limits(problem: "SpeedProblem") -> None:
    """ValueError when the crank speed limits leave no speed that holds the ram speed over the window
    (on the ideal press, with `LIMIT_MARGIN`): omega_max below the speed the window needs somewhere,
    omega_min above it, or alpha_max below the least peak acceleration any such speed has (the speed
    must rise from its least value at the window's start to its least value at its end:
    |alpha| >= (lowest(end)^2 - highest(start)^2) / (2 x the window's crank angle)); and a drive's
    top speed below the window's need (`check_drive_speed`). Nothing is computed when none of the
    three limits nor a drive is given."""
    if problem.omega_max is None and problem.omega_min is None and problem.alpha_max is None \
            and problem.drive is None:
        return
    press, mechanism = problem.press, problem.mechanism
    theta, lowest, highest = window_crank_speeds(press, problem.ram_speed, problem.tol, problem.window,
                                                 mechanism=mechanism)
    if problem.drive is not None:
        check_drive_speed(problem, float(lowest.max()))
    where = lambda k: f"h = {float(ideal_kinematics(press, mechanism, theta[k])['ram_height']):.4g} m"  # noqa: E731
    v = f"{problem.ram_speed:g} m/s"
    if problem.omega_max is not None and problem.omega_max < (1 - LIMIT_MARGIN) * lowest.max():
        need = lowest.max()
        raise ValueError(f"omega_max must be in [{need:.4g}, inf) rad/s, got {problem.omega_max!r}: the crank must "
                         f"turn at {need:.4g} rad/s at {where(int(np.argmax(lowest)))} for the ram to move at {v} "
                         "in the window; raise omega_max or lower |ram_speed|")
    if problem.omega_min is not None and problem.omega_min > (1 + LIMIT_MARGIN) * highest.min():
        need = highest.min()
        raise ValueError(f"omega_min must be in (0, {need:.4g}] rad/s, got {problem.omega_min!r}: the crank must "
                         f"turn at most {need:.4g} rad/s at {where(int(np.argmin(highest)))} for the ram to "
                         f"move at {v} in the window")
    rise = (lowest[-1] ** 2 - highest[0] ** 2) / (2 * abs(theta[-1] - theta[0]))
    if problem.alpha_max is not None and rise > 0 and problem.alpha_max < (1 - LIMIT_MARGIN) * rise:
        raise ValueError(f"alpha_max must be in [{rise:.4g}, inf) rad/s^2, got {problem.alpha_max!r}: holding the "
                         f"ram at {v} over the window, the crank speed rises from {highest[0]:.4g} rad/s or less to "
                         f"{lowest[-1]:.4g} rad/s or more, which needs at least {rise:.4g} rad/s^2")


def check_drive_speed(problem: "SpeedProblem", window_need: float) -> None:
    """ValueError when the drive's top speed, brought to the crank, is below the mean crank speed or
    below `window_need`, the speed (rad/s) the window needs somewhere on the ideal press (with
    `LIMIT_MARGIN`; `window_crank_speeds`)."""
    d = problem.drive
    top = d.max_speed / d.gear_ratio
    need = max(2 * np.pi / problem.period, (1 - LIMIT_MARGIN) * window_need)
    if top < need:
        raise ValueError(f"drive.max_speed must be in [{need * d.gear_ratio:.4g}, inf) rad/s at gear_ratio "
                         f"{d.gear_ratio:g}, got {d.max_speed!r}: the crank must turn at {need:.4g} rad/s "
                         f"({'its mean speed' if need == 2 * np.pi / problem.period else 'in the window'}); "
                         "a faster motor or a smaller gear ratio")


def check_ram_speed(press: PressParams, period: float, ram_speed: float, window: tuple[float, float],
                    mechanism: Mechanism = SLIDER_CRANK) -> float:
    """Validate a window ram speed: negative and within `ram_speed_range` (ValueError otherwise)."""
    v = chk.finite("ram_speed", ram_speed)
    if v >= 0:
        raise ValueError(f"ram_speed must be negative (downstroke, dh/dt < 0), got {v!r} m/s")
    fastest, slowest = ram_speed_range(press, period, window, mechanism)
    if not fastest <= v <= slowest:
        raise ValueError(
            f"ram_speed must be in [{fastest:.4g}, {slowest:.4g}] m/s for period={period:g} s (stroke_rate_spm="
            f"{60 / period:.4g}), window="
            f"({window[0]:g}, {window[1]:g}), crank_radius={press.crank_radius:g} m (a stroke of {mechanism.stroke(press):g} m) "
            f"and rod_length={press.rod_length:g} m: the crank cannot deliver {v!r} m/s over that window at that period "
            f"(the window may take at most {MAX_WINDOW_SHARE:.0%} of the period and the crank may cross it at most "
            f"{MAX_WINDOW_SPEED_RATIO:g}x faster than its mean speed)"
        )
    return v


class ReversalWarning(UserWarning):
    """The rod's load must reverse every stroke, whatever the crank speed (`SpeedProblem.reversal_cause`):
    the journals will cross their clearances and impact."""


@dataclass(frozen=True)
class SpeedProblem:
    """Minimise a load over a Fourier crank speed, with the ram at constant speed in a window.

    Parameters
    ----------
    press : PressParams
        The press.
    period : float
        Cycle time T, s (60 / strokes per minute).
    ram_speed : float
        Ram velocity in the window, m/s, negative and within `ram_speed_range`.
    window : (float, float)
        (h1/H, h2/H) on the downstroke, 0 < h2 < h1 < 1: the ram speed holds at every instant at
        which the ram (of whichever model is solved or checked) is between h2 H and h1 H.
    objective : str
        A name in `pressocp.objectives.OBJECTIVES` (peak motor torque by default).
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
        rod's static tension (`static_tension`). The slider hangs from the rod; a bound >= 0
        forbids the joint-force reversal (tension to compression, the ram falling faster than g)
        that makes the journals cross their clearance and impact. None: no bound.
    max_pin_force : float or None
        Cap on the crank-pin and wrist-pin force magnitudes, N, held at every sample together with
        any objective (bearing rating). None: no cap.
    mechanism : Mechanism
        Keyword-only: the linkage (`pressocp.mechanism`) whose input crank the speed drives, the
        slider-crank by default; its slider-crank part is `press`.
    drive : Drive or None
        Keyword-only: the servo motor and gear (`pressocp.drive.Drive`) whose figures every result
        reports (motor torque and speed, against its ratings); None: no drive.
    max_tension : float or None
        Keyword-only: upper bound on the rod's axial tension at both pins in the rigid model, N,
        above the least static tension over the stroke (`static_tension`). With a counterbalance
        that lifts more than the ram and rod weigh, the rod is in compression at rest; a bound <= 0
        keeps it so (the joints loaded one way, upward) all cycle. None: no bound.
    counterbalance_range : (float, float) or None
        Keyword-only: optimise the counterbalance's force (`pressocp.params.Counterbalance.force`, N
        at bottom dead centre) in [low, high] together with the crank speed, its gas law as the
        press gives it. None: the press's counterbalance as it is.
    """

    press: PressParams
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
    max_pin_force: float | None = None
    mechanism: Mechanism = field(default=SLIDER_CRANK, kw_only=True, repr=False)
    drive: Drive | None = field(default=None, kw_only=True, repr=False)
    max_tension: float | None = field(default=None, kw_only=True)
    counterbalance_range: tuple[float, float] | None = field(default=None, kw_only=True)

    def __post_init__(self) -> None:
        chk.instance("press", self.press, PressParams)
        if not hasattr(self.mechanism, "linkage"):
            raise ValueError(f"mechanism must be a Mechanism (pressocp.mechanism), got {type(self.mechanism).__name__}")
        self.mechanism.check_press(self.press)
        if self.drive is not None:
            chk.instance("drive", self.drive, Drive)
        chk.convert_reals(self)
        T = chk.positive("period", self.period, "s")
        v = chk.finite("ram_speed", self.ram_speed)
        w0, w1 = check_window(self.window)
        object.__setattr__(self, "period", T)
        object.__setattr__(self, "window", (w0, w1))
        chk.choice("objective", self.objective, tuple(OBJECTIVES))
        if OBJECTIVES[self.objective].drive and self.drive is None:
            raise ValueError(f"objective {self.objective!r} reads the motor: it needs a drive (SpeedProblem.drive, "
                             "a [drive] table in a scenario)")
        chk.integer("n_harmonics", self.n_harmonics, 1, 50)
        check_ram_speed(self.press, T, v, (w0, w1), self.mechanism)
        if self.ram_speed_tol is not None:
            chk.in_open_interval("ram_speed_tol", self.ram_speed_tol, 0.0, abs(v), "m/s")
        spm = self.stroke_rate_spm
        if spm < MIN_PLAUSIBLE_SPM:
            chk.suspect(f"period = {T:.4g} s is {spm:.3g} strokes/min (stroke_rate_spm), slow for a servo press "
                        f"(below {MIN_PLAUSIBLE_SPM:g}): a crank speed in rad/s? {spm:.3g} rad/s is "
                        f"{spm * 60.0 / (2 * np.pi):.3g} strokes/min (period {2 * np.pi / spm:.3g} s); "
                        f"or a period in strokes/min? {T:.3g} strokes/min is a period of {spm:.3g} s")
        wbar = 2 * np.pi / T
        if self.omega_min is not None:
            chk.in_open_interval("omega_min", self.omega_min, 0.0, wbar, "rad/s")
        if self.omega_max is not None:
            w = chk.in_open_interval("omega_max", self.omega_max, wbar, np.inf, "rad/s")
            if w > MAX_OMEGA_RATIO * wbar:
                chk.suspect(f"omega_max = {w:g} rad/s is {w / wbar:.3g} x the mean crank speed ({wbar:.4g} rad/s): a "
                            f"value in rpm? {w:g} rpm is {w * 2 * np.pi / 60:.4g} rad/s")
        if self.alpha_max is not None:
            chk.positive("alpha_max", self.alpha_max, "rad/s^2")
        low, high = self.static_tension
        if self.min_tension is not None:
            chk.in_open_interval("min_tension", self.min_tension, -np.inf, low, "N (the rod's least static tension: "
                                 "hanging weight less counterbalance and process force)")
        if self.counterbalance_range is not None:
            lo, hi = check_counterbalance_range(self.counterbalance_range, self.hanging_weight)
            object.__setattr__(self, "counterbalance_range", (lo, hi))
        if self.max_tension is not None:
            chk.in_open_interval("max_tension", self.max_tension, high, np.inf, "N (the rod's greatest static tension: "
                                 "hanging weight less the counterbalance)")
        if self.max_pin_force is not None:
            chk.in_open_interval("max_pin_force", self.max_pin_force, self.hanging_weight, np.inf, "N")
        check_speed_limits(self)

    def objective_value(self, response: Any) -> float:
        """The problem's objective on a response (a `SimResult` over one period, both ends included,
        or a mapping of output arrays with ``t``), with the problem's drive."""
        return OBJECTIVES[self.objective].value(response, self.drive)

    # Derived values ------------------------------------------------------------------------------
    @property
    def stroke_rate_spm(self) -> float:
        """Strokes per minute, 60 / T."""
        return 60.0 / self.period

    @property
    def hanging_weight(self) -> float:
        """Weight of rod and slider, N: the static rod tension is about this."""
        return (self.press.slider_mass + self.press.rod_mass) * self.press.gravity

    @property
    def static_tension(self) -> tuple[float, float]:
        """(least, greatest) axial tension of the rod with the ram at rest in the stroke, N: the
        hanging weight less the counterbalance's lift (greatest at bottom dead centre, least at the
        top), the least also less the process force's largest value (it acts in the working window,
        where the ram moves at constant speed)."""
        H, cb, pf = self.stroke, self.press.counterbalance, self.press.process_force
        W = self.hanging_weight
        forming = pf.peak
        return W - cb.force_at(0.0) - forming, W - cb.force_at(H)

    def free_parameters(self) -> dict[str, tuple[float, float]]:
        """Press parameters optimised with the speed, by dotted name, with their (low, high) ranges
        (`counterbalance_range`)."""
        return {} if self.counterbalance_range is None else {"counterbalance.force": self.counterbalance_range}

    def lifted(self) -> "SpeedProblem":
        """This problem with the counterbalance at the top of its `counterbalance_range` (itself
        without one): the most the optimiser can lift the ram with."""
        if self.counterbalance_range is None:
            return self
        top = self.press.with_value("counterbalance.force", self.counterbalance_range[1])
        return self.replace(press=top, counterbalance_range=None)

    def reversal_side(self) -> str | None:
        """The sign the rod's axial load can keep all cycle: "tension" when the ram hangs from it
        (`static_tension` > 0 at every height, the process force included), "compression" when the
        counterbalance lifts more than ram and rod weigh at every height, None when neither: the
        load must reverse every stroke, and the journals cross their clearances."""
        low, high = self.static_tension
        if low > 0.0:
            return "tension"
        if high < 0.0:
            return "compression"
        return None

    def without_reversal(self, margin: float) -> "SpeedProblem | None":
        """This problem with the rod's axial load held on its `reversal_side` at `margin` (a share) of
        its static value: tension >= margin x the least static tension, or tension <= margin x the
        greatest (negative); None when the load must reverse."""
        side = self.reversal_side()
        low, high = self.static_tension
        if side == "tension":
            return self.replace(min_tension=margin * low)
        if side == "compression":
            return self.replace(max_tension=margin * high)
        return None

    def reversal_cause(self) -> str:
        """Why the rod's load must reverse every stroke, and the remedy ("" when it need not)."""
        if self.reversal_side() is not None:
            return ""
        W, cb, pf = self.hanging_weight, self.press.counterbalance, self.press.process_force
        forming = pf.peak
        low, high = self.static_tension
        parts = [f"ram and rod hang from the rod with {format_force(W, 4)}"]
        if cb.force > 0.0:
            parts.append(f"the counterbalance lifts {format_force(cb.force_at(self.stroke), 4)} to {format_force(cb.force, 4)} over "
                         "the stroke")
        if forming > 0.0:
            parts.append(f"the process force reaches {format_force(forming, 4)}")
        need = 1.2 * W * (1.0 + self.stroke / cb.gas_length) ** cb.exponent
        return (f"the rod's load must change sign every stroke ({'; '.join(parts)}: at rest it is {format_force(low, 4)} at "
                f"least and {format_force(high, 4)} at most), so the joint forces reverse and the journals cross their "
                f"clearances whatever the crank speed. A counterbalance that lifts more than ram and rod weigh at "
                f"every height keeps the joints loaded one way: press.counterbalance.force of about {format_force(need, 4)} "
                f"or more (at bottom dead centre, with its gas_length and exponent)")

    @property
    def tol(self) -> float:
        """Allowed ram speed deviation, m/s."""
        return 0.01 * abs(self.ram_speed) if self.ram_speed_tol is None else float(self.ram_speed_tol)

    @property
    def omega_lower(self) -> float:
        """Lower crank speed bound, rad/s."""
        return 0.05 * 2 * np.pi / self.period if self.omega_min is None else float(self.omega_min)

    @property
    def stroke(self) -> float:
        """The ram's stroke H on the problem's mechanism, m."""
        return self.mechanism.stroke(self.press)

    @property
    def window_heights(self) -> tuple[float, float]:
        """(h1 H, h2 H): ram heights at which the window starts and ends, m."""
        return self.window[0] * self.stroke, self.window[1] * self.stroke

    @property
    def window_duration(self) -> float:
        """t2 - t1, s."""
        return (self.window[0] - self.window[1]) * self.stroke / abs(self.ram_speed)

    def replace(self, **changes: Any) -> "SpeedProblem":
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)

    # Saving ------------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain-data form (JSON-safe): ``{"press": ..., field: value, ...}``."""
        d = {k: v for k, v in asdict(self).items() if k not in ("press", "mechanism", "drive")}
        d["window"] = list(self.window)
        if self.counterbalance_range is not None:
            d["counterbalance_range"] = list(self.counterbalance_range)
        if self.mechanism != SLIDER_CRANK:
            d["mechanism"] = mechanism_to_dict(self.mechanism)
        if self.drive is not None:
            d["drive"] = self.drive.to_dict()
        return {"press": self.press.to_dict(), **d}

    @classmethod
    def from_dict(cls, data: dict) -> "SpeedProblem":
        """Inverse of `to_dict`."""
        d = dict(data)
        press = PressParams.from_dict(d.pop("press", {}))
        for key in ("window", "counterbalance_range"):
            if d.get(key) is not None:
                d[key] = tuple(d[key])
        if "mechanism" in d:
            d["mechanism"] = mechanism_from_dict(d["mechanism"])
        if d.get("drive") is not None:
            d["drive"] = Drive(**d["drive"])
        return cls(press, **d)


#: A counterbalance range reaching above this many hanging weights is suspected of a unit slip (kN).
MAX_COUNTERBALANCE_RATIO = 1000.0


def check_counterbalance_range(value: Any, hanging_weight: float) -> tuple[float, float]:
    """(low, high) of a counterbalance's force, N: two numbers, 0 <= low < high."""
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"counterbalance_range must be two numbers [low, high] in N, got {value!r}") from None
    chk.nonnegative("counterbalance_range[0]", lo, "N")
    chk.in_open_interval("counterbalance_range[1]", hi, lo, np.inf, "N")
    if hi > MAX_COUNTERBALANCE_RATIO * hanging_weight:
        chk.suspect(f"counterbalance_range reaches {hi:g} N, {hi / hanging_weight:.3g} x the hanging weight of ram and "
                    f"rod ({hanging_weight:.4g} N): a value in mN? {hi:g} mN is {hi / 1000:g} N")
    return lo, hi


def in_window(problem: SpeedProblem, theta: np.ndarray, ram_height: np.ndarray) -> np.ndarray:
    """Mask of the samples at which a ram is in the working window: on the downstroke (crank angle
    in [0, pi) modulo 2 pi) and between h2 H and h1 H."""
    h1, h2 = problem.window_heights
    down = np.mod(np.asarray(theta), 2 * np.pi) < problem.mechanism.bottom_dead_centre(problem.press)
    h = np.asarray(ram_height)
    return down & (h >= h2) & (h <= h1)
