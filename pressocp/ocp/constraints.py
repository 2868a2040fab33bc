"""Constraint pieces shared by the transcriptions: a named collector, the closed-form constraints
on the Fourier coefficients (epigraph, working window, crank speed and acceleration bounds) and the
lifted crank motion (theta, omega, alpha at sample times as variables tied linearly to them)."""

from __future__ import annotations

import casadi as ca
import numpy as np

from ..speed import FourierSpeed, series
from .problem import SpeedProblem


def violation(g: np.ndarray, lbg: np.ndarray, ubg: np.ndarray) -> np.ndarray:
    """Amount by which each constraint value lies outside [lbg, ubg] (0 inside)."""
    return np.maximum(lbg - g, 0.0) + np.maximum(g - ubg, 0.0)


class Constraints:
    """lbg <= g <= ubg built group by group; ``groups`` keeps (name, first index, size)."""

    def __init__(self) -> None:
        self._g: list = []
        self._lb: list[np.ndarray] = []
        self._ub: list[np.ndarray] = []
        self.groups: list[tuple[str, int, int]] = []
        self.size = 0

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


def add_epigraph(cons: Constraints, loads: list, s, scale: float) -> None:
    """-s <= q <= s for every load sample, scaled by ``scale``."""
    for q in loads:
        cons.add((q - s) / scale, -np.inf, 0.0, "epigraph")
        cons.add((-q - s) / scale, -np.inf, 0.0, "epigraph")


def add_window(cons: Constraints, problem: SpeedProblem, f_kin: ca.Function, c, t1, samples: int,
               backoff: float = 1.0) -> None:
    """Kinematic ram speed within ``backoff`` x tol at ``samples`` points of [t1, t2], h(t1) = h1 H on
    the downstroke. ``f_kin`` is (t, c) -> (h, v, theta); ``t1`` a number or a symbol."""
    P = problem
    tw = t1 + P.window_duration * ca.DM(np.linspace(0.0, 1.0, samples)).T
    _, vw, _ = f_kin.map(samples)(tw, ca.repmat(c, 1, samples))
    cons.add((vw - P.ram_speed) / P.tol, -backoff, backoff, "ram_speed_kinematic")
    h1, _, th1 = f_kin(t1, c)
    cons.add(h1 / P.params.stroke - P.window[0], 0.0, 0.0, "window_start")
    cons.add(th1, 0.0, np.pi, "window_start")


def add_speed_bounds(cons: Constraints, problem: SpeedProblem, omega, alpha) -> None:
    """omega_min <= omega (<= omega_max) and |alpha| <= alpha_max at the given samples."""
    P = problem
    wbar = 2 * np.pi / P.period
    cons.add(omega / wbar, P.omega_lower / wbar, np.inf if P.omega_max is None else P.omega_max / wbar, "omega")
    if P.alpha_max is not None:
        cons.add(alpha / P.alpha_max, -1.0, 1.0, "alpha")


def crank_motion(speed: FourierSpeed, times: np.ndarray) -> np.ndarray:
    """Crank angle, speed and acceleration (rows; rad, rad/s, rad/s^2) of `speed` at `times`, s."""
    return np.array(series(times, speed.a, speed.b, speed.period, speed.theta0))


def crank_map(n: int, period: float, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The crank motion at `times` as an affine map of the 2n Fourier coefficients (theta0 = 0):
    ``vec(motion) = m0 + A @ c`` with motion 3 x len(times) stacked by column (`crank_motion`)."""
    zero = np.zeros(n)
    m0 = crank_motion(FourierSpeed(period, zero, zero), times).ravel(order="F")
    A = np.column_stack([crank_motion(FourierSpeed(period, e[:n], e[n:]), times).ravel(order="F") - m0
                         for e in np.eye(2 * n)])
    return m0, A


def crank_scale(period: float) -> np.ndarray:
    """Scales of (theta, omega, alpha) for a period T: 1 rad, the mean speed 2 pi/T and its square."""
    w_bar = 2 * np.pi / period
    return np.array([1.0, w_bar, w_bar**2])


def add_crank_motion(cons: Constraints, W, c, period: float, times: np.ndarray) -> None:
    """W (3 x len(times): theta, omega, alpha) equals the Fourier series of the coefficients ``c``
    at ``times``: a linear equality (group "crank_motion"), scaled by `crank_scale`.

    Lifting the crank motion into variables makes each sample's loads depend on its own three
    variables only, so the exact Hessian of the Lagrangian is block-diagonal instead of dense in
    the 2n coefficients over all samples."""
    m0, A = crank_map(c.numel() // 2, period, times)
    scale = np.tile(crank_scale(period), len(times))
    cons.add((ca.vec(W) - ca.mtimes(ca.DM(A), c) - m0) / scale, 0.0, 0.0, "crank_motion")
