"""`Rigid`: the transcription of the ideal press. The press has no states, so the loads are
closed-form functions of the crank motion at sample times, which is lifted into variables tied
linearly to the Fourier coefficients. IPOPT with the exact Hessian solves it in seconds; its
optimum is the floor the other stages compare with, and their warm start.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import ClassVar

import casadi as ca
import numpy as np

from .. import checks as chk
from ..compile_cache import NLP_FLAGS, check_jit, function_options, oracle_options, use_jit
from ..interrupt import compiling
from ..design import design_speed
from ..model import ModelSpec, PressModel
from ..objectives import get as get_objective
from ..problem import SpeedProblem
from ..mechanism.ideal import ideal_response
from ..speed import FourierSpeed
from ..ipopt_options import IPOPT_RIGID
from .nlp import (Constraints, NlpData, NlpOutcome, NlpRun, add_drive_limits, add_kinematic_window, add_objective, add_pin_cap,
                  add_speed_bounds, lifted_crank, objective_scale, scaled_crank_start, solve_nlp, with_motor)
from .stage import NlpPoint, StageResult, Transcription, WarmStart, settings_repr

#: Outputs of the ideal press at one sample, besides the crank motion.
LOAD_OUTPUTS = ("torque", "slider_normal_force", "crank_pin_force", "wrist_pin_force", "crank_pin_tension",
                "wrist_pin_tension")


def loads_function(problem: SpeedProblem, symbols: tuple[str, ...] = (), jit: bool = False) -> ca.Function:
    """(theta, omega, alpha, q) -> `LOAD_OUTPUTS` of the ideal press (inverse dynamics), SX, one
    sample; ``q`` holds the press parameters `symbols` (dotted names), empty without them. With
    `jit`, it and its derivatives are compiled (`pressocp.compile_cache`)."""
    th, om, al = ca.SX.sym("theta"), ca.SX.sym("omega"), ca.SX.sym("alpha")
    press, q = problem.press.with_symbols(tuple(symbols)) if symbols else (problem.press, [])
    dyn = problem.mechanism.inverse_dynamics(press, th, om, al)
    with compiling():
        return ca.Function("loads", [th, om, al, ca.vertcat(*q) if q else ca.SX(0, 1)],
                           [dyn[k] for k in LOAD_OUTPUTS], function_options(jit, flags=NLP_FLAGS))


#: Share of the ram-speed tolerance a relaxed rigid stage holds (`Rigid.relaxed`). On press60, whose
#: answer is the rigid optimum, 0.99 re-simulated 0.04 % lower than 0.9 (76.125 against 76.153 N m)
#: with the ram 8.7e-6 m/s inside its tolerance on the clearance model; 1.0 left it by 1.4e-6 m/s.
RELAX_BACKOFF = 0.99
#: IPOPT's iteration limit of a relaxed rigid stage (press60 needed 45 from the rigid optimum).
RELAX_ITERATIONS = 100


@dataclass(frozen=True)
class Rigid(Transcription):
    """Direct transcription on the ideal press (no states), exact Hessian.

    Attributes
    ----------
    samples : int
        Uniform samples over the period for the loads and the crank-speed bounds, 50..20000.
    window_samples : int
        Samples of the ram-speed constraint in the window, 10..5000.
    backoff : float
        Share of the ram-speed tolerance held at the samples, in (0, 1]: the verification checks the
        whole window, and a clearance model adds the journals' motion to the ram velocity.
    ipopt : dict
        Extra nlpsol options (e.g. ``{"ipopt.max_iter": 50}``) on top of `IPOPT_RIGID`.
    jit : bool or "auto"
        Compile the loads and the ram's kinematics with their derivatives (`pressocp.compile_cache`;
        the function evaluations were 60-75 % of a rigid stage on CasADi's virtual machine). "auto":
        when a C compiler is found.
    """

    samples: int = 1000
    window_samples: int = 200
    backoff: float = 0.9
    ipopt: dict = field(default_factory=dict)
    jit: bool | str = "auto"

    has_states: ClassVar[bool] = False
    gives_parametric_point: ClassVar[bool] = True

    def __post_init__(self) -> None:
        chk.integer("samples", self.samples, 50, 20000)
        chk.integer("window_samples", self.window_samples, 10, 5000)
        chk.in_closed_interval("backoff", self.backoff, 1e-3, 1.0)
        check_jit(self.jit)

    def __repr__(self) -> str:
        return settings_repr(self)

    def solve(self, problem: SpeedProblem, model: PressModel | None = None, start: WarmStart | None = None,
              name: str = "rigid", progress: bool = False) -> StageResult:
        """Solve `problem` on the ideal press.

        Parameters
        ----------
        problem : SpeedProblem
        model : PressModel, optional
            The model the answer is meant for. Its ram hangs lower by its clearances
            (`PressModel.ram_drop`), so it enters the height window earlier: the rigid window is
            widened upward by that drop, so that the ram speed holds on that model's window too.
            When the rod's load is held in compression (`SpeedProblem.reversal_side`: a
            counterbalance lifts more than ram and rod weigh) the journals rest on the other side
            and the ram rides higher by as much: the window is widened downward instead.
            Press parameters it carries (`PressModel.symbols`) become the NLP's p, and the stage holds
            the NLP at its solution (``StageResult.point``); a bearing's parameters do not enter.
        start : WarmStart, optional
            Start speed; default the kinematic design (`design_speed`). With a ``point`` of a rigid
            stage on the same samples (`grid`), the NLP starts there with its multipliers and its
            objective scale: the same NLP, other bounds allowed (``backoff``).
        name : str
            Stage name in records and the progress bar.
        progress : bool
            A tqdm bar over IPOPT's iterations.

        Returns
        -------
        StageResult
            ``success`` False (with the least-infeasible iterate) when IPOPT does not converge.
        """
        P, T, n, N = problem, problem.period, problem.n_harmonics, self.samples
        objective = get_objective(P.objective)
        drop = 0.0 if model is None else model.ram_drop
        up = 0.0 if P.reversal_side() == "compression" else drop  # a rod in compression lifts the ram
        h_start = P.window_heights[0] + up
        duration = P.window_duration + drop / abs(P.ram_speed)
        initial, t1_0 = start_speed(P, start, h_start, up)
        t1_0 = float(np.clip(t1_0, 0.0, T - duration))

        point = start.point if start is not None and start.point is not None \
            and start.point.grid == self.grid() else None
        c, s, t1 = ca.MX.sym("c", 2 * n), ca.MX.sym("s"), ca.MX.sym("t1")
        symbols = () if model is None else model.symbols
        free = P.free_parameters()
        if free and symbols:
            raise ValueError(f"a rigid stage cannot carry press parameters ({', '.join(symbols)}) and optimise "
                             f"{', '.join(free)} at once")
        names = tuple(free) or symbols
        q = ca.MX.sym("q", len(names)) if names else ca.MX(0, 1)
        ts = np.linspace(0.0, T, N, endpoint=False)
        cons = Constraints()
        Wv, W = lifted_crank(cons, c, T, ts)
        jit = use_jit(self.jit, "the rigid stage")
        y = dict(zip(LOAD_OUTPUTS, loads_function(P, names, jit).map(N)(W[0, :], W[1, :], W[2, :], q)))
        y.update(theta=W[0, :], omega=W[1, :])
        scale = objective_scale(objective.value(ideal_response(P.press, P.mechanism, initial, ts), P.drive, period=T,
                                                alpha=initial.evaluate(ts)[2])) if point is None else point.scale
        f = add_objective(cons, objective, with_motor(P, objective, y, W[1, :], W[2, :]), s, scale, ts, T)
        add_kinematic_window(cons, P, c, t1, duration, self.window_samples, self.backoff, h_start, jit)
        add_speed_bounds(cons, P, W[1, :], W[2, :])
        add_rod_load_side(cons, P, ca.vertcat(y["crank_pin_tension"], y["wrist_pin_tension"]))
        add_pin_cap(cons, P, y)
        add_drive_limits(cons, P, y["torque"], W[1, :], W[2, :], ts)
        w = ca.vertcat(c, s, t1, ca.vec(Wv), q if free else ca.MX(0, 1))
        W0 = scaled_crank_start(initial, ts).ravel(order="F")
        lo, hi = (np.array([b[k] for b in free.values()]) for k in (0, 1))
        q0 = np.clip([P.press.value(name) for name in free], lo, hi)
        w0 = np.concatenate([initial.coefficients, [scale, t1_0], W0, q0]) if point is None else point.w
        lbw = np.concatenate([np.full(2 * n, -np.inf), [0.0, 0.0], np.full(W0.size, -np.inf), lo])
        ubw = np.concatenate([np.full(2 * n, np.inf), [np.inf, T - duration], np.full(W0.size, np.inf), hi])
        out = solve_nlp(NlpData(w, f, cons, w0, lbw, ubw, parameters=(q, model.nominal) if symbols and not free else None,
                                multipliers=None if point is None else (point.lam_x, point.lam_g)),
                        NlpRun(f"rigid_{name}", {**IPOPT_RIGID, **oracle_options(jit), **self.ipopt}, objective,
                               scale, f"{name} (rigid press, {N} samples)", progress))
        return self._result(P, name, out, scale, (drop, up), warm=point is not None)

    def _result(self, P: SpeedProblem, name: str, out: NlpOutcome, scale: float, window: tuple[float, float],
                warm: bool) -> StageResult:
        """The stage's record from IPOPT's outcome `out`; the objective re-evaluated on the ideal press
        at the answer (with any press parameter it chose). `window`: how far (m) the height window was
        extended, and how far of it upward."""
        drop, up = window
        T, n, free = P.period, P.n_harmonics, P.free_parameters()
        ts = np.linspace(0.0, T, self.samples, endpoint=False)
        speed = FourierSpeed.from_coefficients(T, out.w[: 2 * n])
        chosen = dict(zip(free, (float(v) for v in out.w[out.w.size - len(free):]))) if free else {}
        sampled = ideal_response(P.press.with_values(chosen), P.mechanism, speed, ts)
        return StageResult(
            name=name, transcription=repr(self), model=ModelSpec("rigid", (), mechanism=P.mechanism).describe(), success=out.success,
            status=out.status, iterations=out.iterations, wall_time=out.wall_time,
            objective=get_objective(P.objective).value(sampled, P.drive, period=T, alpha=speed.evaluate(ts)[2]),
            speed=speed, last_speed=FourierSpeed.from_coefficients(T, out.last_w[: 2 * n]),
            t1=float(out.w[2 * n + 1]), history=out.history, barrier=out.barrier, iteration_log=out.iteration_log,
            violations_start=out.violations_start, violations=out.violations,
            details={"window_extension_m": drop, "window_extended": "up" if up else "down", "min_tension_N": P.min_tension,
                     "max_tension_N": P.max_tension,
                     **({"free": chosen} if free else {}), "samples": self.samples,
                     "window_samples": self.window_samples, "backoff": self.backoff, "warm": warm},
            timing=dict(out.timing), point=out.point,
            nlp=None if out.lam_x is None or not out.success else
            NlpPoint(out.w, out.lam_x, out.lam_g, np.arange(self.window_samples), scale, self.grid()),
            settings=self.settings())

    def relaxed(self, stage: StageResult) -> "Rigid | None":
        """`stage`'s NLP holding `RELAX_BACKOFF` of the ram-speed tolerance, IPOPT stopped after
        `RELAX_ITERATIONS`; None when the stage held that much already or has no `NlpPoint` of this
        grid to start from. Started from that point it is the same NLP with its ram-speed bounds
        moved out, so IPOPT moves only as far as the bounds."""
        if stage.nlp is None or stage.nlp.grid != self.grid() or stage.details.get("backoff", 1.0) >= RELAX_BACKOFF:
            return None
        return replace(self, backoff=RELAX_BACKOFF, ipopt={"ipopt.max_iter": RELAX_ITERATIONS, **self.ipopt})

    def grid(self) -> tuple:
        """What a warm start's `NlpPoint` must match: the samples of the loads and of the window."""
        return ("rigid", self.samples, self.window_samples)


def start_speed(problem: SpeedProblem, start: WarmStart | None, h_start: float, drop: float) -> tuple[FourierSpeed,
                                                                                                       float]:
    """The rigid stage's start: the speed (`start`'s with the problem's harmonics and theta0 = 0, or
    the kinematic design) and the time at which the ram passes `h_start` (m) going down (s), with the
    window widened upward by the ram's `drop` (m)."""
    T = problem.period
    if start is None:
        d = design_speed(problem)
        return d.speed, d.t1 - drop / abs(problem.ram_speed)
    if not np.isclose(start.speed.period, T):
        raise ValueError(f"start.speed.period must equal the problem's period {T:g} s, got {start.speed.period:g} s")
    padded = start.speed.padded(problem.n_harmonics)
    initial = FourierSpeed(T, padded.a, padded.b, 0.0)
    th1 = float(problem.mechanism.input_angle_at_height(problem.press, min(h_start, problem.stroke), "down"))
    tg = np.linspace(0, T, 20001)
    return initial, float(np.interp(th1, initial.theta(tg), tg))


def add_rod_load_side(cons: Constraints, problem: SpeedProblem, tension: ca.MX) -> None:
    """Rows that hold the rod's load on one side (no joint-force reversal): the joints' tension (N)
    above `SpeedProblem.min_tension` or below `SpeedProblem.max_tension`, scaled by the hanging weight."""
    if problem.min_tension is not None:  # the rod in tension
        cons.add((tension - problem.min_tension) / problem.hanging_weight, 0.0, np.inf, "rod_tension")
    if problem.max_tension is not None:  # the rod in compression
        cons.add((problem.max_tension - tension) / problem.hanging_weight, 0.0, np.inf, "rod_compression")
