"""Parametric sensitivity of an NLP at its solution: the implicit function theorem on the KKT
system (sIPOPT's approach, Pirnay, López-Negrete and Biegler 2012).

At IPOPT's solution of ``min f(x, p) s.t. lbg <= g(x, p) <= ubg, lbx <= x <= ubx``, stationarity
``grad f + J' lam_g + lam_x = 0`` and the complementarity of each bound, ``|lam_i| slack_i = mu``,
are differentiated with respect to p:

    [ H    J_A'     ] [ dx/dp     ]     [ d(grad_x L)/dp ]
    [ J_A  -diag(D) ] [ dlam_A/dp ] = - [ dg_A/dp        ],     D_i = slack_i / |lam_i|

over the constraints whose multiplier outweighs their slack (A; equalities have D = 0); the others
keep a zero multiplier. Strongly active constraints (slack ~ 0) are held, weakly active ones (slack
and multiplier both ~ 0) enter with their barrier weight, which is where the derivative of the
optimum is one-sided, and they are counted. The optimal value's derivative is the envelope theorem's
dL/dp = df/dp + lam_g' dg/dp; ``df_dp_direct`` recomputes it from dx/dp as a check.

The linear prediction also says how far p may move before the active set changes: an active
constraint leaves when its multiplier reaches zero, an inactive one enters when it reaches a bound.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from .nlp import ParametricPoint

#: A constraint at its bound with both slack and multiplier below this (scaled units) is weakly active.
WEAK_TOL = 1e-4


@dataclass
class KktSensitivity:
    """Derivatives of an NLP's solution with respect to its parameters p.

    Attributes
    ----------
    df_dp : ndarray, (np,)
        Derivative of the optimal objective (envelope theorem: dL/dp at the solution).
    df_dp_direct : ndarray, (np,)
        The same from the solution's derivative: grad_x f . dx/dp + df/dp (a check of the linear solve).
    dx_dp : ndarray, (nx, np)
    active, weak : ndarray of bool, (ng,)
        Inequality constraints held in the solve (active), and those at their bound with a multiplier
        near zero (weakly active).
    step_up, step_down : ndarray, (np,)
        Steps of each parameter (its unit; ``step_down`` <= 0) to the first predicted active-set change
        of a constraint that is not weakly active (inf when none is predicted).
    change_up, change_down : list of str
        The constraint group that changes first, per parameter ("" when none).
    residual : float
        Relative residual of the KKT solve.
    """

    df_dp: np.ndarray
    df_dp_direct: np.ndarray
    dx_dp: np.ndarray
    active: np.ndarray
    weak: np.ndarray
    step_up: np.ndarray
    step_down: np.ndarray
    change_up: list
    change_down: list
    residual: float


def side(lam: np.ndarray, value: np.ndarray, lb: np.ndarray, ub: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(slack to the bound the multiplier pushes against, equality mask). CasADi's multipliers are
    positive at an upper bound and negative at a lower one; slack is inf for a zero multiplier."""
    eq = lb == ub
    slack = np.where(lam > 0, ub - value, np.where(lam < 0, value - lb, np.inf))
    return np.where(eq, 0.0, np.maximum(slack, 0.0)), eq


def first_changes(steps: np.ndarray, who: np.ndarray) -> tuple[float, float, str, str]:
    """The smallest positive and the largest negative of `steps` (NaN ignored) and their labels
    (inf/-inf and "" when there is none)."""
    steps = np.where(np.isnan(steps), np.inf, steps)
    pos, neg = np.where(steps > 0, steps, np.inf), np.where(steps < 0, steps, -np.inf)
    ku, kd = (int(np.argmin(pos)), int(np.argmax(neg))) if steps.size else (0, 0)
    up, down = (float(pos[ku]), float(neg[kd])) if steps.size else (np.inf, -np.inf)
    return up, down, str(who[ku]) if np.isfinite(up) else "", str(who[kd]) if np.isfinite(down) else ""


def events(lam: np.ndarray, dlam: np.ndarray, value: np.ndarray, rate: np.ndarray, lb: np.ndarray, ub: np.ndarray,
           held: np.ndarray, eq: np.ndarray) -> np.ndarray:
    """Parameter steps at which a held inequality's multiplier reaches zero or a free constraint
    reaches one of its bounds (one column per kind; NaN or inf where never)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        leave = np.where(held & ~eq, -lam / dlam, np.nan)
        upper = np.where(~held, (ub - value) / rate, np.nan)
        lower = np.where(~held, (lb - value) / rate, np.nan)
    return np.stack([leave, upper, lower], axis=1)


def kkt_sensitivity(point: ParametricPoint) -> KktSensitivity:
    """dx/dp, d(optimal f)/dp and the predicted range of the active set at `point`."""
    nx, npar, ng = point.x.size, point.p.size, point.lbg.size
    x, p, lg = ca.MX.sym("x", nx), ca.MX.sym("p", npar), ca.MX.sym("lam_g", ng)
    f, g = point.nlp(x, p)
    lag = f + ca.dot(lg, g)
    grad = ca.gradient(lag, x)
    H = ca.hessian(lag, x)[0]
    fun = ca.Function("kkt", [x, p, lg], [H, ca.jacobian(grad, p), ca.jacobian(g, x), ca.jacobian(g, p),
                                          ca.gradient(f, x), ca.jacobian(lag, p).T, ca.jacobian(f, p).T, g])
    H, Hp, J, Gp, fx, Lp, fp, gv = fun(point.x, point.p, point.lam_g)
    gv = np.asarray(gv).ravel()

    slack_g, eq_g = side(point.lam_g, gv, point.lbg, point.ubg)
    slack_x, eq_x = side(point.lam_x, point.x, point.lbx, point.ubx)
    held_g = eq_g | (np.abs(point.lam_g) >= slack_g)
    held_x = eq_x | (np.abs(point.lam_x) >= slack_x)
    ig, ix = np.flatnonzero(held_g), np.flatnonzero(held_x)
    dg = np.where(eq_g, 0.0, slack_g / np.where(point.lam_g == 0, 1.0, np.abs(point.lam_g)))[ig]
    dxb = np.where(eq_x, 0.0, slack_x / np.where(point.lam_x == 0, 1.0, np.abs(point.lam_x)))[ix]

    Ja = J[ig.tolist(), :]
    E = ca.DM.triplet(list(range(ix.size)), ix.tolist(), [1.0] * ix.size, ix.size, nx)
    K = ca.blockcat([[H, Ja.T, E.T],
                     [Ja, -ca.diag(ca.DM(dg)), ca.DM(ig.size, ix.size)],
                     [E, ca.DM(ix.size, ig.size), -ca.diag(ca.DM(dxb))]])
    rhs = -ca.vertcat(Hp, Gp[ig.tolist(), :], ca.DM(ix.size, npar))
    sol = ca.solve(K, ca.densify(rhs), "mumps")
    residual = float(ca.norm_fro(ca.mtimes(K, sol) - rhs) / max(float(ca.norm_fro(rhs)), 1e-300))
    sol = np.asarray(sol)
    dx = sol[:nx, :]
    dlam_g = np.zeros((ng, npar))
    dlam_g[ig, :] = sol[nx : nx + ig.size, :]
    dlam_x = np.zeros((nx, npar))
    dlam_x[ix, :] = sol[nx + ig.size :, :]

    # where the active set changes, per parameter
    weak = ~eq_g & np.isfinite(slack_g) & (slack_g < WEAK_TOL) & (np.abs(point.lam_g) < WEAK_TOL)
    rate_g = np.asarray(ca.mtimes(J, ca.DM(dx)) + Gp)
    names = np.empty(ng, dtype=object)
    for name, i0, k in point.groups:
        names[i0 : i0 + k] = name
    who = np.concatenate([np.repeat(names, 3), np.full(3 * nx, "variable bound", dtype=object)])
    changes = []
    for j in range(npar):  # weakly active constraints change at once; they are counted, not timed
        ev_g = events(point.lam_g, dlam_g[:, j], gv, rate_g[:, j], point.lbg, point.ubg, held_g, eq_g)
        ev_g[weak, :] = np.nan
        ev_x = events(point.lam_x, dlam_x[:, j], point.x, dx[:, j], point.lbx, point.ubx, held_x, eq_x)
        changes.append(first_changes(np.concatenate([ev_g.ravel(), ev_x.ravel()]), who))
    fx = np.asarray(fx).ravel()
    return KktSensitivity(
        df_dp=np.asarray(Lp).ravel(), df_dp_direct=fx @ dx + np.asarray(fp).ravel(), dx_dp=dx,
        active=held_g & ~eq_g, weak=weak, step_up=np.array([c[0] for c in changes]),
        step_down=np.array([c[1] for c in changes]), change_up=[c[2] for c in changes],
        change_down=[c[3] for c in changes], residual=residual)


__all__ = ["KktSensitivity", "WEAK_TOL", "kkt_sensitivity"]
