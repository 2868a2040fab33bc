"""Checking a speed on a model, outside any optimiser: periodic re-simulation on a fine grid, the
objective on it, and the ram speed over the model's own height window."""

from __future__ import annotations

import numpy as np

from .model import PressModel
from .objectives import get as get_objective
from .problem import SpeedProblem, in_window
from .result import SimResult
from .series import PIN_FORCES
from .drive import Drive, MotorCycle, motor_cycle
from .mechanism.ideal import ideal_inverse_dynamics, ideal_response
from .simulate import Integrator, SimulationError, simulate
from .speed import FourierSpeed

#: A response whose objective exceeds the rigid model's by this factor impacts (journals in free
#: flight): it is not searched for a periodic steady state (there is often none).
IMPACT_RATIO = 1.10
#: Output samples per cycle of a verification.
VERIFY_SAMPLES = 20001


def rigid_reference(problem: SpeedProblem, speed: FourierSpeed) -> SimResult:
    """The ideal press's response to `speed` on the verification grid (`VERIFY_SAMPLES` per cycle):
    the reference a re-simulation on a model with clearance is compared with."""
    return ideal_response(problem.press, problem.mechanism, speed, np.linspace(0.0, problem.period, VERIFY_SAMPLES))


def ram_speed_deviation(sim: SimResult, problem: SpeedProblem) -> float | None:
    """max |v - ram_speed| over the samples at which the response's own ram is in the height window
    on the downstroke, m/s; None when no sample is."""
    mask = in_window(problem, sim.theta, sim.ram_height)
    return float(np.max(np.abs(sim.ram_velocity[mask] - problem.ram_speed))) if mask.any() else None


def ram_speed_violation(sim: SimResult, problem: SpeedProblem) -> float:
    """`ram_speed_deviation` - tol, m/s (<= 0: within tolerance; -tol when no sample is in the window)."""
    dev = ram_speed_deviation(sim, problem)
    return -problem.tol if dev is None else dev - problem.tol


def ram_speed_error(sim: SimResult, problem: SpeedProblem) -> float:
    """`ram_speed_deviation` relative to |ram_speed| (0 when no sample is in the window)."""
    dev = ram_speed_deviation(sim, problem)
    return 0.0 if dev is None else dev / abs(problem.ram_speed)


def window_times(sim: SimResult, problem: SpeedProblem) -> tuple[float, float]:
    """First and last sample time at which the response's ram is in the window, s (NaN if never)."""
    t = sim.t[in_window(problem, sim.theta, sim.ram_height)]
    return (float(t[0]), float(t[-1])) if t.size else (float("nan"), float("nan"))


def settled_state(model: PressModel, speed: FourierSpeed, cycles: int, rtol: float) -> np.ndarray:
    """Scaled state after `cycles` cycles from rest (CVODES at `rtol`)."""
    r = simulate(model, speed, cycles=cycles, integrator=Integrator("cvodes", rtol), n_out=cycles + 1, work=False)
    return r.states[:, -1] / model.x_scale


def cycle_from(model: PressModel, speed: FourierSpeed, rtol: float, x0: np.ndarray, cycle: int,
               reason: str) -> SimResult:
    """One cycle from the scaled state `x0` on the fine grid, standing in for a periodic response that
    was not found or not searched for: ``stats["periodic"]`` records which cycle from rest it is and why."""
    sim = simulate(model, speed, integrator=Integrator("cvodes", rtol), n_out=VERIFY_SAMPLES, x0=x0, work=False)
    sim.stats["periodic"] = {"found": False, "reason": reason, "cycle": cycle}
    return sim


def verify_speed(model: PressModel, speed: FourierSpeed, rtol: float = 1e-9,
                 x0: np.ndarray | None = None) -> SimResult:
    """Periodic re-simulation (CVODES, `VERIFY_SAMPLES` samples per cycle, no work quadratures: the
    search's settled cycle is the answer), its search started from the scaled state `x0` (default the
    model's). When the response has no periodic steady state (an
    impacting, chaotic one), the 6th cycle from rest is returned and ``stats["periodic"]`` says so."""
    try:
        return simulate(model, speed, periodic=True, integrator=Integrator("cvodes", rtol), n_out=VERIFY_SAMPLES,
                        x0=x0, work=False)
    except SimulationError as err:
        return cycle_from(model, speed, rtol, settled_state(model, speed, 5, rtol), cycle=6,
                          reason=str(err).splitlines()[0])


def is_periodic(sim: SimResult) -> bool | str:
    """True when the response is a periodic steady state, else the reason it is not."""
    info = sim.stats.get("periodic", {})
    return True if info.get("found", True) else str(info.get("reason", "not periodic"))


def screen(model: PressModel, speed: FourierSpeed, reference: float, objective: str,
           rtol: float = 1e-7, drive: Drive | None = None) -> tuple[SimResult, float]:
    """Response of `speed` on `model` and its objective over `reference` (the rigid model's value).

    A screen first: the 4th cycle from rest. If that impacts (ratio > `IMPACT_RATIO`), it is the
    answer and no periodic state is searched for (there is often none: the journals' free flight is
    chaotic, and the failing search took ~25 s at T = 0.8 s on the rigid rod, minutes on the flexible
    one). Otherwise the periodic response (`verify_speed`) from the screen's state.
    Returns (sim, ratio); `is_periodic(sim)` tells which. `drive`: the problem's, for an objective
    that reads the motor."""
    def value(sim: SimResult) -> float:
        return get_objective(objective).value(sim, drive)

    if model.is_rigid:  # closed form, nothing to settle
        sim = verify_speed(model, speed, rtol)
        return sim, value(sim) / reference
    x3 = settled_state(model, speed, 3, rtol)
    sim = cycle_from(model, speed, rtol, x3, cycle=4, reason="")
    ratio = value(sim) / reference
    if ratio > IMPACT_RATIO:
        sim.stats["periodic"]["reason"] = (f"not searched: the objective is {ratio:.3g} x the rigid press's "
                                           f"(impacts or rod vibration; 4th cycle from rest)")
        return sim, ratio
    sim = verify_speed(model, speed, rtol, x0=x3)
    return sim, value(sim) / reference


#: The screen `settled_response` runs before a periodic search: cycles from rest, their rtol, and the
#: change of the scaled state over the last of them above which the response has not settled (1e-2:
#: 1 micrometre at a 0.1 mm clearance). At rtol 1e-7 the rigid rod's impacting 75 spm response changed
#: by 2.7e-4 a cycle (it is periodic: the search at 1e-9 settles in 4 cycles), the flexible rod's by 0.1-0.7.
SETTLE_SCREEN_CYCLES, SETTLE_SCREEN_RTOL, SETTLE_SCREEN_CHANGE = 6, 1e-7, 1e-2


def settled_response(problem: SpeedProblem, model: PressModel, speed: FourierSpeed, rtol: float = 1e-9,
                     reference: float | None = None) -> SimResult:
    """The response of `speed` on `model` that a simulation reports: the periodic one (`verify_speed`
    at `rtol`) unless a screen shows there is none to find.

    The screen: up to `SETTLE_SCREEN_CYCLES` cycles from rest at `SETTLE_SCREEN_RTOL`, integrated
    to their ends only; the first whose change of state (max-norm, scaled) is within
    `SETTLE_SCREEN_CHANGE` ends it. When none is, and the last changes it by at least half as much as
    the one three cycles before, the last cycle is integrated again at `rtol` from the screen's
    state; if its objective exceeds `reference` (the ideal press's) by `IMPACT_RATIO`, it is the
    answer and ``stats["periodic"]`` says why. On the flexible rod at 75 spm the rigid design's
    response changed by 0.11-0.45 a cycle for 9 cycles, a cycle cost 31 s at rtol 1e-9 (1.5 s at
    1e-7), and the periodic search ran over 28 minutes.

    Otherwise the periodic search starts from the screen's last state when one more screened cycle
    does not impact (within `IMPACT_RATIO` of `reference`): it skips the transient from rest at
    `rtol` (the journals fall from the bearings' centres and hit), 3.1 s against 32 s on the flexible
    rod at press75's optimum, the peak 5e-8 apart. An impacting response's search starts from rest,
    as it always did: its peaks depend on where the search starts (on the rigid rod's impacting rigid
    design, from the screen's state the slider force's peak moved 5 %, both within the search's
    tolerance). `reference` defaults to the ideal press's objective (`rigid_reference`)."""
    if model.is_rigid:
        return verify_speed(model, speed, rtol)
    if reference is None:
        reference = problem.objective_value(rigid_reference(problem, speed))
    n, screen = SETTLE_SCREEN_CYCLES, Integrator("cvodes", SETTLE_SCREEN_RTOL)
    x, change = np.asarray(model.x0, float), []
    for _ in range(n):  # cycle by cycle: a response that settles stops the screen after 2 (0.25 s at 75 spm)
        start = x
        run = simulate(model, speed, cycles=1, integrator=screen, n_out=2, x0=start, work=False)
        x = run.states[:, -1] / np.asarray(model.x_scale, float)
        change.append(float(np.max(np.abs(x - start))))
        if change[-1] <= SETTLE_SCREEN_CHANGE:
            break
    else:
        if change[-1] > 0.5 * change[-4]:
            sim = cycle_from(model, speed, rtol, start, cycle=n, reason="")
            ratio = problem.objective_value(sim) / reference if reference > 0 else np.inf
            if ratio > IMPACT_RATIO:
                sim.stats["periodic"]["reason"] = (
                    f"not searched: the state's change over a cycle from rest was {change[-4]:.2g} after cycle "
                    f"{n - 3} and {change[-1]:.2g} after cycle {n} (scaled, rtol {SETTLE_SCREEN_RTOL:g}), and the "
                    f"objective is {ratio:.3g} x the ideal press's (impacts or rod vibration); cycle {n} from rest, "
                    f"its first {n - 1} at rtol {SETTLE_SCREEN_RTOL:g}")
                return sim
    probe = simulate(model, speed, cycles=1, integrator=screen, n_out=2001, x0=x, work=False)
    impacts = problem.objective_value(probe) > IMPACT_RATIO * reference
    return verify_speed(model, speed, rtol, x0=None if impacts else x)


def cap_excess(problem: SpeedProblem, peaks: dict[str, float]) -> dict[str, float]:
    """``{"max_pin_force": excess}`` when the larger crank-pin or wrist-pin peak of `peaks` (N, keyed by
    series name) exceeds `SpeedProblem.max_pin_force`, the excess a share of the cap; else empty."""
    cap = problem.max_pin_force
    pin = max((peaks.get(name, 0.0) for name in PIN_FORCES), default=0.0)
    return {"max_pin_force": pin / cap - 1.0} if cap is not None and pin > cap else {}


def limits_exceeded(problem: SpeedProblem, speed: FourierSpeed, sim: SimResult) -> dict[str, float]:
    """The problem's limits that `sim`, the response to `speed`, exceeds, each with its excess as a share
    of the limit (> 0): ``max_pin_force`` (the larger crank-pin or wrist-pin peak over
    `SpeedProblem.max_pin_force`) and, with a drive, ``drive_peak_torque``, ``drive_rms`` and
    ``drive_speed`` (the motor cycle's margins, `motor_cycle_of`, negated). Empty when every limit
    holds or none is set. An NLP holds them at its samples only: between them, and where the
    re-simulation's journals leave their walls, a limit can be exceeded (the 75 spm seed under a
    6000 N cap re-simulated at 6620 N, 2026-11-29), so an answer is verified only when this is empty."""
    out = cap_excess(problem, {name: sim.peak(name) for name in PIN_FORCES})
    if problem.drive is not None:
        motor = motor_cycle_of(problem, speed, sim)
        for name, margin in (("drive_peak_torque", motor.peak_torque_margin), ("drive_rms", motor.rms_margin),
                             ("drive_speed", motor.speed_margin)):
            if margin < 0.0:
                out[name] = -float(margin)
    return out


def describe_excess(limits: dict[str, float]) -> str:
    """`limits_exceeded`'s result in words ("" when empty)."""
    return "; ".join(f"the re-simulation exceeds {name} by {100 * excess:.3g} %" for name, excess in limits.items())


def unverified_reason(problem: SpeedProblem, speed: FourierSpeed, sim: SimResult) -> str:
    """Why `sim`, the response to `speed`, does not verify it ("" when it does): not periodic, the ram
    speed out of tolerance over the response's own window, or a limit exceeded (`limits_exceeded`)."""
    periodic = is_periodic(sim)
    if periodic is not True:
        return f"its re-simulation is not periodic ({periodic})"
    viol = ram_speed_violation(sim, problem)
    if viol > 0.0:
        return f"the re-simulated ram speed leaves its tolerance by {viol:.2g} m/s"
    return describe_excess(limits_exceeded(problem, speed, sim))


def motor_cycle_of(problem: SpeedProblem, speed: FourierSpeed, sim: SimResult) -> MotorCycle:
    """The problem's drive over one period of `sim`, the response to `speed` (its first period, from
    its first sample): the speed's crank motion, the response's crank torque, the ideal press's
    inertia about the crank."""
    keep = sim.t - sim.t[0] <= speed.period * (1 + 1e-12)
    t, theta = sim.t[keep], sim.theta[keep]
    _, omega, alpha = speed.evaluate(t)
    inertia = 2 * ideal_inverse_dynamics(problem.press, problem.mechanism, theta, 1.0, 0.0)["kinetic_energy"]
    return motor_cycle(problem.drive, t, omega, alpha, sim.torque[keep], inertia)
