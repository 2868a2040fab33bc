"""One cycle of a press's states and their forward sensitivities, sampled densely by the compiled
driver (`pressocp.cvodes_fsa`), and the derivatives of its peaks read from it.

A peak J = |y(t*)| is differentiated at its time t*: dJ/dp = sign(y) dy/dp at t*. The sensitivity
dy/dp changes quickly about a peak of the seed optimum (a journal on its wall), so t* must be the peak
of the very run that carries the directions: the seed optimum's peak times located on a plain run of
the same tolerance lay 1-4 µs from the sensitivity run's, and that alone made the derivatives' error
against central differences at rtol 1e-12 0.9 % at rtol 1e-8 and 4.8 % at 3e-8; read at the
sensitivity run's own peaks, 0.2-0.3 % at either (docs/decisions/2026-12-02-peaks-of-the-sensitivity-run.md).
So the states and directions are sampled together (`SAMPLES` per cycle), the peaks located on those
samples (a parabola through the top three), and the derivative at t* interpolated by the parabola
through the three samples about it.

The cycle whose directions are kept is also the periodic search's confirming cycle: the search settles
cycle by cycle on the plain driver and runs the cycle expected to settle with its directions; when it
ends within the tolerance of its start, and so does the Newton step from its own monodromy matrix,
that start is the periodic state (one plain cycle fewer than a search followed by a sensitivity run).
Otherwise the next cycle with directions starts from that step: the map contracts strongly (the
largest eigenvalue of dPhi/dx0 is 2.4e-3 at constant speed), so a settled cycle's residual is its
start's distance from the periodic state, and the search's 1000 rtol left states 1e-6 to 1e-5 from
it at rtol 1e-8, which moved derivatives that are cancellations (the contact stiffness's at constant
speed, 2e-17 N m per N/m, came out -5.9e-15); one step takes the state to about 1e-10.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from .cvodes_fsa import ForwardSensitivities, FsaError
from .model import OUTPUT_NAMES, PressModel
from .result import SimResult
from .simulate import (DIRECT, HINT, Integrator, SimulationError, direct_driver, expect_settled, periodic_state,
                       sim_result)
from .speed import FourierSpeed

#: Samples of a cycle in which the peaks are located and their derivatives interpolated. At a tenth of
#: them (2001) the seed optimum's derivatives were off by a factor of 3, at 10 001 by 2.5 %.
SAMPLES = 20001
#: Tolerance of the periodic state, in units of rtol (max-norm of x(T) - x(0), scaled states).
PERIODIC_TOL = 1e3
#: Settling cycles of the periodic search before its cycles with directions.
MAX_SETTLE = 12
#: Newton steps of the periodic search from the cycles with directions (their monodromy matrix) before
#: it hands over to `pressocp.simulate.periodic_state`.
MAX_NEWTON = 3


def parameter_scale(values: np.ndarray) -> np.ndarray:
    """|p| per parameter, 1 where p = 0: the unit of the sensitivity directions. A direction in SI
    units can be far from the states' size (a metre of clearance is 1e4 clearances, a N/m of contact
    stiffness 1e-8 of it), and CVODES's error control weighs the directions' states with the
    states' tolerance: on the seed optimum SI seeds took 59 680 steps for the 11-direction cycle,
    seeds of this unit 37 385, the derivatives the same
    (docs/decisions/2026-11-29-sensitivity-seeds-and-reuse.md)."""
    values = np.abs(np.asarray(values, dtype=float))
    return np.where(values > 0.0, values, 1.0)


def parameter_seeds(nx: int, scale: np.ndarray) -> np.ndarray:
    """The parameter components Q (n_parameters x (nx + n_parameters)) of the directions d/dx0 (first
    nx, none) and d/dq with q = p / `scale` (one each)."""
    Q = np.zeros((scale.size, nx + scale.size))
    Q[:, nx:] = np.diag(scale)
    return Q


def state_motion(end: np.ndarray, periodic: bool) -> np.ndarray:
    """d x(0) / d p from the directions at the cycle's end `end` = [dPhi/dx0, dPhi/dp] (nx x (nx +
    n_parameters)): (I - dPhi/dx0)^-1 dPhi/dp for the periodic state, zero for a start at rest."""
    nx = end.shape[0]
    return np.linalg.solve(np.eye(nx) - end[:, :nx], end[:, nx:]) if periodic else np.zeros((nx, end.shape[1] - nx))


def output_jacobian(msym: PressModel) -> ca.Function:
    """(t, x, speed parameters, press parameters) -> (every output of `OUTPUT_NAMES`, their Jacobians
    with respect to the scaled states and to the press parameters `msym` carries (its ``symbols``,
    SI)), kept with `msym`."""
    if "output_jacobian" not in msym.functions:
        n = len(msym.symbols)
        t, x = ca.SX.sym("t"), ca.SX.sym("x", msym.nx)
        ps, q = ca.SX.sym("ps", msym.p.numel() - n), ca.SX.sym("q", n)
        y = ca.vertcat(*msym.outputs(t, x, ca.vertcat(ps, q)))
        msym.functions["output_jacobian"] = ca.Function("output_jacobian", [t, x, ps, q],
                                                        [y, ca.jacobian(y, x), ca.jacobian(y, q)])
    return msym.functions["output_jacobian"]


def refined(t: np.ndarray, mag: np.ndarray, k: int) -> float:
    """Time of the vertex of the parabola through sample `k` and its neighbours (t[k] at an end)."""
    if 0 < k < mag.size - 1:
        y0, y1, y2 = mag[k - 1], mag[k], mag[k + 1]
        denom = y0 - 2 * y1 + y2
        if denom < 0:
            return float(t[k] + 0.5 * (y0 - y2) / denom * (t[k + 1] - t[k]))
    return float(t[k])


@dataclass
class SensitivityCycle:
    """One cycle of states and directions sampled on a uniform grid.

    Attributes
    ----------
    response : SimResult
        The states and outputs at the samples (``t`` from 0, s).
    X : ndarray, shape (nx, SAMPLES)
        Scaled states at the samples.
    S : ndarray, shape (nx, nx + n_parameters, SAMPLES - 1)
        The directions at the samples after t = 0: d x(t) / d x(0) and d x(t) / d p (per SI unit of
        p); at t = 0 they are the identity and zero.
    dx0 : ndarray, shape (nx, n_parameters)
        d x(0) / d p: the motion of the periodic state, (I - dPhi/dx0)^-1 dPhi/dp; zero for a first
        cycle from rest.
    info : dict
        The periodic search's ``cycles``, ``newton`` steps, ``residual``, ``step`` and ``fallback``
        (`sensitivity_cycle`).
    """

    response: SimResult
    X: np.ndarray
    S: np.ndarray
    dx0: np.ndarray
    info: dict

    def at_peak(self, msym: PressModel, speed: FourierSpeed, t_peak: float, output: int) -> tuple[float, np.ndarray]:
        """The output `output` (index in `OUTPUT_NAMES`) at `t_peak` (s) and sign(y) dy/dp there, each
        interpolated by the parabola through the three samples about it."""
        t = self.response.t
        n, nx = t.size, self.X.shape[0]
        k = min(max(int(round(t_peak / (t[1] - t[0]))), 1), n - 2)
        pv = msym.parameters(speed)
        n_speed = pv.size - self.dx0.shape[1]
        Y = output_jacobian(msym)
        values, derivs = [], []
        for j in (k - 1, k, k + 1):
            v, y_x, y_q = (np.asarray(a) for a in Y(t[j], self.X[:, j], pv[:n_speed], pv[n_speed:]))
            St = np.eye(nx, self.S.shape[1]) if j == 0 else self.S[:, :, j - 1]
            values.append(v[output, 0])
            derivs.append(y_x[output] @ (St[:, :nx] @ self.dx0 + St[:, nx:]) + y_q[output])
        u = (t_peak - t[k]) / (t[k] - t[k - 1])
        w = np.array([0.5 * u * (u - 1.0), 1.0 - u * u, 0.5 * u * (u + 1.0)])
        y = float(w @ np.array(values))
        return y, np.sign(y) * (w @ np.array(derivs))

    def peak_near(self, output: int, t_guess: float, window: float) -> float:
        """Time (s) of the local maximum of |output| nearest `t_guess` within `window` s of it (the
        sample nearest `t_guess` when there is none), located between samples by a parabola."""
        t = self.response.t
        mag = np.abs(getattr(self.response, OUTPUT_NAMES[output]))
        dt = t[1] - t[0]
        lo = max(int(np.floor((t_guess - window) / dt)), 1)
        hi = min(int(np.ceil((t_guess + window) / dt)), t.size - 2)
        k = np.arange(lo, hi + 1)
        maxima = k[(mag[k] >= mag[k - 1]) & (mag[k] >= mag[k + 1])]
        if maxima.size == 0:
            return float(t[min(max(int(round(t_guess / dt)), 0), t.size - 1)])
        return refined(t, mag, int(maxima[np.argmin(np.abs(t[maxima] - t_guess))]))


def sensitivity_cycle(model: PressModel, msym: PressModel, fsa: ForwardSensitivities, speed: FourierSpeed,
                      rtol: float, periodic: bool, extra_cycles: int = 0) -> SensitivityCycle:
    """The cycle of `model` driven by `speed` with its directions (`fsa`, of `msym`: `model` with its
    last parameters as symbols), sampled at `SAMPLES`: the periodic one (to 1000 `rtol` in scaled
    states) when `periodic`, else the first from the model's rest state.

    The periodic search settles from rest on `model`'s plain compiled driver until the next cycle is
    expected to settle (`pressocp.simulate.expect_settled`), then `extra_cycles` plain cycles more,
    then runs cycles with directions (`newton_cycles`); when those do not reach the tolerance,
    `periodic_state` searches from the best of them (settling, then Newton's method on difference
    Jacobians with a line search) and one cycle with directions runs from its answer. ``info``
    of the result: ``cycles`` (plain and with directions), ``newton`` steps, ``residual`` (of the
    cycle returned), ``step`` (the Newton step from it, max-norm of scaled states; nan after the
    fallback), ``fallback`` (whether `periodic_state` finished the search).

    Raises
    ------
    SimulationError
        A run failed, or the periodic search did not converge.
    """
    tol = PERIODIC_TOL * rtol
    if not periodic:
        return with_directions(model, msym, fsa, speed, model.x0, rtol, periodic,
                               {"cycles": 1, "newton": 0, "residual": np.nan, "step": np.nan, "fallback": False})
    x, plain = settled(model, speed, rtol, tol, extra_cycles)
    run, best, runs = newton_cycles(model, msym, fsa, speed, x, rtol, tol)
    if run is not None:
        run.info.update(cycles=plain + runs, newton=runs - 1, fallback=False)
        return run
    x, info = periodic_state(model, speed, Integrator(DIRECT, rtol), x_start=best, tol=tol)
    run = with_directions(model, msym, fsa, speed, x, rtol, periodic, {})
    run.info.update(cycles=plain + runs + info["cycles"] + 1, newton=runs - 1 + info["newton"],
                    residual=info["residual"], step=np.nan, fallback=True)
    return run


def settled(model: PressModel, speed: FourierSpeed, rtol: float, tol: float,
            extra_cycles: int) -> tuple[np.ndarray, int]:
    """The state after plain cycles from rest on `model`'s compiled driver until the next is expected
    to settle within `tol` (at most `MAX_SETTLE`), then `extra_cycles` more; and the cycles run."""
    driver = direct_driver(model, False)
    p = model.parameters(speed)
    none = (np.zeros((model.nx, 0)), np.zeros((0, 0)))
    x, residuals, extra = model.x0, [], 0
    while len(residuals) < MAX_SETTLE:
        if expect_settled(residuals, tol, from_rest=True):
            if extra == extra_cycles:
                break
            extra += 1
        try:
            x_next = driver.run(x, p, *none, np.array([speed.period]), rtol)[0][:, 0]
        except FsaError as err:
            raise SimulationError(str(err), time=err.time, method=DIRECT, hint=HINT) from None
        residuals.append(max(float(np.max(np.abs(x_next - x))), np.finfo(float).tiny))
        x = x_next
    return x, len(residuals)


def newton_cycles(model: PressModel, msym: PressModel, fsa: ForwardSensitivities, speed: FourierSpeed,
                  x: np.ndarray, rtol: float, tol: float) -> tuple[SensitivityCycle | None, np.ndarray, int]:
    """Cycles with directions from `x`, each from the last one's start plus its Newton step
    (I - dPhi/dx0)^-1 (x(T) - x(0)) from its own monodromy matrix, at most `MAX_NEWTON` steps, while
    the residual falls: (the answer or None, the start with the lowest residual, cycles run).

    The answer is the first cycle whose residual and step are both within `tol`; else, once the
    residual stops falling or a step's cycle fails (through impacts the period map is not smooth
    enough for these steps), the cycle with the lowest residual when that residual is within `tol`
    (its step, which a residual at the integrator's noise can inflate, is in ``info``); else None."""
    nx = model.nx
    best: SensitivityCycle | None = None
    for newton in range(MAX_NEWTON + 1):
        try:
            run = with_directions(model, msym, fsa, speed, x, rtol, True, {})
        except SimulationError:
            if best is None:
                raise
            break
        change = run.X[:, -1] - x
        res = float(np.max(np.abs(change)))
        try:
            step = np.linalg.solve(np.eye(nx) - run.S[:, :nx, -1], change)
        except np.linalg.LinAlgError:
            step = np.full(nx, np.nan)
        size = float(np.max(np.abs(step)))  # nan when the step is
        run.info.update(residual=res, step=size)
        if res <= tol and size <= tol:
            return run, x, newton + 1
        if best is not None and res >= best.info["residual"]:
            break
        best = run
        if not np.isfinite(size):
            break
        x = x + step
    runs = newton + 1
    if best.info["residual"] <= tol:
        return best, best.X[:, 0], runs
    return None, best.X[:, 0], runs


def with_directions(model: PressModel, msym: PressModel, fsa: ForwardSensitivities, speed: FourierSpeed,
                    x0: np.ndarray, rtol: float, periodic: bool, info: dict) -> SensitivityCycle:
    """One cycle from the scaled state `x0` with its nx + n_parameters directions, sampled at `SAMPLES`,
    and its outputs. The directions are kept at every sample: SAMPLES nx (nx + n_parameters)
    doubles, 15 MB on the rigid rod with both clearances (8 states) and 3 parameters, about 300 MB on
    the 8-element rod (40 states) with 7. The samples' spacing is the period's 20 000th: 40 µs at
    75 spm, where 10 001 samples put the seed optimum's derivatives 2.5 % off."""
    nx, n_par = model.nx, fsa.n_parameters
    t = np.linspace(0.0, speed.period, SAMPLES)
    pv = msym.parameters(speed)
    # differentiated with respect to q = p / scale: the directions' states are then of the states'
    # own size, and the error control weighs them alike
    scale = parameter_scale(pv[pv.size - n_par:])
    Q = parameter_seeds(nx, scale)
    try:  # Ctrl-C stops it (KeyboardInterrupt)
        X, S, stats = fsa.run(x0, pv, np.eye(nx, nx + n_par), Q, t[1:], rtol)
    except FsaError as err:
        raise SimulationError(str(err), time=err.time, method="cvodes (sensitivities)", hint=HINT) from None
    X = np.hstack([x0[:, None], X])
    S[:, nx:, :] /= scale[:, None]
    dx0 = state_motion(S[:, :, -1], periodic)
    response = sim_result(model, model.parameters(speed), t, X, None,
                          {"steps": int(stats["steps"]), "rhs_evaluations": int(stats["rhs"])}, DIRECT)
    return SensitivityCycle(response, X, S, dx0, info)


__all__ = ["PERIODIC_TOL", "SAMPLES", "SensitivityCycle", "output_jacobian", "parameter_scale", "parameter_seeds",
           "refined", "sensitivity_cycle", "state_motion"]
