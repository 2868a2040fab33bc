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

import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ..ipopt_options import IPOPT_TRACKING
from .nlp import ParametricPoint

#: A constraint at its bound with both slack and multiplier below this (scaled units) is weakly active.
WEAK_TOL = 1e-4
#: Regularisations of a singular KKT matrix's constraint block, tried in turn, and the refinement steps.
DELTAS = (1e-10, 1e-8, 1e-6)
REFINEMENTS = 3


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
        Relative residual of the KKT solve (against the unregularised matrix).
    regularisation : float
        The -delta I added to the constraint block of a singular KKT matrix (0: none). A singular
        matrix means dependent held constraints: their multipliers, and so dJ*/dp, are one of a set.
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
    regularisation: float = 0.0


def side(lam: np.ndarray, value: np.ndarray, lb: np.ndarray, ub: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(slack to the bound the multiplier pushes against, equality mask). CasADi's multipliers are
    positive at an upper bound and negative at a lower one; slack is inf for a zero multiplier."""
    eq = lb == ub
    slack = np.where(lam > 0, ub - value, np.where(lam < 0, value - lb, np.inf))
    return np.where(eq, 0.0, np.maximum(slack, 0.0)), eq


def held(lam: np.ndarray, value: np.ndarray, lb: np.ndarray, ub: np.ndarray) -> tuple:
    """The bounds held in the KKT solve: equalities and those whose multiplier outweighs their slack.
    Returns (slack, equality mask, held mask, barrier weights slack/|lam| of the held ones)."""
    slack, eq = side(lam, value, lb, ub)
    mask = eq | (np.abs(lam) >= slack)
    weight = np.where(eq, 0.0, slack / np.where(lam == 0, 1.0, np.abs(lam)))[mask]
    return slack, eq, mask, weight


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


def solve_kkt(K, rhs: np.ndarray, nx: int) -> tuple[np.ndarray, float, float]:
    """Solve the KKT system K sol = rhs (SuperLU). When K is singular (the held constraints are
    dependent: a min-max optimum holds more samples than it has degrees of freedom, so their
    multipliers are not unique), the constraint block is regularised by -delta I, as IPOPT does, and
    the answer refined against K itself (`REFINEMENTS` steps); delta grows until the factorisation
    succeeds. Returns (sol, relative residual against K, delta; 0 without regularisation)."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    norm = max(float(np.linalg.norm(rhs)), 1e-300)
    try:
        sol = splu(K).solve(rhs)
        residual = float(np.linalg.norm(K @ sol - rhs)) / norm
        if np.isfinite(residual) and residual < 1e-8:
            return sol, residual, 0.0
    except RuntimeError:  # exactly singular
        pass
    m = K.shape[0] - nx
    for delta in DELTAS:
        shift = sp.diags(np.concatenate([np.zeros(nx), np.full(m, -delta)]), format="csc")
        try:
            lu = splu((K + shift).tocsc())
        except RuntimeError:
            continue
        sol = lu.solve(rhs)
        for _ in range(REFINEMENTS):
            sol = sol + lu.solve(rhs - K @ sol)
        return sol, float(np.linalg.norm(K @ sol - rhs)) / norm, delta
    raise np.linalg.LinAlgError("the KKT matrix stays singular with regularisation up to "
                                f"{DELTAS[-1]:g}: the NLP's solution is not a regular point")


def derivatives(point: ParametricPoint) -> tuple:
    """The NLP's derivatives at the solution, from the solver's own (compiled) functions: the Hessian
    of the Lagrangian H (sparse), the constraint Jacobian J (sparse), d(grad_x L)/dp and dg/dp (dense,
    n x np), grad_x f, df/dp and dL/dp, and g."""
    S, x, p, lam = point.solver, point.x, point.p, point.lam_g
    nx, npar, ng = x.size, p.size, lam.size
    H = ca.triu2symm(S.get_function("nlp_hess_l")(x, p, 1.0, lam))
    _, J = S.get_function("nlp_jac_g")(x, p)
    grad = S.get_function("nlp_grad")
    f, g, gx, gp = grad(x, p, 1.0, lam)
    seeds = (np.zeros((nx, npar)), np.eye(npar), np.zeros((1, npar)), np.zeros((ng, npar)))
    fp, Gp, Hp, _ = grad.forward(npar)(x, p, 1.0, lam, f, g, gx, gp, *seeds)
    _, fx = S.get_function("nlp_grad_f")(x, p)
    return (H.sparse(), J.sparse(), np.asarray(Hp), np.asarray(Gp), np.asarray(fx).ravel(), np.asarray(fp).ravel(),
            np.asarray(gp).ravel(), np.asarray(g).ravel())


def kkt_sensitivity(point: ParametricPoint) -> KktSensitivity:
    """dx/dp, d(optimal f)/dp and the predicted range of the active set at `point`.

    The KKT matrix is factorised by SuperLU (scipy), with partial pivoting: the matrix is symmetric
    but indefinite, and a min-max optimum holds more active constraints than it has degrees of
    freedom, which only the barrier weights keep nonsingular (CasADi's MUMPS interface returned a
    wrong solution on the 75 spm collocation KKT matrix, residual 2e2)."""
    import scipy.sparse as sp

    nx, npar, ng = point.x.size, point.p.size, point.lbg.size
    H, J, Hp, Gp, fx, fp, Lp, gv = derivatives(point)
    slack_g, eq_g, held_g, dg = held(point.lam_g, gv, point.lbg, point.ubg)
    _, eq_x, held_x, dxb = held(point.lam_x, point.x, point.lbx, point.ubx)
    ig, ix = np.flatnonzero(held_g), np.flatnonzero(held_x)
    J = sp.csr_matrix(J)
    Ja = J[ig, :]
    E = sp.csr_matrix((np.ones(ix.size), (np.arange(ix.size), ix)), shape=(ix.size, nx))
    K = sp.bmat([[H, Ja.T, E.T], [Ja, -sp.diags(dg), None], [E, None, -sp.diags(dxb)]], format="csc")
    rhs = -np.vstack([Hp, Gp[ig, :], np.zeros((ix.size, npar))])
    sol, residual, regularisation = solve_kkt(K, rhs, nx)
    dx = sol[:nx, :]
    dlam_g = np.zeros((ng, npar))
    dlam_g[ig, :] = sol[nx : nx + ig.size, :]
    dlam_x = np.zeros((nx, npar))
    dlam_x[ix, :] = sol[nx + ig.size :, :]

    # where the active set changes, per parameter
    weak = ~eq_g & np.isfinite(slack_g) & (slack_g < WEAK_TOL) & (np.abs(point.lam_g) < WEAK_TOL)
    rate_g = J @ dx + Gp
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
    return KktSensitivity(
        df_dp=Lp, df_dp_direct=fx @ dx + fp, dx_dp=dx,
        active=held_g & ~eq_g, weak=weak, step_up=np.array([c[0] for c in changes]),
        step_down=np.array([c[1] for c in changes]), change_up=[c[2] for c in changes],
        change_down=[c[3] for c in changes], residual=residual, regularisation=regularisation)



@dataclass
class TrackedOptimum:
    """An NLP re-solved at other parameter values from a solution's primal-dual point (`resolve_tracking`).

    f : float
        Its optimal objective (the NLP's own, scaled, units).
    x : ndarray
    success : bool
    status : str
    iterations : int
    wall_time : float
        s, including building the solver.
    """

    f: float
    x: np.ndarray
    success: bool
    status: str
    iterations: int
    wall_time: float


def resolve_tracking(point: ParametricPoint, p: np.ndarray, options: dict | None = None) -> TrackedOptimum:
    """The NLP of `point` at parameters `p`, started at point's solution and multipliers (`IPOPT_TRACKING`):
    the local optimum that `kkt_sensitivity` differentiates, followed to `p`, so that differences of
    tracked optima check its derivative. `options` are added to `IPOPT_TRACKING` (e.g. the NLP's own
    Hessian choice)."""
    t0 = time.perf_counter()
    solver = ca.nlpsol("tracking", "ipopt", point.solver.oracle(), {**IPOPT_TRACKING, **(options or {})})
    sol = solver(x0=point.x, p=np.asarray(p, float), lam_x0=point.lam_x, lam_g0=point.lam_g, lbx=point.lbx,
                 ubx=point.ubx, lbg=point.lbg, ubg=point.ubg)
    st = solver.stats()
    return TrackedOptimum(f=float(sol["f"]), x=np.asarray(sol["x"]).ravel(), success=bool(st["success"]),
                          status=str(st["return_status"]), iterations=int(st.get("iter_count", -1)),
                          wall_time=time.perf_counter() - t0)


__all__ = ["KktSensitivity", "TrackedOptimum", "WEAK_TOL", "kkt_sensitivity", "resolve_tracking"]
