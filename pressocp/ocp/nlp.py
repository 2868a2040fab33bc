"""NLP pieces every transcription uses: a named constraint collector, the lifted crank motion,
the objective (epigraph or RMS) from the registry, the crank-speed bounds and pin-force cap, the
IPOPT option sets, and `solve_nlp` (IPOPT with an iteration record, a progress bar in the
objective's unit, the least-infeasible iterate kept, and Ctrl-C raised as `KeyboardInterrupt`)."""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from ..compile_cache import NLP_FLAGS, compile_seconds, function_options
from ..interrupt import compiling, interruptible
from ..ipopt_options import IPOPT_WARM_START
from ..objectives import Objective, trapezoid_weights
from ..problem import SpeedProblem
from ..series import PIN_FORCES
from ..simulate import first_line
from ..speed import FourierSpeed, series


def violation(g: np.ndarray, lbg: np.ndarray, ubg: np.ndarray) -> np.ndarray:
    """Amount by which each constraint value lies outside [lbg, ubg] (0 inside)."""
    return np.maximum(lbg - g, 0.0) + np.maximum(g - ubg, 0.0)


class Constraints:
    """lbg <= g <= ubg built group by group; ``groups`` keeps (name, first index, size).

    A constraint may need variables of its own (a running sum that keeps a mean over every sample
    sparse): `variables` makes them, and `solve_nlp` appends them to the transcription's variables
    and starts them at their start expressions (``lifted`` keeps symbol, start, lower, upper)."""

    def __init__(self) -> None:
        self._g: list = []
        self._lb: list[np.ndarray] = []
        self._ub: list[np.ndarray] = []
        self.groups: list[tuple[str, int, int]] = []
        self.size = 0
        self.lifted: list[tuple[Any, Any, np.ndarray, np.ndarray]] = []

    def variables(self, name: str, start, lo=-np.inf, hi=np.inf):
        """New NLP variables, one per entry of the expression `start` (of the transcription's
        variables and parameters), which gives their start value; bounds `lo`, `hi`."""
        v = ca.MX.sym(name, start.numel())
        self.lifted.append((v, ca.vec(start), np.broadcast_to(lo, (v.numel(),)), np.broadcast_to(hi, (v.numel(),))))
        return v

    def add(self, expr, lo, hi, name: str = "") -> None:
        """Append ``vec(expr)`` with bounds ``lo``, ``hi`` (scalars or arrays)."""
        k = expr.numel()
        self.groups.append((name, self.size, k))
        self._g.append(ca.vec(expr))
        self._lb.append(np.broadcast_to(lo, (k,)))
        self._ub.append(np.broadcast_to(hi, (k,)))
        self.size += k

    @property
    def g(self):
        return ca.vertcat(*self._g)

    @property
    def lbg(self) -> np.ndarray:
        return np.concatenate(self._lb)

    @property
    def ubg(self) -> np.ndarray:
        return np.concatenate(self._ub)

    def by_group(self, g: np.ndarray) -> dict[str, float]:
        """Largest violation per group name for constraint values ``g``."""
        d = violation(np.asarray(g).ravel(), self.lbg, self.ubg)
        out: dict[str, float] = {}
        for name, i0, k in self.groups:
            out[name] = max(out.get(name, 0.0), float(np.max(d[i0 : i0 + k], initial=0.0)))
        return out


class UniformPartition:
    """Equal pieces of one period (shooting intervals, collocation elements); a subclass has the
    fields ``period`` (s) and tells `pieces`."""

    period: float

    @property
    def pieces(self) -> int:
        raise NotImplementedError

    @property
    def h(self) -> float:
        """Length of a piece, s."""
        return self.period / self.pieces

    @property
    def starts(self) -> np.ndarray:
        """Start times of the pieces, s."""
        return self.h * np.arange(self.pieces)


# The crank motion ------------------------------------------------------------------------------
def crank_motion(speed: FourierSpeed, times: np.ndarray) -> np.ndarray:
    """Crank angle, speed and acceleration (rows; rad, rad/s, rad/s^2) of `speed` at `times`, s."""
    return np.array(series(times, speed.a, speed.b, speed.period, speed.theta0))


def crank_map(n: int, period: float, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The crank motion at `times` as an affine map of the 2n Fourier coefficients (theta0 = 0):
    ``vec(motion) = m0 + A @ c`` with motion 3 x len(times) stacked by column (`crank_motion`)."""
    zero = np.zeros(n)
    m0 = crank_motion(FourierSpeed(period, zero, zero), times).ravel(order="F")
    A = np.column_stack([crank_motion(FourierSpeed.from_coefficients(period, e), times).ravel(order="F") - m0
                         for e in np.eye(2 * n)])
    return m0, A


def crank_rows(problem: SpeedProblem, c, times: np.ndarray):
    """theta, omega, alpha rows (3 x len(times)) at `times` as the affine map of the coefficients ``c``."""
    m0, A = crank_map(problem.n_harmonics, problem.period, np.asarray(times))
    return ca.reshape(ca.mtimes(ca.DM(A), c) + m0, 3, len(times))


def crank_scale(period: float) -> np.ndarray:
    """Scales of (theta, omega, alpha) for a period T: 1 rad, the mean speed 2 pi/T and its square."""
    w_bar = 2 * np.pi / period
    return np.array([1.0, w_bar, w_bar**2])


def lifted_crank(cons: Constraints, c, period: float, times: np.ndarray) -> tuple:
    """Crank motion variables at `times`, tied to the Fourier coefficients ``c`` by a linear
    equality (group "crank_motion", scaled by `crank_scale`).

    Lifting the crank motion into variables makes each sample's loads depend on its own three
    variables only, so the exact Hessian of the Lagrangian is block-diagonal instead of dense in the
    2n coefficients over all samples.

    Returns
    -------
    Wv : ca.MX, 3 x len(times)
        The scaled variables (to put into the NLP's x).
    W : ca.MX
        theta (rad), omega (rad/s), alpha (rad/s^2) rows: ``Wv`` times the scales.
    """
    Wv = ca.MX.sym("W", 3, len(times))
    W = Wv * ca.DM(crank_scale(period))
    tie(cons, W, c, period, times)
    return Wv, W


def tie(cons: Constraints, W, c, period: float, times: np.ndarray) -> None:
    """The linear equality W = Fourier series of ``c`` at ``times`` (group "crank_motion")."""
    m0, A = crank_map(c.numel() // 2, period, times)
    scale = np.tile(crank_scale(period), len(times))
    cons.add((ca.vec(W) - ca.mtimes(ca.DM(A), c) - m0) / scale, 0.0, 0.0, "crank_motion")


def scaled_crank_start(speed: FourierSpeed, times: np.ndarray) -> np.ndarray:
    """Start values of the lifted crank variables: `crank_motion` divided by `crank_scale` (3 x m)."""
    return crank_motion(speed, times) / crank_scale(speed.period)[:, None]


def ram_function(problem: SpeedProblem, jit: bool = False) -> ca.Function:
    """(t, c) -> (ram height, ram velocity, theta) of the ideal press driven by the Fourier speed with
    coefficients c (SX); compiled with its derivatives with `jit` (`pressocp.compile_cache`)."""
    n, T = problem.n_harmonics, problem.period
    t, c = ca.SX.sym("t"), ca.SX.sym("c", 2 * n)
    th, om, al = series(t, c[:n], c[n:], T)
    kin = problem.mechanism.kinematics_function(problem.press)(theta=th, omega=om, alpha=al)
    with compiling():
        return ca.Function("ram", [t, c], [kin["ram_height"], kin["ram_velocity"], th],
                           function_options(jit, flags=NLP_FLAGS))


def add_kinematic_window(cons: Constraints, problem: SpeedProblem, c, t1, duration: float, samples: int,
                         backoff: float, h_start: float | None = None, jit: bool = False) -> None:
    """The ideal press's ram speed within ``backoff`` x tol at `samples` points of [t1, t1 + duration]
    (``t1`` a number or a symbol); with `h_start` (m) also h(t1) = h_start on the downstroke, and the
    ram at or below the window's end height h_start - |ram_speed| duration at t1 + duration, so
    that the ram leaves the window inside the sampled span (a ram slower than asked, within its
    tolerance, would otherwise leave it after the last sample, where nothing holds its speed).
    `jit`: the ram function compiled (`ram_function`)."""
    f = ram_function(problem, jit)
    tw = t1 + duration * ca.DM(np.linspace(0.0, 1.0, samples)).T
    hw, vw, _ = f.map(samples)(tw, ca.repmat(c, 1, samples))
    cons.add((vw - problem.ram_speed) / problem.tol, -backoff, backoff, "ram_speed_kinematic")
    if h_start is not None:
        h1, _, th1 = f(t1, c)
        cons.add((h1 - h_start) / problem.stroke, 0.0, 0.0, "window_start")
        cons.add(th1, 0.0, problem.mechanism.bottom_dead_centre(problem.press), "window_start")
        h_end = h_start - abs(problem.ram_speed) * duration
        cons.add((hw[-1] - h_end) / problem.stroke, -np.inf, 0.0, "window_end")


# Objective, bounds and caps ----------------------------------------------------------------------
def add_objective(cons: Constraints, objective: Objective, y: Mapping, s, scale: float,
                  times: np.ndarray, period: float):
    """The objective on the sample rows ``y[name]`` at `times` (s, one period of `period`; a drive
    objective's rows from `with_motor`): the epigraph -s <= term <= s of every term (returns
    s/scale), the mean square of the RMS term (returns mean(term^2)/scale^2), the integral of the
    term (periodic trapezoidal weights; returns it/scale), or the swing: the running integral of
    (term - its mean) in time order (`running_sum`) between two variables of its own, lo <=
    stored_k <= hi (returns (hi - lo)/scale)."""
    terms = objective.terms(y)
    if objective.kind == "rms":
        return ca.sumsqr(terms[0]) / terms[0].numel() / scale**2
    if objective.kind in ("integral", "swing"):
        weights = trapezoid_weights(times, period)
        if objective.kind == "integral":
            return ca.dot(ca.vec(terms[0]), ca.DM(weights)) / scale
        order = np.argsort(np.asarray(times, float))
        energy = running_sum(cons, ca.vec(terms[0])[order.tolist()] / scale, weights[order])
        stored = energy - energy[-1] * ca.DM(np.cumsum(weights[order]) / period)
        hi, lo = cons.variables("swing_high", ca.mmax(stored)), cons.variables("swing_low", ca.mmin(stored))
        cons.add(stored - hi, -np.inf, 0.0, "swing")
        cons.add(lo - stored, -np.inf, 0.0, "swing")
        return hi - lo
    for q in terms:
        cons.add((q - s) / scale, -np.inf, 0.0, "epigraph")
        cons.add((-q - s) / scale, -np.inf, 0.0, "epigraph")
    return s / scale


def objective_scale(value: float) -> float:
    """The NLP's objective scale from the objective's value at the start: its magnitude, or 1 where
    it is zero (an energy of a press without losses or process force)."""
    return abs(value) if abs(value) > 1e-12 else 1.0


def unscaled(objective: Objective, f: float, scale: float) -> float:
    """The objective's value (its unit) from the NLP objective f (`add_objective`)."""
    return float(np.sqrt(max(f, 0.0)) * scale) if objective.kind == "rms" else float(f * scale)


def add_speed_bounds(cons: Constraints, problem: SpeedProblem, omega, alpha) -> None:
    """omega_min <= omega (<= omega_max) and |alpha| <= alpha_max at the given samples."""
    P = problem
    wbar = 2 * np.pi / P.period
    cons.add(omega / wbar, P.omega_lower / wbar, np.inf if P.omega_max is None else P.omega_max / wbar, "omega")
    if P.alpha_max is not None:
        cons.add(alpha / P.alpha_max, -1.0, 1.0, "alpha")


def add_dense_speed_bounds(cons: Constraints, problem: SpeedProblem, c, samples: int) -> None:
    """`add_speed_bounds` at `samples` uniform times, the crank motion an affine map of ``c``."""
    motion = crank_rows(problem, c, np.linspace(0.0, problem.period, samples, endpoint=False))
    add_speed_bounds(cons, problem, motion[1, :], motion[2, :])


#: Share of `SpeedProblem.max_pin_force` held at the samples: on the 75 spm scene the re-simulated peak
#: between the Radau points was 0.06 % above the value held at them.
PIN_CAP_BACKOFF = 0.995


def add_pin_cap(cons: Constraints, problem: SpeedProblem, y: Mapping) -> None:
    """crank-pin and wrist-pin force <= `PIN_CAP_BACKOFF` x problem.max_pin_force at every sample (if a
    cap is set)."""
    if problem.max_pin_force is not None:
        for name in PIN_FORCES:
            cons.add(y[name] / problem.max_pin_force, -np.inf, PIN_CAP_BACKOFF, "max_pin_force")


#: Share of the drive's ratings held at the samples (as `PIN_CAP_BACKOFF`).
DRIVE_BACKOFF = 0.995


def add_drive_limits(cons: Constraints, problem: SpeedProblem, torque, omega, alpha, times: np.ndarray) -> None:
    """The drive's limits at the samples `times` (s) of the crank torque `torque`, speed `omega` and
    acceleration `alpha` (rows, N m, rad/s, rad/s^2; the lifted crank motion keeps each sample's
    terms in its own variables), each held at `DRIVE_BACKOFF` of its rating: the motor torque under
    the peak curve (`pressocp.drive.Drive.peak_torque_at`: the peak torque, and |torque| x speed
    under the power limit) and the motor speed under its top speed. The motor torque is the driving
    or the regenerating one (`pressocp.drive.motor_cycle`); a bound on both is a bound on whichever
    acts. The RMS motor torque under the continuous rating: the mean of its square over the period
    (periodic trapezoidal weights on `times`) is a running sum in variables of its own, one per
    sample (`running_sum`), so that each row holds one sample's variables: one dense row made
    the constraint Jacobian take 1.5 s per iteration instead of 0.01 s
    (docs/decisions/2026-11-26-drive-limits.md). Nothing without a drive."""
    d = problem.drive
    if d is None:
        return
    speed = d.gear_ratio * omega
    curve = None
    if d.curve_speeds:  # the data sheet's points: |motor| <= the linear interpolant at the speed
        table = ca.interpolant("peak_curve", "linear", [list(d.curve_speeds)], list(d.curve_torques))
        curve = table.map(speed.numel())(ca.fabs(speed))
    for motor in d.motor_torques(torque, alpha):
        if curve is None:
            cons.add(motor / d.peak_torque, -DRIVE_BACKOFF, DRIVE_BACKOFF, "drive_peak_torque")
        else:
            cons.add(ca.vertcat(DRIVE_BACKOFF * curve - motor, DRIVE_BACKOFF * curve + motor) / d.peak_torque,
                     0.0, np.inf, "drive_peak_torque")
        if d.power_limit is not None:
            cons.add(motor * speed / d.power_limit, -DRIVE_BACKOFF, DRIVE_BACKOFF, "drive_power")
    cons.add(speed / d.max_speed, -np.inf, DRIVE_BACKOFF, "drive_speed")
    motor = acting_motor_torque(d, torque, alpha)
    weights = trapezoid_weights(times, problem.period) / problem.period
    mean_square = running_sum(cons, (motor / d.continuous_torque) ** 2, weights)[-1]
    cons.add(mean_square, -np.inf, DRIVE_BACKOFF**2, "drive_rms")


#: Width of the blend between the driving and the regenerating gear factor in `acting_motor_torque`,
#: as a share of the motor's peak torque brought to the crank.
GEAR_BLEND = 1e-3


def acting_motor_torque(drive, torque, alpha):
    """The motor torque that acts (N m; `pressocp.drive.motor_cycle`: crank torque / (i eta) while the
    crank's power is positive, crank torque x eta / i while it is negative, plus the rotor's inertia
    torque) as one smooth expression: the two gear factors blended by a tanh of the crank torque
    over `GEAR_BLEND` of the motor's peak torque at the crank. Near zero crank torque, where the
    blend acts, both terms are near zero."""
    driving, regenerating = drive.motor_torques(torque, alpha)
    share = 0.5 * (1.0 + ca.tanh(torque / (GEAR_BLEND * drive.peak_torque * drive.gear_ratio)))
    return regenerating + share * (driving - regenerating)


def running_sum(cons: Constraints, terms, weights: np.ndarray):
    """The running sums r_k = r_(k-1) + weights_k terms_k of a row of expressions (one per sample,
    in the order the running sum takes them), as NLP variables of their own
    (`Constraints.variables`) tied by one row per sample (group "running_sum"), so that no row
    holds every sample's variables. Returns r (a column)."""
    q = ca.vec(terms) * ca.DM(weights)
    r = cons.variables("running_sum", ca.cumsum(q))
    cons.add(r - ca.vertcat(0.0, r[:-1]) - q, 0.0, 0.0, "running_sum")
    return r


def motor_rows(drive, torque, omega, alpha) -> dict:
    """The motor's figures of `pressocp.objectives.motor_entries` as smooth CasADi rows:
    ``motor_torque`` (`acting_motor_torque`), ``motor_power`` and ``supply_power``, whose positive
    part is 0.5 (P + sqrt(P^2 + eps^2)) with eps `GEAR_BLEND` of the motor's peak torque times its
    top speed (W)."""
    motor = acting_motor_torque(drive, torque, alpha)
    power = motor * drive.gear_ratio * omega
    eps2 = (GEAR_BLEND * drive.peak_torque * drive.max_speed) ** 2
    positive, negative = 0.5 * (power + ca.sqrt(power**2 + eps2)), 0.5 * (-power + ca.sqrt(power**2 + eps2))
    return {"motor_torque": motor, "motor_power": power,
            "supply_power": positive - drive.regeneration_efficiency * negative}


def with_motor(problem: SpeedProblem, objective: Objective, y: dict, omega, alpha) -> dict:
    """`y` with `motor_rows` added when `objective` reads the motor (crank speed and acceleration
    rows at the samples), else `y` itself."""
    return {**y, **motor_rows(problem.drive, y["torque"], omega, alpha)} if objective.drive else y


#: The drive's constraint groups (`add_drive_limits`) and the rating each holds.
DRIVE_GROUPS = {"drive_peak_torque": "peak_torque", "drive_power": "power_limit", "drive_speed": "max_speed",
                "drive_rms": "continuous_torque"}


def drive_shortfall(violations: dict[str, float]) -> str:
    """What a stage's least-infeasible point says of the drive: each limit it could not hold, by how
    much of its rating (`violations` by constraint group, `StageResult.violations`); empty when it
    held them all. The RMS row holds a mean square: its violation is turned into one of the RMS."""
    over = dict(violations)
    if "drive_rms" in over:
        over["drive_rms"] = float(np.sqrt(DRIVE_BACKOFF**2 + over["drive_rms"]) - DRIVE_BACKOFF)
    short = [f"drive.{field} exceeded by {100 * over[group]:.3g} % of its rating"
             for group, field in DRIVE_GROUPS.items() if over.get(group, 0.0) > 1e-6]
    return "" if not short else ("; the drive is too weak for this problem: " + ", ".join(short)
                                 + " (raise the rating or the gear ratio, or ask less of the press)")


def needed_outputs(problem: SpeedProblem, objective: Objective, extra: tuple[str, ...] = ()) -> tuple[str, ...]:
    """Output names a transcription must sample: the objective's, the pin forces under a cap, the
    torque under a drive, and `extra`, each once in that order."""
    names = list(objective.outputs) + (list(PIN_FORCES) if problem.max_pin_force is not None else []) \
        + (["torque"] if problem.drive is not None else []) + list(extra)
    return tuple(dict.fromkeys(names))


# Solving ---------------------------------------------------------------------------------------
class IterationRecord(ca.Callback):
    """IPOPT iteration callback: objective history, the least-infeasible iterate, optional tqdm bar
    showing the objective in its own unit."""

    def __init__(self, nx: int, cons: Constraints, objective: Objective, scale: float, bar=None, np_: int = 0):
        ca.Callback.__init__(self)
        self.nx, self.ng, self.np, self.lbg, self.ubg, self.bar = nx, cons.size, np_, cons.lbg, cons.ubg, bar
        self.objective, self.scale = objective, scale
        self.history: list[float] = []
        self.times: list[float] = []  # time.perf_counter() at each iteration
        self.best: tuple[float, float, np.ndarray] | None = None
        self.seconds = 0.0  # spent in this callback
        self.construct("iterations", {})

    def get_n_in(self):
        return ca.nlpsol_n_out()

    def get_n_out(self):
        return 1

    def get_name_in(self, i):
        return ca.nlpsol_out(i)

    def get_name_out(self, i):
        return "ret"

    def get_sparsity_in(self, i):
        n = ca.nlpsol_out(i)
        if n == "f":
            return ca.Sparsity.scalar()
        if n in ("x", "lam_x"):
            return ca.Sparsity.dense(self.nx)
        if n in ("g", "lam_g"):
            return ca.Sparsity.dense(self.ng)
        if n == "lam_p" and self.np:
            return ca.Sparsity.dense(self.np)
        return ca.Sparsity(0, 0)

    def eval(self, arg):
        t0 = time.perf_counter()
        try:
            return self.record(arg)
        finally:
            self.seconds += time.perf_counter() - t0

    def record(self, arg):
        f = unscaled(self.objective, float(arg[1]), self.scale)
        g = np.asarray(arg[2]).ravel()
        viol = float(np.max(violation(g, self.lbg, self.ubg), initial=0.0))
        self.history.append(f)
        self.times.append(time.perf_counter())
        if self.best is None or (viol, f) < (self.best[0], self.best[1]) or (viol <= 1e-6 and f < self.best[1]):
            self.best = (viol, f, np.asarray(arg[0]).ravel().copy())
        if self.bar is not None:
            self.bar.update(1)
            self.bar.set_postfix_str(f"{self.objective.name} {f:.5g} {self.objective.unit}, infeasibility {viol:.2g}")
        return [0]


@dataclass
class ParametricPoint:
    """An NLP ``min f(x, p) s.t. lbg <= g(x, p) <= ubg, lbx <= x <= ubx`` at IPOPT's solution for the
    parameter values ``p``: what a parametric sensitivity needs (`pressocp.ocp.kkt`).

    Attributes
    ----------
    solver : ca.Function
        The nlpsol that solved it: its oracle's functions (``nlp_f``, ``nlp_grad``, ``nlp_jac_g``,
        ``nlp_hess_l``, compiled with the NLP's own options) are reused.
    x, p, lam_x, lam_g : ndarray
        The solution, the parameter values and the multipliers (CasADi's sign convention: positive
        at an upper bound, negative at a lower one).
    lbx, ubx, lbg, ubg : ndarray
    groups : list of (name, first index, size)
        The constraint groups (`Constraints.groups`).
    """

    solver: ca.Function
    x: np.ndarray
    p: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray
    lbx: np.ndarray
    ubx: np.ndarray
    lbg: np.ndarray
    ubg: np.ndarray
    groups: list


@dataclass
class NlpOutcome:
    """What `solve_nlp` found.

    Attributes
    ----------
    w : ndarray
        The solution, or (when IPOPT did not succeed) the least-infeasible iterate: the
        transcription's variables (the constraints' own, `Constraints.variables`, left out).
    last_w : ndarray
        IPOPT's final iterate either way (the same variables).
    success : bool
    status : str
    iterations : int
    history : list of float
        Objective per iteration, in the objective's unit.
    barrier : list of float
        IPOPT's barrier parameter per iteration.
    violations_start, violations : dict
        Largest violation per constraint group at the start and at ``w``.
    iteration_log : dict
        Per iteration: ``time_s`` (since the solve started), and IPOPT's ``inf_pr`` and ``inf_du``
        (its scaled primal and dual infeasibility; empty when IPOPT raised).
    wall_time : float
        s.
    point : ParametricPoint or None
        The NLP at IPOPT's solution, when it has parameters and IPOPT succeeded.
    timing : dict
        Where the wall time went (`timing_split`), s.
    lam_x, lam_g : ndarray or None
        IPOPT's multipliers at its final iterate (None when IPOPT raised); ``lam_x`` covers the
        constraints' own variables too (a warm start passes it back with ``w`` alone).
    """

    w: np.ndarray
    last_w: np.ndarray
    success: bool
    status: str
    iterations: int
    history: list
    barrier: list
    violations_start: dict
    violations: dict
    iteration_log: dict
    wall_time: float
    point: ParametricPoint | None = None
    timing: dict = field(default_factory=dict)
    lam_x: np.ndarray | None = None
    lam_g: np.ndarray | None = None


#: CasADi's per-function wall-time counters of an nlpsol, by the name a timing record gives them.
EVALUATIONS = {"objective": ("nlp_f", "nlp_grad_f"), "constraints": ("nlp_g",), "jacobian": ("nlp_jac_g",),
               "hessian": ("nlp_hess_l",)}


def timing_split(stats: dict, build: float, wall: float, callback: float, compile: float = 0.0) -> dict:
    """Where an IPOPT solve's wall time went, s: ``build`` (nlpsol construction: code generation, link
    and set-up), ``compile`` (the C compiler's time, `pressocp.compile_cache.compile_seconds`; none
    when every object file came from the cache), the function and derivative evaluations
    (`EVALUATIONS`, from CasADi's ``t_wall_*`` counters), ``callback`` (the iteration record and
    progress bar), ``solver`` (the rest of IPOPT's own time: the linear solver, MUMPS, above all) and
    ``total``."""
    evals = {k: float(sum(stats.get(f"t_wall_{n}", 0.0) for n in names)) for k, names in EVALUATIONS.items()}
    solve = float(stats.get("t_wall_total", wall - build))
    return {"build": build - compile, "compile": compile, **evals, "callback": callback,
            "solver": max(solve - sum(evals.values()) - callback, 0.0), "total": wall}


def parameter_symbols(q) -> tuple:
    """``(symbol, values)`` of an NLP's parameters from ``(symbol, values)`` or None (an empty
    parameter vector)."""
    return (ca.MX(0, 1), np.zeros(0)) if q is None else (q[0], np.asarray(q[1], float).ravel())


@dataclass
class NlpData:
    """``min f(w, q) s.t. cons, lbw <= w <= ubw``, started at ``w0``.

    ``parameters``: ``(q, values)``, a symbol the expressions depend on and its values (the NLP's p);
    the outcome then holds the `ParametricPoint`. ``multipliers``: ``(lam_x0, lam_g0)``, IPOPT's
    multipliers at ``w0`` from a solve of the same NLP (other bounds allowed) or carried from a coarser
    grid's (`pressocp.ocp.prolong`): a primal-dual warm start with ``warm_options`` (default
    `IPOPT_WARM_START`)."""

    w: Any
    f: Any
    cons: Constraints
    w0: np.ndarray
    lbw: np.ndarray
    ubw: np.ndarray
    parameters: tuple | None = None
    multipliers: tuple[np.ndarray, np.ndarray] | None = None
    warm_options: dict | None = None


@dataclass
class NlpRun:
    """How `solve_nlp` runs IPOPT: the solver's ``name``, complete nlpsol ``options`` (e.g.
    `IPOPT_RIGID` or `IPOPT_WARM` plus overrides), the ``objective`` and its ``scale`` (the iteration
    record's unit), the progress bar (``progress``, labelled ``desc``), and ``keep``: a dict that holds
    the solver afterwards (``keep["solver"]``). CasADi caches the derivatives it builds of a function
    weakly, so a compiled model function's derivatives (built and compiled with the solver) live only
    as long as a solver using them: kept, the next NLP on the same function (a polish round) reuses
    them instead of compiling them again."""

    name: str
    options: dict
    objective: Objective
    scale: float
    desc: str = ""
    progress: bool = False
    keep: dict | None = None


def with_lifted(cons: Constraints, w: ca.MX, q: ca.MX, q0: np.ndarray, w0, lbw, ubw) -> tuple:
    """The decision vector, start and bounds with the constraints' own (lifted) variables appended after
    the transcription's. Each lifted group's start may read the groups made before it."""
    if not cons.lifted:
        return w, w0, lbw, ubw
    nw = w.numel()
    if np.size(w0) == nw:
        w0 = np.asarray(w0, float).ravel()
        done = ca.MX(0, 1)
        for v, e, _, _ in cons.lifted:
            start = ca.Function("lifted_start", [w, q, done], [e])
            w0 = np.concatenate([w0, np.asarray(start(w0[:nw], q0, w0[nw:]), float).ravel()])
            done = ca.vertcat(done, v)
    w = ca.vertcat(w, *[v for v, _, _, _ in cons.lifted])
    lbw = np.concatenate([np.asarray(lbw, float)] + [lo for _, _, lo, _ in cons.lifted])
    ubw = np.concatenate([np.asarray(ubw, float)] + [hi for _, _, _, hi in cons.lifted])
    return w, w0, lbw, ubw


def close_bar(bar, split: dict) -> None:
    """End a stage's progress bar with its time split (s)."""
    bar.set_postfix_str(f"{bar.postfix + '; ' if bar.postfix else ''}{split['build']:.1f} s build, "
                        f"{split['compile']:.1f} s compile, "
                        f"{sum(split[k] for k in EVALUATIONS):.1f} s functions, "
                        f"{split['solver']:.1f} s linear solver", refresh=False)
    bar.close()


def solve_nlp(nlp: NlpData, run: NlpRun) -> NlpOutcome:
    """IPOPT on `nlp` as `run` says. Ctrl-C raises `KeyboardInterrupt` (with ``best`` holding the
    least-infeasible iterate)."""
    w, f, cons, w0, lbw, ubw = nlp.w, nlp.f, nlp.cons, nlp.w0, nlp.lbw, nlp.ubw
    name, options, objective, scale, keep = run.name, run.options, run.objective, run.scale, run.keep
    parameters, multipliers, progress, desc = nlp.parameters, nlp.multipliers, run.progress, run.desc
    t0, c0 = time.perf_counter(), compile_seconds()
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(desc=desc or name, unit="it", leave=True)
    q, q0 = parameter_symbols(parameters)
    nw = w.numel()
    w, w0, lbw, ubw = with_lifted(cons, w, q, q0, w0, lbw, ubw)
    stats: dict = {}
    cb = IterationRecord(w.numel(), cons, objective, scale, bar, q0.size)
    gall = cons.g
    warm = {} if multipliers is None else {"lam_x0": multipliers[0], "lam_g0": multipliers[1]}
    with compiling():  # compiled derivatives are built here
        solver = ca.nlpsol(name, "ipopt", {"x": w, "p": q, "f": f, "g": gall},
                           {**options, **((nlp.warm_options or IPOPT_WARM_START) if warm else {}),
                            "iteration_callback": cb})
    build, compiled = time.perf_counter() - t0, compile_seconds() - c0
    if keep is not None:
        keep["solver"] = solver
    g_fun = ca.Function("constraints", [w, q], [gall])
    viol_start = cons.by_group(g_fun(w0, q0))
    point = None
    try:
        with interruptible() as hit:
            try:
                sol = solver(x0=w0, p=q0, lbx=lbw, ubx=ubw, lbg=cons.lbg, ubg=cons.ubg, **warm)
                lam = (np.asarray(sol["lam_x"]).ravel(), np.asarray(sol["lam_g"]).ravel())
                st = solver.stats()
                stats = st
                wo, success, status = np.asarray(sol["x"]).ravel(), bool(st["success"]), str(st["return_status"])
                iters = int(st.get("iter_count", len(cb.history)))
                its = st.get("iterations", {})
                barrier = [float(m) for m in its.get("mu", [])]
                log = {k: [float(v) for v in its.get(k, [])] for k in ("inf_pr", "inf_du")}
                if q0.size and success:
                    point = ParametricPoint(
                        solver, wo, q0,
                        np.asarray(sol["lam_x"]).ravel(), np.asarray(sol["lam_g"]).ravel(), np.asarray(lbw, float),
                        np.asarray(ubw, float), cons.lbg, cons.ubg, list(cons.groups))
            except RuntimeError as err:  # IPOPT itself raised (e.g. an evaluation error at the start)
                if hit:
                    raise
                wo, success, status, iters = (cb.best[2] if cb.best else w0), False, first_line(err), len(cb.history)
                barrier, log, lam = [], {"inf_pr": [], "inf_du": []}, (None, None)
    except KeyboardInterrupt as stop:
        stop.best = None if cb.best is None else cb.best[2]
        raise
    finally:
        if bar is not None:
            close_bar(bar, timing_split(stats, build, time.perf_counter() - t0, cb.seconds, compiled))
    last = wo
    if not success and cb.best is not None:
        wo = cb.best[2]
    try:
        viol_end = cons.by_group(g_fun(wo, q0))
    except RuntimeError:  # an integrator failing at the returned iterate: the caller locates it
        viol_end = {}
    return NlpOutcome(w=wo[:nw], last_w=last[:nw], success=success, status=status, iterations=iters, history=list(cb.history),
                      barrier=barrier, violations_start=viol_start, violations=viol_end,
                      iteration_log={"time_s": [t - t0 for t in cb.times], **log},
                      wall_time=time.perf_counter() - t0, point=point,
                      timing=timing_split(stats, build, time.perf_counter() - t0, cb.seconds, compiled),
                      lam_x=lam[0], lam_g=lam[1])
