"""What the transcriptions of models with states share: the warm start (the states at the
transcription's times along the periodic response), the working window placed on the model's own ram, the
contact-keeping constraint, the constraints on the output samples, and the NLP solve that turns
into a `StageResult`."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from .. import checks as chk
from ..model import PressModel
from ..objectives import get as get_objective
from ..problem import SpeedProblem
from ..simulate import Integrator, SimulationError, integrate, periodic_orbit
from ..speed import FourierSpeed
from ..verify import settled_state
from ..ipopt_options import IPOPT_CARRIED_START, IPOPT_WARM
from .nlp import (Constraints, NlpData, NlpRun, add_dense_speed_bounds, add_drive_limits, add_objective, add_pin_cap,
                  crank_motion, crank_rows, needed_outputs, objective_scale, parameter_symbols, solve_nlp, with_motor)
from .stage import NlpPoint, StageResult, Transcription, WarmStart, settings_repr

#: Outputs every state transcription samples besides the objective's: the ram's own motion.
RAM_OUTPUTS = ("ram_height", "ram_velocity")


def warm_states(model: PressModel, start: WarmStart, times: np.ndarray, rtol: float) -> tuple[np.ndarray, dict]:
    """Scaled states at `times` (the first 0) along the start speed's periodic response on `model`
    (`periodic_orbit` by CVODES at `rtol`, its search started from ``start.x0`` when given: one cycle
    then), or when none is found along the cycle after three from rest. Returns (nx x len(times)
    states, facts for the stage record)."""
    x_start = None if start.x0 is None else np.asarray(start.x0, float)
    try:
        X, info = periodic_orbit(model, start.speed, times, Integrator("cvodes", rtol), x_start=x_start)
        return X, {"periodic_warm_start": True, "settle_cycles": info["cycles"], "newton_steps": info["newton"]}
    except SimulationError as err:
        x0 = settled_state(model, start.speed, 3, rtol)
        return states_at(model, start.speed, x0, times, rtol), {"periodic_warm_start": False,
                                                                 "reason": str(err).splitlines()[0]}


def states_at(model: PressModel, speed: FourierSpeed, x_start: np.ndarray, times: np.ndarray,
              rtol: float = 1e-8) -> np.ndarray:
    """Scaled states at ``times`` (the first 0), integrated by CVODES from ``x_start`` at t = 0
    (nx x len(times))."""
    x_start = np.asarray(x_start, float)[:, None]
    if len(times) == 1:
        return x_start
    X, _, _ = integrate(model, Integrator("cvodes", rtol), x_start[:, 0], model.parameters(speed),
                        np.asarray(times)[1:], work=False)
    return np.hstack([x_start, X])


def contact_outputs(model: PressModel, min_eccentricity: float | None) -> tuple[str, ...]:
    """Output names of the contact-keeping constraint: the eccentricity of every clearance joint
    when `min_eccentricity` is given (checked: in [0, 1]), else none."""
    if min_eccentricity is None:
        return ()
    chk.in_closed_interval("min_eccentricity", min_eccentricity, 0.0, 1.0)
    return tuple(f"{j}_eccentricity" for j in model.clearance)


def sample_outputs(problem: SpeedProblem, model: PressModel, min_eccentricity: float | None) -> tuple[str, ...]:
    """Every output a state transcription samples, each once: objective, pin forces under a cap, the
    ram's height and velocity, and the eccentricities kept on the walls."""
    return needed_outputs(problem, get_objective(problem.objective),
                          RAM_OUTPUTS + contact_outputs(model, min_eccentricity))


def window_band(problem: SpeedProblem, speed: FourierSpeed, ram_height: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Indices of the samples that bracket the working window of the warm start's ram (the model's
    own, ``ram_height`` at ``times``) on the downstroke: from the last sample at or above h1 H before
    it to the first at or below h2 H after it. The ram speed is held at all of them and the phase at
    the two ends (`add_window_samples`): nothing more is constrained than the window and less than a
    sample spacing on each side."""
    h1, h2 = problem.window_heights
    down = np.mod(speed.theta(times), 2 * np.pi) < np.pi
    within = np.nonzero(down & (ram_height < h1) & (ram_height > h2))[0]
    if within.size < 1 or within[0] == 0 or within[-1] == times.size - 1:
        raise ValueError("the warm start's ram does not pass the working window inside the sampled period: "
                         "check the start speed")
    return np.arange(within[0] - 1, within[-1] + 2)


def add_window_samples(cons: Constraints, problem: SpeedProblem, y: Mapping, inside: np.ndarray,
                       backoff: float) -> None:
    """The phase: the model's ram is at or above h1 H at the first sample of `inside` (`window_band`)
    and at or below h2 H at the last, so every instant at which it is in the window lies between
    them; and its speed within ``backoff`` x tol at all of them, the two ends included (so that the
    speed is held on both sides of the instants at which the ram crosses h1 H and h2 H)."""
    P = problem
    h1, h2 = P.window_heights
    cons.add((y["ram_velocity"][:, inside.tolist()] - P.ram_speed) / P.tol, -backoff, backoff, "ram_speed_samples")
    cons.add((y["ram_height"][:, int(inside[0])] - h1) / P.stroke, 0.0, np.inf, "window_phase")
    cons.add((y["ram_height"][:, int(inside[-1])] - h2) / P.stroke, -np.inf, 0.0, "window_phase")


def keep_contact(cons: Constraints, y: Mapping, model: PressModel, min_eccentricity: float | None) -> None:
    """Every clearance joint's eccentricity ratio >= `min_eccentricity` at every sample (if given)."""
    for name in contact_outputs(model, min_eccentricity):
        cons.add(y[name], min_eccentricity, np.inf, "eccentricity")


@dataclass(frozen=True, kw_only=True)
class StateSettings(Transcription):
    """Settings every transcription of a model with states has (keyword-only).

    Attributes
    ----------
    min_eccentricity : float or None
        Keep contact: every clearance joint's eccentricity ratio |e|/c stays at or above this at every
        sample (in [0, 1]; 1 = the journal never leaves its bearing wall, so the joint force can only
        turn by sliding round the wall, never by a free flight and impact). None: free flight allowed.
    periodic : bool
        x(T) = x(0); otherwise the first state is held at the warm start's.
    backoff : float
        Share of the ram-speed tolerance held at the samples, in (0, 1] (between samples the speed may
        stray a little: measured 0.1 % of tol over with 1.0 on a 2 ms grid).
    omega_samples : int
        Samples of the closed-form crank-speed bounds over the period.
    ipopt : dict
        Extra nlpsol options on top of `IPOPT_WARM` (and the transcription's own).
    """

    min_eccentricity: float | None = None
    periodic: bool = True
    backoff: float = 0.98
    omega_samples: int = 1000
    ipopt: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.min_eccentricity is not None:
            chk.in_closed_interval("min_eccentricity", self.min_eccentricity, 0.0, 1.0)
        chk.in_closed_interval("backoff", self.backoff, 1e-3, 1.0)
        chk.integer("omega_samples", self.omega_samples, 10, 100_000)

    def __repr__(self) -> str:
        return settings_repr(self)


def check_states(problem: SpeedProblem, model: PressModel) -> None:
    """Checks shared by the state transcriptions, before any solve."""
    if model.is_rigid:
        raise ValueError("this transcription needs a model with states (clearance or a flexible rod); "
                         "use Rigid() for the ideal press")
    if model.n_harmonics != problem.n_harmonics:
        raise ValueError(f"model.n_harmonics ({model.n_harmonics}) must equal the problem's n_harmonics "
                         f"({problem.n_harmonics})")


@dataclass
class StateNlp:
    """The pieces of a state transcription's NLP, as the transcription builds them.

    Attributes
    ----------
    c, X : ca.MX
        The Fourier coefficients and the transcription's other variables (states, lifted crank
        motion; one column vector).
    X0 : ndarray
        The start of ``X``.
    y, y0 : dict
        Output rows at the sample ``times`` (names from `sample_outputs`): symbolic, and their values
        at the start.
    times : ndarray
        The sample times, s.
    cons : Constraints
        The transcription's own constraints (continuity or collocation); the samples' are added by
        `solve_states`.
    fixed : ndarray of int, optional
        Entries of X held at X0 (the first state of a non-periodic response).
    coefficient_step : float, optional
        Trust region, rad/s: every Fourier coefficient within this of the start's.
    parameters : (ca.MX, ndarray), optional
        The model's carried press parameters as the NLP's p, and their values; the stage then holds
        the NLP at its solution (``StageResult.point``).
    motion : ca.MX, optional
        The crank's theta, omega and alpha rows at ``times`` in the NLP's variables (the lifted
        crank motion), for the drive's limits; None: the affine map of ``c``.
    """

    c: Any
    X: Any
    X0: np.ndarray
    y: dict
    y0: dict
    times: np.ndarray
    cons: Constraints
    fixed: np.ndarray | None = None
    coefficient_step: float | None = None
    parameters: tuple | None = None
    motion: Any = None


@dataclass
class StageRun:
    """How a state transcription's stage is solved and recorded.

    Attributes
    ----------
    name, desc : str
        The stage's name, and its progress bar's label.
    options : dict
        nlpsol options on top of `IPOPT_WARM`.
    progress : bool
        Show the progress bar.
    details : dict
        The stage's ``details``.
    grid : tuple
        The transcription's grid, recorded in the stage's `NlpPoint` (``StageResult.nlp``).
    keep : dict, optional
        Holds the solver afterwards (`solve_nlp`).
    warm : NlpPoint, optional
        A solution of this NLP (same grid): its variables, multipliers, window samples and objective
        scale are taken instead of the start's, a primal-dual warm start. On another grid (with
        `carry`): its objective scale and epigraph value, and its multipliers through `carry`.
    carry : callable, optional
        ``(groups, band) -> (lam_g, why)``: `warm`'s constraint multipliers carried to this NLP's
        layout (`Constraints.groups`, the ram speed held at the samples ``band``), or (None, the
        reason) when they cannot be (`pressocp.ocp.prolong.carried_multipliers`).
    """

    name: str
    desc: str
    options: dict
    progress: bool
    details: dict
    grid: tuple = ()
    keep: dict | None = None
    warm: NlpPoint | None = None
    carry: Callable | None = None


def solve_states(problem: SpeedProblem, model: PressModel, start: FourierSpeed, nlp: StateNlp, run: StageRun,
                 settings: StateSettings) -> StageResult:
    """The NLP of a state transcription from its pieces (`nlp`), solved as `run` says, with the ram
    speed held at `settings.backoff` of its tolerance and the crank-speed bounds at
    `settings.omega_samples` samples; the stage is labelled with `settings`' repr (the transcription
    records its ``StageResult.settings`` itself: collocation with the grid it resolved)."""
    c, X, X0, y, y0, times, cons = nlp.c, nlp.X, nlp.X0, nlp.y, nlp.y0, nlp.times, nlp.cons
    fixed, coefficient_step, parameters = nlp.fixed, nlp.coefficient_step, nlp.parameters
    name, options, warm, grid = run.name, run.options, run.warm, run.grid
    same = warm is not None and warm.grid == grid  # else a coarser grid's solution, carried by `run.carry`
    backoff, omega_samples = settings.backoff, settings.omega_samples
    P, T, n = problem, problem.period, problem.n_harmonics
    objective = get_objective(P.objective)
    s = ca.MX.sym("s")
    motion = None if P.drive is None else crank_rows(P, c, times) if nlp.motion is None else nlp.motion
    alpha0 = crank_motion(start.padded(n), times)[2] if objective.drive else None
    scale = objective_scale(objective.value({**y0, "t": times}, P.drive, period=T, alpha=alpha0)) \
        if warm is None else warm.scale
    y_objective = y if motion is None else with_motor(P, objective, y, motion[1, :], motion[2, :])
    f = add_objective(cons, objective, y_objective, s, scale, times, T)
    inside = warm.band if same else window_band(P, start, y0["ram_height"].ravel(), times)
    add_window_samples(cons, P, y, inside, backoff)
    add_dense_speed_bounds(cons, P, c, omega_samples)
    add_pin_cap(cons, P, y)
    if P.drive is not None:
        add_drive_limits(cons, P, y["torque"], motion[1, :], motion[2, :], times)
    w = ca.vertcat(c, s, X)
    s0 = scale if objective.kind == "peak" else 0.0  # the epigraph starts at the warm start's peak
    w0 = np.concatenate([start.padded(n).coefficients, [s0], np.asarray(X0, float).ravel()])
    lbw, ubw = np.full(w0.size, -np.inf), np.full(w0.size, np.inf)
    lbw[2 * n] = 0.0
    if coefficient_step is not None:  # validated by the transcription's settings
        lbw[: 2 * n], ubw[: 2 * n] = w0[: 2 * n] - coefficient_step, w0[: 2 * n] + coefficient_step
    if fixed is not None:
        k = 2 * n + 1 + np.asarray(fixed)
        lbw[k] = ubw[k] = w0[k]
    multipliers = None
    if same:
        w0, multipliers = np.asarray(warm.w, float), (warm.lam_x, warm.lam_g)
    elif warm is not None:
        w0[2 * n] = warm.w[2 * n]  # the epigraph at the coarser grid's optimum, in the same scale
        lam_g, why = run.carry(cons.groups, inside) if run.carry is not None else (None, "nothing carries them")
        n_w = w.numel() + sum(v.numel() for v, _, _, _ in cons.lifted)
        multipliers = None if lam_g is None else (np.zeros(n_w), lam_g)
        run.details["multipliers_carried"] = True if lam_g is not None else why
    out = solve_nlp(NlpData(w, f, cons, w0, lbw, ubw, parameters, multipliers,
                            None if same else IPOPT_CARRIED_START),
                    NlpRun(name, {**IPOPT_WARM, **options}, objective, scale, run.desc, run.progress, run.keep))
    speed = FourierSpeed.from_coefficients(T, out.w[: 2 * n])
    q, q0 = parameter_symbols(parameters)
    try:
        alpha = [motion[2, :]] if objective.drive else []
        y_fun = ca.Function("y_at", [w, q], [ca.vertcat(*[y[k] for k in objective.outputs], *alpha)])
        rows = np.asarray(y_fun(out.w, q0))
        value = objective.value({"t": times, **{k: rows[i] for i, k in enumerate(objective.outputs)}}, P.drive,
                                period=T, alpha=rows[-1] if objective.drive else None)
    except RuntimeError:  # an integrator failing at the returned iterate: the caller locates it
        value = float("nan")
    return StageResult(
        name=name, transcription=repr(settings), model=model.spec.describe(), success=out.success, status=out.status,
        iterations=out.iterations, wall_time=out.wall_time, objective=value, speed=speed,
        last_speed=FourierSpeed.from_coefficients(T, out.last_w[: 2 * n]), t1=float(times[inside[0]]),
        history=out.history, barrier=out.barrier, iteration_log=out.iteration_log,
        violations_start=out.violations_start, violations=out.violations, details=run.details,
        timing=dict(out.timing),
        states=out.w[2 * n + 1 :], point=out.point,
        nlp=None if out.lam_x is None or not out.success else NlpPoint(out.w, out.lam_x, out.lam_g, inside, scale,
                                                                         grid, list(cons.groups)))
