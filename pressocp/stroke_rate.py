"""The highest stroke rate at which a press runs its job with a given servo drive.

"How fast can this press run this job with this motor?" At each stroke rate tried, the speed that
minimises the problem's objective (peak crank torque by default) is optimised on the target model
with the drive's limits and the pin-force cap left out of the NLP (`optimize_speed`), and
re-simulated. When that answer meets every limit on its re-simulation (the drive's peak-torque curve
with its power limit, top speed and continuous (RMS) rating, the pin-force cap, the ram speed in the
window), the rate holds. When it misses only limits an NLP can hold, the rate is optimised once more
with the drive's limits and the cap as constraints (`RateSearch.hold_limits`), and that answer's
re-simulation decides. The search steps the rate up (or down) from the problem's until the verdict
changes, then bisects to `RateSearch.tolerance_spm`, and finally tries the found rate plus
`RateSearch.check_step` to show which limit fails there.

Why two optimisations and not one: the unconstrained optimum is the cheap verdict where the drive
has room (one optimisation, no drive rows in the NLP), and a drive-constrained NLP at a rate the
ideal press cannot meet ends after its rigid stage with the shortfall named. Why not the first alone:
the minimum-crank-torque speed says nothing of the motor's own torque, which adds the rotor's inertia
reflected through the gear; where the crank's optimum is flat (press60 lifting its ram: 76.15 N m
at every rate) the motor's peak and RMS torque are whatever that optimum happens to be, so that
alone would call rates infeasible that the drive runs (docs/decisions/2026-12-02-rate-holds-the-drive.md).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from . import checks as chk
from .drive import MotorCycle
from .model import PressModel
from .ocp import OcpResult, Strategy, optimize_speed
from .problem import SpeedProblem
from .verify import limits_exceeded, motor_cycle_of, unverified_reason


@dataclass(frozen=True)
class RateSearch:
    """How `max_stroke_rate` searches.

    Attributes
    ----------
    tolerance_spm : float
        Width of the final bracket, strokes/min, > 0.
    step : float
        Factor by which the rate steps up (or down) from the problem's until feasibility changes, > 1.
    check_step : float
        Relative step above the found rate at which the answer is tried once more, to show the limit
        that fails there, in (0, 0.5).
    max_trials : int
        Most rates tried, 2..40, each one or two optimisations (the check above the found rate is one
        more).
    strategy : str or Strategy
        `optimize_speed`'s strategy at each rate.
    hold_limits : bool
        When a rate's unconstrained optimum misses only limits an NLP can hold (the drive's peak
        curve, top speed and RMS rating; the pin-force cap), optimise that rate again with them as
        constraints and judge the rate by that answer. False: one optimisation per rate, the
        unconstrained optimum's verdict stands (a rate can then be called infeasible that the
        drive runs).
    """

    tolerance_spm: float = 1.0
    step: float = 1.15
    check_step: float = 0.02
    max_trials: int = 12
    strategy: str | Strategy = "auto"
    hold_limits: bool = True

    def __post_init__(self) -> None:
        chk.convert_reals(self)
        chk.positive("tolerance_spm", self.tolerance_spm, "strokes/min")
        chk.in_open_interval("step", self.step, 1.0, 3.0)
        chk.in_open_interval("check_step", self.check_step, 0.0, 0.5)
        chk.integer("max_trials", self.max_trials, 2, 40)
        chk.instance("hold_limits", self.hold_limits, bool)


@dataclass
class RateTrial:
    """One stroke rate tried: its verified optimum and what it failed, if anything.

    Attributes
    ----------
    rate_spm : float
        Strokes per minute.
    feasible : bool
        Every limit held on the re-simulation.
    failed : dict
        Limits missed by the answer that decides the rate, by name, with the margin (a share of the
        rating; negative) or the reason (``verified``: why the optimum is not verified).
    margins : dict
        The motor's margins on the re-simulation (peak-curve, RMS, speed; shares) and the largest pin
        force (N), when the optimisation ran.
    peak_torque : float
        Verified peak crank torque, N m (nan when the problem at that rate is invalid).
    wall_time : float
        s, both optimisations when there were two.
    result : OcpResult or None
        The optimum that decides the rate (None when the problem at that rate is invalid).
    motor : MotorCycle or None
        Its motor cycle.
    held : bool
        The drive's limits and the pin-force cap were constraints of that optimum's NLP (the
        unconstrained optimum missed one of them; `RateSearch.hold_limits`).
    unconstrained_failed : dict
        With `held`: what the unconstrained optimum missed, as `failed`.
    """

    rate_spm: float
    feasible: bool
    failed: dict
    margins: dict = field(default_factory=dict)
    peak_torque: float = float("nan")
    wall_time: float = 0.0
    result: OcpResult | None = field(default=None, repr=False)
    motor: MotorCycle | None = field(default=None, repr=False)
    held: bool = False
    unconstrained_failed: dict = field(default_factory=dict)

    @property
    def optimisations(self) -> int:
        """Optimisations run at this rate: 0 (invalid problem), 1, or 2 (`held`)."""
        return 0 if self.result is None else 1 + self.held

    def summary(self) -> dict:
        """Plain data."""
        return {"rate_spm": self.rate_spm, "feasible": self.feasible, "failed": self.failed, "margins": self.margins,
                "peak_torque": self.peak_torque, "wall_time": self.wall_time, "held": self.held,
                "unconstrained_failed": self.unconstrained_failed}


@dataclass
class RateResult:
    """The highest feasible stroke rate found.

    Attributes
    ----------
    rate_spm : float or None
        The highest rate tried at which every limit held (None: none of those tried). When the check
        above the bracket's feasible end holds too (the verdicts are not monotone in the rate), the
        check is repeated above it, within `RateSearch.max_trials` + 1 rates.
    best : RateTrial or None
        The trial at that rate.
    above : RateTrial or None
        The trial at `rate_spm` x (1 + check_step): the limit that fails just above (it is `best`
        itself when the checks ran out of rates while holding).
    trials : list of RateTrial
        Every rate tried, in order.
    wall_time : float
        s.
    """

    rate_spm: float | None
    best: RateTrial | None
    above: RateTrial | None
    trials: list[RateTrial]
    wall_time: float

    def summary(self) -> dict:
        """Plain data: the rate, its trial and the one above, and every trial."""
        return {"max_stroke_rate_spm": self.rate_spm, "best": None if self.best is None else self.best.summary(),
                "above": None if self.above is None else self.above.summary(),
                "trials": [t.summary() for t in self.trials], "wall_time": self.wall_time}


#: What a trial's `failed` names that an NLP can hold as constraints (`RateSearch.hold_limits`).
HOLDABLE = frozenset({"peak_torque_margin", "rms_margin", "speed_margin", "max_pin_force"})
#: `pressocp.verify.limits_exceeded`'s names of the limits -> a trial's ``failed`` keys (a drive's
#: margins, or the pin-force cap's excess negated: < 0 when failed).
LIMIT_KEYS = {"drive_peak_torque": "peak_torque_margin", "drive_rms": "rms_margin", "drive_speed": "speed_margin",
              "max_pin_force": "max_pin_force"}


def judge(rate_spm: float, problem: SpeedProblem, solved: SpeedProblem, result: OcpResult) -> RateTrial:
    """`result`, the optimum of `solved` (`problem` at `rate_spm`, with or without its drive and
    pin-force cap in the NLP), checked on its re-simulation against `problem`'s drive and cap."""
    motor = motor_cycle_of(problem, result.speed, result.simulation)
    pin = max(result.peaks["crank_pin_force"], result.peaks["wrist_pin_force"])
    margins = {"peak_torque_margin": motor.peak_torque_margin, "rms_margin": motor.rms_margin,
               "speed_margin": motor.speed_margin, "max_pin_force": pin}
    exceeded = limits_exceeded(problem, result.speed, result.simulation)  # the verification's own check
    failed: dict = {key: -exceeded[name] for name, key in LIMIT_KEYS.items() if name in exceeded}
    if not result.verified:  # why: not converged (IPOPT's status), or what the re-simulation shows
        failed["verified"] = (unverified_reason(solved, result.speed, result.simulation) if result.success
                              else f"not converged ({result.status})") or result.status
    return RateTrial(rate_spm, not failed, failed, margins, result.peak_torque, 0.0, result, motor)


def try_rate(problem: SpeedProblem, model: PressModel | None, rate_spm: float, strategy: str | Strategy = "auto",
             progress: bool = False, hold_limits: bool = True) -> RateTrial:
    """`problem` at `rate_spm`: its verified optimum without the drive's limits and the pin-force cap
    in the NLP, checked against them on its re-simulation; when it misses only those limits and
    `hold_limits`, the optimum with them as constraints, checked the same way (see the module)."""
    t0 = time.perf_counter()
    try:
        at_rate = problem.replace(period=60.0 / rate_spm)
        free = at_rate.replace(drive=None, max_pin_force=None)
    except ValueError as err:  # e.g. the window takes too much of a shorter period, or the drive's top speed
        return RateTrial(rate_spm, False, {"problem": str(err)}, wall_time=time.perf_counter() - t0)
    spec_model = None if model is None else model.spec.build(at_rate.press, at_rate.n_harmonics)
    trial = judge(rate_spm, at_rate, free, optimize_speed(free, spec_model, strategy=strategy, progress=progress))
    if hold_limits and trial.failed and set(trial.failed) <= HOLDABLE:
        first = trial.failed
        held = optimize_speed(at_rate, spec_model, strategy=strategy, progress=progress)
        trial = judge(rate_spm, at_rate, at_rate, held)
        trial.held, trial.unconstrained_failed = True, first
    trial.wall_time = time.perf_counter() - t0
    return trial


def max_stroke_rate(problem: SpeedProblem, model: PressModel | None = None, search: RateSearch = RateSearch(),
                    progress: bool = False) -> RateResult:
    """The highest stroke rate at which `problem`'s press meets its drive's limits (see the module).

    Parameters
    ----------
    problem : SpeedProblem
        The job at a first rate to try (its period), with a drive (`SpeedProblem.drive`).
    model : PressModel, optional
        Target model; default both clearances and a rigid rod. Rebuilt at each rate's harmonics.
    search : RateSearch
        Bracket, steps and the number of optimisations.
    progress : bool
        Progress bars of each optimisation.

    Returns
    -------
    RateResult
    """
    chk.instance("problem", problem, SpeedProblem)
    chk.instance("search", search, RateSearch)
    if problem.drive is None:
        raise ValueError("problem.drive must be a Drive: the stroke rate is limited by the drive's ratings")
    t0 = time.perf_counter()
    trials: list[RateTrial] = []

    def trial(rate: float) -> RateTrial:
        found = next((t for t in trials if np.isclose(t.rate_spm, rate, rtol=1e-9)), None)
        if found is None:
            found = try_rate(problem, model, rate, search.strategy, progress, search.hold_limits)
            trials.append(found)
        return found

    rate = problem.stroke_rate_spm
    first = trial(rate)
    good, bad = (rate, None) if first.feasible else (None, rate)
    while (good is None or bad is None) and len(trials) < search.max_trials:
        rate = rate * search.step if bad is None else rate / search.step
        if trial(rate).feasible:
            good = rate if good is None else max(good, rate)
        else:
            bad = rate if bad is None else min(bad, rate)
    while good is not None and bad is not None and bad - good > search.tolerance_spm \
            and len(trials) < search.max_trials:
        mid = 0.5 * (good + bad)
        if trial(mid).feasible:
            good = mid
        else:
            bad = mid
    above = None
    while good is not None:  # until the check above fails: its +check_step shows the limit that binds
        above = trial(good * (1 + search.check_step))
        if not above.feasible or len(trials) > search.max_trials:
            break
        good = above.rate_spm
    feasible = [t for t in trials if t.feasible]
    best = max(feasible, key=lambda t: t.rate_spm) if feasible else None
    return RateResult(None if best is None else best.rate_spm, best, above, trials, time.perf_counter() - t0)
