"""Direct-collocation transcription (Radau IIA) of the speed problem on a model with states: the
transcription that converges on the clearance model (with the journals kept on their walls).

The period is cut into K equal elements. In each, the scaled state is a polynomial of degree d
through its start value and d Radau points; the explicit ODE holds at the Radau points
(collocation equations), the loads and the ram velocity are sampled there, and the end value of
one element is the start of the next (the last one wraps to the first for a periodic response).
The NLP variables are the Fourier coefficients, the epigraph variable, every state value and the
crank motion (theta, omega, alpha) at every point, tied linearly to the coefficients, so the model
terms couple only the variables of one point. IPOPT solves it with the same constraints, barrier
and options as the shooting stages (`solve_nlp`), plus optionally ``min_eccentricity``: contact
kept in every clearance joint, so no iterate has a free flight the grid cannot resolve.

No integrator runs inside the NLP, so an iteration is cheap, but the elements must resolve the
contact dynamics (kHz modes of the rod on the bearing films): a too coarse grid is not a
simulation of the model, and its optimum means nothing. Check it with `collocation_defect`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

from .. import _checks as chk
from ..model import OUTPUT_NAMES, PressModel
from ..speed import FourierSpeed
from .constraints import Constraints, add_crank_motion, crank_motion, crank_scale
from .problem import SpeedProblem
from .shooting import (LOADS, ShootingSolution, check_start, contact_outputs, keep_contact, solve_states_nlp,
                       states_at, to_solution)

#: Fraction of the ram speed tolerance held at the Radau points.
RAM_SPEED_BACKOFF = 0.98
#: IPOPT options of the collocation NLP on top of the shooting stages' (`solve_nlp`), measured on the
#: seed case (1600 elements, exact Hessian, jit):
#: - zero initial constraint multipliers instead of IPOPT's least-squares estimate, whose extra linear
#:   system took 7 s and changed nothing (66 -> 67 iterations, same optimum);
#: - no MUMPS scaling (its automatic choice, 77, is the default): IPOPT's own time (mostly MUMPS)
#:   0.54 s per iteration instead of 0.86 s (back-solves 0.13 instead of 0.35 s), 67 iterations against 75,
#:   the same optimum to 1e-10. (The rigid stages are left at 77: there it changed the default case's
#:   exit from Solve_Succeeded to Solved_To_Acceptable_Level.)
IPOPT_OPTIONS = {"ipopt.constr_mult_init_max": 0.0, "ipopt.mumps_scaling": 0}
#: CasADi JIT of the point function and its derivatives (``jit=True``). Measured on the seed case,
#: 1600 elements: ≈ 8 s of compilation (with `JIT_DIRECTIONS`; 45 s without), then the Hessian takes
#: 0.2 s instead of 2.0 s and the Jacobian 0.10 s instead of 0.93 s per iteration.
JIT_OPTIONS = {"jit": True, "compiler": "shell", "jit_options": {"flags": ["-O1"], "verbose": False}}
#: Directions per derivative sweep of the NLP functions when the point function is compiled (the
#: oracle's ``max_num_dir``; CasADi's default 64 let the exact Hessian take all 9 colours in one
#: ``fwd9_adj1_point``). Measured on the seed model, gcc -O1, 4800 points: 9 directions compile in
#: 31 s and evaluate the Hessian in 46 us per point; 3 directions in 5 s and 43-48 us per point
#: (three calls); 1 direction in 1.6 s and 59 us. Without ``jit`` the virtual machine is 23 % slower
#: with 3 directions (2.4 against 2.0 s per Hessian), so the default stays there.
JIT_DIRECTIONS = 3


def nlp_options(jit: bool) -> dict:
    """nlpsol options of the collocation NLP: `IPOPT_OPTIONS`, and with `jit` at most `JIT_DIRECTIONS`
    directions per derivative sweep (the oracle's ``max_num_dir``)."""
    return {**IPOPT_OPTIONS, **({"oracle_options": {"max_num_dir": JIT_DIRECTIONS}} if jit else {})}


def radau_matrices(degree: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Collocation points and matrices of the Radau IIA scheme of `degree` d.

    Returns
    -------
    tau : ndarray, (d + 1,)
        0 and the d Radau points in (0, 1] (the last is 1).
    C : ndarray, (d + 1, d + 1)
        ``C[j, r]``: derivative of the j-th Lagrange basis polynomial at ``tau[r]``, so that
        ``sum_j C[j, r] x_j = h dx/dt(tau[r])`` on an element of length h.
    D : ndarray, (d + 1,)
        Basis polynomials at 1: the element's end value is ``sum_j D[j] x_j``.
    """
    d = chk.integer("degree", degree, 1, 9)
    tau = np.append(0.0, ca.collocation_points(d, "radau"))
    C = np.zeros((d + 1, d + 1))
    D = np.zeros(d + 1)
    for j in range(d + 1):
        basis = np.poly1d([1.0])
        for r in range(d + 1):
            if r != j:
                basis *= np.poly1d([1.0, -tau[r]]) / (tau[j] - tau[r])
        D[j] = basis(1.0)
        C[j] = np.polyder(basis)(tau)
    return tau, C, D


@dataclass(frozen=True)
class CollocationGrid:
    """K equal elements of Radau degree d over one period.

    Attributes
    ----------
    period : float
        s.
    elements : int
        K.
    degree : int
        d (3: order 5).
    """

    period: float
    elements: int
    degree: int = 3

    def __post_init__(self) -> None:
        chk.positive("period", self.period, "s")
        chk.integer("elements", self.elements, 1, 100_000)
        chk.integer("degree", self.degree, 1, 9)

    @property
    def h(self) -> float:
        """Element length, s."""
        return self.period / self.elements

    @property
    def starts(self) -> np.ndarray:
        """Start times of the elements, s."""
        return self.h * np.arange(self.elements)

    @property
    def points(self) -> np.ndarray:
        """Times of every state value, element by element (start, then the d Radau points), s."""
        tau = radau_matrices(self.degree)[0]
        return (self.starts[:, None] + self.h * tau[None, :]).ravel()

    @property
    def radau(self) -> list[int]:
        """Indices of the Radau points in `points` (every point but the element starts)."""
        d = self.degree
        return [k * (d + 1) + j for k in range(self.elements) for j in range(1, d + 1)]

    def layout(self, nx: int, nw: int) -> tuple[np.ndarray, np.ndarray]:
        """Positions in one variable vector of a state (nx rows) at every point and of nw more
        variables at every Radau point, stored point by point: (nx x K(d+1), nw x Kd) indices."""
        d, per = self.degree, nx + self.degree * (nx + nw)
        k, j = np.meshgrid(np.arange(self.elements), np.arange(d + 1), indexing="ij")
        first = k * per + np.where(j == 0, 0, nx + (j - 1) * (nx + nw))  # first state entry of each point
        zi = first.ravel()[None, :] + np.arange(nx)[:, None]
        wi = first[:, 1:].ravel()[None, :] + nx + np.arange(nw)[:, None]
        return zi, wi

    @property
    def times(self) -> np.ndarray:
        """Times of the Radau points (where the loads are sampled), element by element, s."""
        return self.points[self.radau]


def point_function(model: PressModel, names: tuple[str, ...], jit: bool = False) -> ca.Function:
    """The model at one collocation point: ``(x [nx], crank [3]) -> (dx/dt [nx], y [len(names)])``,
    the outputs `names` (`PressModel.at_crank`). With `jit`, it and its derivatives are compiled by
    the system C compiler (`JIT_OPTIONS`)."""
    x, crank = ca.SX.sym("x", model.nx), ca.SX.sym("crank", 3)
    out = model.at_crank(x, crank)
    y = ca.vertcat(*[out[1 + OUTPUT_NAMES.index(n)] for n in names])
    opts = {**JIT_OPTIONS, "der_options": JIT_OPTIONS} if jit else {}
    return ca.Function("point", [x, crank], [out[0], y], ["x", "crank"], ["ode", "y"], opts)


def collocation_residuals(model: PressModel, grid: CollocationGrid, names: tuple[str, ...], X, crank,
                          jit: bool = False) -> tuple:
    """Collocation defects, element end values and outputs of the whole grid.

    The model is evaluated point by point (one mapped `point_function`) and the Radau matrices act
    as sparse linear maps across the grid, so each nonlinear term depends on the variables of one
    point only (its nx states and 3 crank values): the exact Hessian is block-diagonal by point.

    Parameters
    ----------
    X : ca.MX or array, nx x K(d+1)
        Scaled states at `CollocationGrid.points`.
    crank : ca.MX or array, 3 x Kd
        theta (rad), omega (rad/s), alpha (rad/s^2) at `CollocationGrid.times`.
    jit : bool
        Compile the point function (`point_function`).

    Returns
    -------
    defect (nx x Kd), xf (nx x K), y (len(names) x Kd)
        ``sum_j C[j, r] x_j - h f(x_r, crank_r)`` per Radau point, the end value of each element and
        the outputs at the Radau points.
    """
    _, C, D = radau_matrices(grid.degree)
    K, d = grid.elements, grid.degree
    X = X if isinstance(X, ca.MX) else ca.DM(np.asarray(X, float))
    crank = crank if isinstance(crank, ca.MX) else ca.DM(np.asarray(crank, float))
    F, Y = point_function(model, names, jit).map(K * d)(X[:, grid.radau], crank)
    # block-diagonal C (K(d+1) x Kd) and D (K(d+1) x K) as sparse matrices
    k, j, m = (a.ravel() for a in np.meshgrid(np.arange(K), np.arange(d + 1), np.arange(d), indexing="ij"))
    Cb = ca.DM.triplet((k * (d + 1) + j).tolist(), (k * d + m).tolist(), C[j, 1 + m].tolist(), K * (d + 1), K * d)
    k, j = (a.ravel() for a in np.meshgrid(np.arange(K), np.arange(d + 1), indexing="ij"))
    Db = ca.DM.triplet((k * (d + 1) + j).tolist(), k.tolist(), D[j].tolist(), K * (d + 1), K)
    return ca.mtimes(X, Cb) - grid.h * F, ca.mtimes(X, Db), Y


def collocation_states(model: PressModel, speed: FourierSpeed, x_start: np.ndarray, grid: CollocationGrid,
                       rtol: float = 1e-8) -> np.ndarray:
    """Scaled states at every collocation time (`CollocationGrid.points`), integrated by CVODES from
    ``x_start`` at t = 0: the warm start (nx x K(d+1))."""
    return states_at(model, speed, x_start, grid.points, "cvodes", rtol)


def collocation_defect(model: PressModel, speed: FourierSpeed, states: np.ndarray, grid: CollocationGrid) -> float:
    """Largest collocation defect of ``states`` (scaled, nx x K(d+1)) over the grid: near 0 when the
    polynomials reproduce the model's solution, i.e. when the elements resolve its dynamics."""
    defect = collocation_residuals(model, grid, ("torque",), states, crank_motion(speed, grid.times))[0]
    return float(np.max(np.abs(np.asarray(defect))))


def solve_collocation(problem: SpeedProblem, model: PressModel, initial: FourierSpeed, states: np.ndarray,
                      t1: float, grid: CollocationGrid, stage: str = "collocation", periodic: bool = True,
                      window_samples: int = 200, omega_samples: int = 1000, ipopt_options: dict | None = None,
                      progress: bool = False, scale: float | None = None,
                      coefficient_step: float | None = None,
                      min_eccentricity: float | None = None, jit: bool = False) -> ShootingSolution:
    """One direct-collocation stage of the speed problem on `model`, warm-started at (initial, states).

    Parameters
    ----------
    problem : SpeedProblem
    model : PressModel
        A model with states; its ``n_harmonics`` must equal the problem's.
    initial : FourierSpeed
        Warm-start speed.
    states : ndarray
        Warm-start scaled states at `CollocationGrid.points`, nx x K(d+1) (`collocation_states`).
    t1 : float
        Window start, s, held fixed.
    grid : CollocationGrid
    stage : str
        Name used in reports.
    periodic : bool
        x(T) = x(0); otherwise the first state is held at ``states[:, 0]``.
    window_samples, omega_samples, ipopt_options, progress, scale, coefficient_step
        As in `solve_shooting` (``ipopt_options`` on top of `nlp_options`).
    min_eccentricity : float, optional
        Keep contact: the eccentricity ratio |e|/c of every clearance joint stays at or above this at
        every Radau point (in [0, 1]; 1 = the journal never leaves the bearing wall, so the joint
        force can only turn by sliding round the wall, never by a free flight and impact).
    jit : bool
        Compile the model's point function and its derivatives with the system C compiler
        (`JIT_OPTIONS`): worth it for long solves on fine grids, not for small ones.

    Returns
    -------
    ShootingSolution
        ``nodes`` are the element start states (nx x K).
    """
    P, T, n, K, d = problem, problem.period, problem.n_harmonics, grid.elements, grid.degree
    if not np.isclose(grid.period, T):
        raise ValueError(f"grid.period must equal the problem's period ({T:g} s), got {grid.period:g} s")
    states = check_start(P, model, states, K * (d + 1), "states", coefficient_step)
    t_start = time.perf_counter()
    names = LOADS[P.objective] + ("ram_velocity",)
    ecc = contact_outputs(model, min_eccentricity)
    # the crank motion at every Radau point is lifted into variables W (scaled rows) tied to the
    # coefficients by a linear constraint: each point then depends on its own variables only, and
    # the exact Hessian is block-diagonal instead of having 2n dense rows over all the states
    w_scale = crank_scale(T)
    c, s = ca.MX.sym("c", 2 * n), ca.MX.sym("s")
    zi, wi = grid.layout(model.nx, 3)
    X = ca.MX.sym("X", zi.size + wi.size)
    Z, W = X[zi.ravel(order="F").tolist()].reshape(zi.shape), X[wi.ravel(order="F").tolist()].reshape(wi.shape)
    W = W * ca.DM(w_scale)
    defect, Xf, Y = collocation_residuals(model, grid, names + ecc, Z, W, jit)
    W0 = crank_motion(initial.padded(n), grid.times)
    y0 = np.asarray(collocation_residuals(model, grid, names, states, W0)[2])
    X0 = np.zeros((X.numel(), 1))
    X0[zi, 0], X0[wi, 0] = states, W0 / w_scale[:, None]
    cons = Constraints()
    cons.add(defect, 0.0, 0.0, "collocation")
    Y = keep_contact(cons, Y, len(names), min_eccentricity)
    add_crank_motion(cons, W, c, T, grid.times)
    starts = Z[:, :: d + 1]
    nxt = ca.horzcat(starts[:, 1:], starts[:, :1]) if periodic else starts[:, 1:]
    cons.add((Xf if periodic else Xf[:, :-1]) - nxt, 0.0, 0.0, "continuity")
    # the model's ram speed is held at the Radau points only, and the first one lies after t1: 2 %
    # back-off (measured on a smooth case without it: 0.3 % of tol over at t1, where the kinematic
    # bound was active and the journals add their motion)
    r = solve_states_nlp(P, initial, c, s, X, X0, Y, y0, grid.times, t1, cons, scale, periodic,
                         f"collocation_{stage}", f"{stage} ({K}x{d} radau)", window_samples, omega_samples,
                         {**nlp_options(jit), **(ipopt_options or {})}, progress, coefficient_step,
                         RAM_SPEED_BACKOFF, model.nx)
    Zo = r["states"][zi, 0]
    return to_solution(r, nodes=Zo[:, :: d + 1], status=r["status"], wall_time=time.perf_counter() - t_start,
                       violations=r["violations"], failure=None)
