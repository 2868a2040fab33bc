"""`MultipleShooting`: the period cut into N equal intervals, each integrated by SUNDIALS (IDAS or
CVODES, on the explicit ODE) from its node state, with the loads at S output
samples inside it. The interval integrator is built once, given forward-mode sensitivities (the
backward IDAS pass fails on clearance contact) and mapped over the intervals in threads. The NLP
variables are the Fourier coefficients, the node states and the epigraph variable; IPOPT uses a
limited-memory Hessian.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import casadi as ca
import numpy as np

from .. import checks as chk
from ..model import OUTPUT_NAMES, PressModel
from ..problem import SpeedProblem
from ..compile_cache import check_jit, use_jit
from ..interrupt import compiling
from ..simulate import HINT, SimulationError, calling, compiled_dae, first_line
from .nlp import Constraints, UniformPartition
from .stage import StageResult, WarmStart
from .states import (StageRun, StateNlp, StateSettings, check_states, keep_contact, sample_outputs, solve_states,
                     warm_states)

INTEGRATORS = ("idas", "cvodes")


class ShootingError(SimulationError):
    """An interval integrator failed. Attributes: ``stage``, ``interval`` (0-based), ``t_start``, ``t_end``."""

    def __init__(self, message: str, stage: str, interval: int, t_start: float, t_end: float, method: str):
        self.stage, self.interval, self.t_start, self.t_end = stage, interval, t_start, t_end
        super().__init__(f"stage {stage!r}, shooting interval {interval} (t = {t_start:.4g}..{t_end:.4g} s): "
                         f"{message}", method=method, hint=HINT)


@dataclass(frozen=True)
class ShootingGrid(UniformPartition):
    """The period (s) cut into N = ``intervals`` equal shooting intervals, with S = ``samples`` output
    samples in each (the last one at the interval's end)."""

    period: float
    intervals: int
    samples: int

    @property
    def pieces(self) -> int:
        return self.intervals

    @property
    def nodes(self) -> np.ndarray:
        """Start times of the intervals, s."""
        return self.starts

    @property
    def local(self) -> np.ndarray:
        """Sample times inside an interval, measured from its start, s."""
        return self.h * np.arange(1, self.samples + 1) / self.samples

    @property
    def times(self) -> np.ndarray:
        """All sample times in the order of the mapped outputs, s."""
        return (self.nodes[:, None] + self.local[None, :]).ravel()


def interval_function(model: PressModel, grid: ShootingGrid, names: tuple[str, ...], integrator: str = "idas",
                      rtol: float = 1e-6, atol: float | None = None, max_steps: int = 10**6,
                      jit: bool | str = False) -> ca.Function:
    """One shooting interval as a CasADi Function with forward-mode derivatives. With `jit` (True, or
    "auto": when a C compiler is found) the integrator evaluates the DAE and its derivatives as compiled
    code (`pressocp.simulate.calling`).

    Both integrators take the explicit ODE (the accelerations solved for in the right-hand side); IDAS
    computes its consistent state derivative with IDACalcIC, which is exact on an ODE. On the
    semi-explicit DAE IDACalcIC could fail where CVODES integrated
    (docs/decisions/2026-11-27-idas-shooting-ode.md).

    Returns
    -------
    ca.Function
        ``(x0 [nx], p [np], t0) -> (xf [nx], y [len(names) x S])``: scaled end state and the outputs
        `names` (see `pressocp.model.OUTPUT_NAMES`) at ``t0 + grid.local``.
    """
    chk.choice("integrator", integrator, INTEGRATORS)
    tau, t0 = ca.SX.sym("tau"), ca.SX.sym("t0")
    dae = model.dae(explicit=True, work=False)
    dae.update(ode=ca.substitute(dae["ode"], model.t, tau + t0), t=tau, p=ca.vertcat(model.p, t0))
    if use_jit(jit, "the shooting intervals"):
        dae = calling(compiled_dae(dae))
    opts = {"reltol": rtol, "abstol": rtol if atol is None else atol, "max_num_steps": max_steps}
    if integrator == "idas":
        opts.update(calc_ic=True)
    with compiling():  # SUNDIALS's Jacobian of a compiled DAE is compiled here
        F = ca.integrator("shooting_" + integrator, integrator, dae, 0.0, grid.local, opts)
    x0, p, ts = ca.MX.sym("x0", model.nx), ca.MX.sym("p", model.p.numel()), ca.MX.sym("t0")
    X = F(x0=x0, p=ca.vertcat(p, ts))["xf"]
    S = grid.samples
    out = model.outputs.map(S)(ts + ca.DM(grid.local).T, X, ca.repmat(p, 1, S))
    y = ca.vertcat(*[out[OUTPUT_NAMES.index(n)] for n in names])
    return ca.Function("interval", [x0, p, ts], [X[:, -1], y], ["x0", "p", "t0"], ["xf", "y"],
                       {"ad_weight": 0.0, "ad_weight_sp": 0.0})


def locate_failure(G: ca.Function, X: np.ndarray, p: np.ndarray, grid: ShootingGrid, stage: str,
                   integrator: str) -> ShootingError | None:
    """Integrate every interval separately; the first failure as a `ShootingError`, or None."""
    for k, t0 in enumerate(grid.nodes):
        try:
            xf, y = G(X[:, k], p, t0)
            if not (np.all(np.isfinite(np.asarray(xf))) and np.all(np.isfinite(np.asarray(y)))):
                raise RuntimeError("non-finite state or output")
        except RuntimeError as err:
            return ShootingError(first_line(err), stage, k, float(t0), float(t0 + grid.h), integrator)
    return None


@dataclass(frozen=True, repr=False)
class MultipleShooting(StateSettings):
    """Multiple shooting through a SUNDIALS integrator, limited-memory Hessian.

    Attributes
    ----------
    integrator : {"idas", "cvodes"}
        Interval integrator.
    intervals : int
        Intervals per period, 1..400.
    samples : int
        Output samples per interval for the load and ram-speed constraints, 1..1000. The ram speed is
        also held at the two samples that bracket the working window, up to one sample spacing outside
        it, so coarse samples ask more than the problem does: on the slender-rod scene (16 intervals)
        collocation's optimum broke those bounds by 0.42 x the tolerance at 25 samples and shooting
        ended 2.8 % higher; at 100, by 0.06 x, and it ended 1.7 % lower (2026-11-27).
    rtol : float
        Integrator tolerance (atol = rtol on the scaled states).
    max_steps : int
        Step limit of each interval integration.
    coefficient_step : float or None
        Trust region, rad/s: every Fourier coefficient stays within this of the start's.
    jit : bool or "auto"
        Integrate with the DAE and its derivatives compiled ("auto": when a C compiler is found).
    min_eccentricity, periodic, backoff, omega_samples, ipopt
        Keyword-only, as in `StateSettings` (by default no contact kept).
    """

    integrator: str = "idas"
    intervals: int = 16
    samples: int = 25
    rtol: float = 1e-6
    max_steps: int = 10**6
    coefficient_step: float | None = None
    jit: bool | str = "auto"

    #: A start that impacts is first solved with a softer contact (`Strategy.soft_factor`).
    needs_soft_start: ClassVar[bool] = True

    def __post_init__(self) -> None:
        super().__post_init__()
        chk.choice("integrator", self.integrator, INTEGRATORS)
        chk.integer("intervals", self.intervals, 1, 400)
        chk.integer("samples", self.samples, 1, 1000)
        chk.positive("rtol", self.rtol)
        chk.integer("max_steps", self.max_steps, 1, 10**9)
        if self.coefficient_step is not None:
            chk.positive("coefficient_step", self.coefficient_step, "rad/s")
        check_jit(self.jit)

    def grid(self, period: float) -> ShootingGrid:
        return ShootingGrid(period, self.intervals, self.samples)

    def shooting(self) -> "MultipleShooting":
        """This transcription: the strategy's trust-region refinement runs it."""
        return self

    def solve(self, problem: SpeedProblem, model: PressModel, start: WarmStart, name: str = "target",
              progress: bool = False) -> StageResult:
        """One multiple-shooting stage on `model`, warm-started at the start speed's periodic response.

        Raises
        ------
        ShootingError
            When the warm start itself cannot be integrated (no iterate to return).
        """
        check_states(problem, model)
        grid = self.grid(problem.period)
        N, S = grid.intervals, grid.samples
        rtol = min(self.rtol, 1e-7)
        nodes, warm = warm_states(model, start, grid.nodes, rtol)
        names = sample_outputs(problem, model, self.min_eccentricity)
        G = interval_function(model, grid, names, self.integrator, self.rtol, max_steps=self.max_steps, jit=self.jit)
        p0 = model.parameters(start.speed)
        Gm = G.map(N, "thread", 2)
        try:
            y0 = np.asarray(Gm(nodes, np.tile(p0[:, None], (1, N)), grid.nodes[None, :])[1])
        except RuntimeError:
            y0 = None
        if y0 is None or not np.all(np.isfinite(y0)):  # find the interval, one at a time
            raise locate_failure(G, nodes, p0, grid, name, self.integrator) or SimulationError(
                f"stage {name!r}: the mapped intervals failed, each alone integrates", method=self.integrator,
                hint=HINT)

        n = problem.n_harmonics
        c = ca.MX.sym("c", 2 * n)
        X = ca.MX.sym("X", model.nx, N)
        Xf, Y = Gm(X, ca.repmat(ca.vertcat(c, problem.period, 0.0), 1, N), ca.DM(grid.nodes).T)
        cons = _continuity(X, Xf, self.periodic)
        y = {k: Y[i, :] for i, k in enumerate(names)}
        keep_contact(cons, y, model, self.min_eccentricity)
        nlp = StateNlp(c, ca.vec(X), nodes.ravel(order="F"), y, {k: y0[i : i + 1, :] for i, k in enumerate(names)},
                       grid.times, cons, fixed=None if self.periodic else np.arange(model.nx),
                       coefficient_step=self.coefficient_step)
        run = StageRun(name, f"{name} ({N}x{S} {self.integrator})", self.ipopt, progress,
                       {"intervals": N, "samples": S, **warm})
        r = solve_states(problem, model, start.speed, nlp, run, self)
        r.states = r.states.reshape(nodes.shape, order="F")
        r.settings = self.settings()
        if not r.success:
            failure = locate_failure(G, r.states, model.parameters(r.speed), grid, name, self.integrator)
            if failure is not None:
                r.status, r.violations = f"{r.status}; {failure}", {}
        return r


def _continuity(X, Xf, periodic: bool) -> Constraints:
    """Constraints with the node continuity x_end(k) = x_node(k+1) (the last wraps when periodic)."""
    cons = Constraints()
    nxt = ca.horzcat(X[:, 1:], X[:, :1]) if periodic else X[:, 1:]
    cons.add((Xf if periodic else Xf[:, :-1]) - nxt, 0.0, 0.0, "continuity")
    return cons
