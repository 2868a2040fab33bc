"""`Collocation`: direct collocation (Radau IIA) of the speed problem on a model with states, the
transcription that converges on the clearance model (with the journals kept on their walls).

The period is cut into K equal elements. In each, the scaled state is a polynomial of degree d
through its start value and d Radau points; the explicit ODE holds at the Radau points
(collocation equations), the loads and the ram motion are sampled there, and the end value of one
element is the start of the next (the last one wraps to the first for a periodic response). The
NLP variables are the Fourier coefficients, the epigraph variable, every state value and the crank
motion (theta, omega, alpha) at every Radau point, tied linearly to the coefficients, so the model
terms couple only the variables of one point and the exact Hessian is block-diagonal by point.
With ``min_eccentricity`` every clearance joint keeps contact, so no iterate has a free flight
the grid cannot resolve.

No integrator runs inside the NLP, so an iteration is cheap, but the elements must resolve the
contact dynamics (kHz modes of the rod on the bearing films): a too coarse grid is not a
simulation of the model, and its optimum means nothing. `collocation_defect` tells.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import ClassVar

import casadi as ca
import numpy as np

from .. import checks as chk
from ..compile_cache import NLP_FLAGS, check_jit, compile_seconds, function_options, oracle_options, use_jit
from ..interrupt import compiling
from ..ipopt_options import IPOPT_COLLOCATION, IPOPT_RESCALED
from ..model import OUTPUT_NAMES, PressModel
from ..problem import SpeedProblem
from ..simulate import for_repeated_use
from ..speed import FourierSpeed
from .nlp import Constraints, UniformPartition, crank_motion, crank_scale, scaled_crank_start, tie
from .prolong import Samples, carried_multipliers
from .stage import NlpPoint, Resimulated, StageResult, WarmStart
from .states import (StageRun, StateNlp, StateSettings, check_states, keep_contact, sample_outputs, solve_states,
                     states_at, warm_states)

#: Elements per second of period of the first grid, by rod (at least `MIN_ELEMENTS`). Rigid rod: 2 ms
#: elements; on the 75 spm case (400 elements) the optimum re-simulates within 0.7 % of the NLP's peak,
#: at 0.27 x the cost per iteration of 1600 elements. Flexible rod: 0.5 ms, as fine as a refinement
#: goes; on the slender-rod scene the 0.63 ms grid (100 elements) re-simulated within 0.4 % of its NLP,
#: yet its optimum was 10 % higher (79.0 against 71.7 N m).
ELEMENTS_PER_SECOND = {"rigid": 500, "flexible": 2000}
#: Fewest elements of a default grid.
MIN_ELEMENTS = 100
#: Elements per second of period of the finest grid a refinement reaches (0.5 ms elements: on the
#: 75 spm case the optimum re-simulates within 0.02 % at 1600 elements).
MAX_ELEMENTS_PER_SECOND = 2000


def nlp_options(jit: bool) -> dict:
    """nlpsol options of the collocation NLP: `IPOPT_COLLOCATION`, and with `jit` few directions per
    derivative sweep (`pressocp.compile_cache.oracle_options`)."""
    return {**IPOPT_COLLOCATION, **oracle_options(jit)}


def radau_matrices(degree: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Collocation points, matrices and weights of the Radau IIA scheme of `degree` d
    (`casadi.collocation_coeff`).

    Returns
    -------
    tau : ndarray, (d + 1,)
        0 and the d Radau points in (0, 1] (the last is 1).
    C : ndarray, (d + 1, d)
        ``C[j, r]``: derivative of the j-th Lagrange basis polynomial at the r-th Radau point, so that
        ``sum_j C[j, r] x_j = h dx/dt(tau[r + 1])`` on an element of length h.
    D : ndarray, (d + 1,)
        Basis polynomials at 1: the element's end value is ``sum_j D[j] x_j``.
    B : ndarray, (d,)
        Quadrature weights b_r of the Radau points on [0, 1] (the last row of the Butcher matrix A).
    """
    d = chk.integer("degree", degree, 1, 9)
    points = ca.collocation_points(d, "radau")
    C, D, B = ca.collocation_coeff(points)
    return np.append(0.0, points), np.array(C), np.array(D).ravel(), np.array(B).ravel()


@dataclass(frozen=True)
class CollocationGrid(UniformPartition):
    """K elements of Radau degree d over one period: equal ones, or those starting at `edges`.

    Attributes
    ----------
    period : float
        s.
    elements : int
        K.
    degree : int
        d (3: order 5).
    edges : tuple of float or None
        Start of each element as a fraction of the period (K values, the first 0, increasing, all
        below 1); None: K equal elements. A local refinement (`Collocation.refined`) makes them.
    """

    period: float
    elements: int
    degree: int = 3
    edges: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        chk.positive("period", self.period, "s")
        chk.integer("elements", self.elements, 1, 100_000)
        chk.integer("degree", self.degree, 1, 9)
        if self.edges is not None:
            object.__setattr__(self, "edges", check_edges(self.edges, self.elements))

    @property
    def pieces(self) -> int:
        return self.elements

    @property
    def starts(self) -> np.ndarray:
        """Start times of the elements, s."""
        return super().starts if self.edges is None else self.period * np.asarray(self.edges)

    @property
    def lengths(self) -> np.ndarray:
        """Length of each element, s."""
        if self.edges is None:
            return np.full(self.elements, self.h)
        return self.period * np.diff(np.append(np.asarray(self.edges), 1.0))

    @property
    def points(self) -> np.ndarray:
        """Times of every state value, element by element (start, then the d Radau points), s."""
        tau = radau_matrices(self.degree)[0]
        return (self.starts[:, None] + self.lengths[:, None] * tau[None, :]).ravel()

    @property
    def radau(self) -> list[int]:
        """Indices of the Radau points in `points` (every point but the element starts)."""
        d = self.degree
        return [k * (d + 1) + j for k in range(self.elements) for j in range(1, d + 1)]

    @property
    def times(self) -> np.ndarray:
        """Times of the Radau points (where the loads are sampled), element by element, s."""
        return self.points[self.radau]

    @property
    def weights(self) -> np.ndarray:
        """Quadrature weights h b_r of the Radau points (`times`), s (`radau_matrices`)."""
        return np.repeat(self.lengths, self.degree) * np.tile(radau_matrices(self.degree)[3], self.elements)

    @property
    def key(self) -> tuple:
        """The grid as plain data (`NlpPoint.grid`): (K, d), and the edges when they are not equal."""
        return (self.elements, self.degree) if self.edges is None else (self.elements, self.degree, self.edges)

    def splits(self, finer: "CollocationGrid") -> bool:
        """Whether `finer` is this grid with elements cut (same period and degree, more elements, and
        every element start of this grid one of `finer`'s)."""
        if finer.degree != self.degree or finer.period != self.period or finer.elements <= self.elements:
            return False
        mine, theirs = self.starts / self.period, finer.starts / finer.period
        at = np.clip(np.searchsorted(theirs, mine - 1e-12), 0, theirs.size - 1)
        return bool(np.all(np.abs(theirs[at] - mine) <= 1e-9))

    def interpolate(self, states: np.ndarray, finer: "CollocationGrid") -> np.ndarray:
        """`states` (rows x `points`) carried to the points of `finer`, this grid with elements cut
        (`splits`), by this grid's collocation polynomials (each element's degree-d polynomial through
        its start and Radau values). Exact for states polynomial of degree d in each element."""
        if not self.splits(finer):
            raise ValueError(f"a grid of {finer.elements} elements of degree {finer.degree} does not cut the "
                             f"{self.elements} elements of degree {self.degree} of this one")
        tau = radau_matrices(self.degree)[0]
        mine, starts = self.starts, finer.starts
        # each fine element's coarse element (the last coarse start at or before its own start)
        owner = np.clip(np.searchsorted(mine, starts + 1e-12 * self.period, side="right") - 1, 0, self.elements - 1)
        k = np.repeat(owner, tau.size)  # each fine point's coarse element, and in it its local time s
        s = (finer.points - mine[k]) / self.lengths[k]
        basis = np.ones((tau.size, s.size))
        for j in range(tau.size):
            for i in range(tau.size):
                if i != j:
                    basis[j] *= (s - tau[i]) / (tau[j] - tau[i])
        values = np.asarray(states, float).reshape(-1, self.points.size)
        nodes = k[:, None] * (self.degree + 1) + np.arange(tau.size)[None, :]  # each fine point's element nodes
        return np.einsum("rpj,jp->rp", values[:, nodes], basis)

    def cut(self, which: np.ndarray) -> "CollocationGrid":
        """This grid with each element where `which` (bool per element) is True cut in two equal halves."""
        which = np.asarray(which, bool)
        starts = self.starts / self.period
        halves = starts[which] + 0.5 * self.lengths[which] / self.period
        edges = np.sort(np.concatenate([starts, halves]))
        return CollocationGrid(self.period, edges.size, self.degree, tuple(float(e) for e in edges))

    def samples(self, band: np.ndarray) -> Samples:
        """Where this grid's constraint rows lie (`pressocp.ocp.prolong`), the ram speed held at `band`."""
        return Samples(self.period, self.times, self.weights, np.repeat(self.lengths, self.degree),
                       self.starts + self.lengths, np.asarray(band, int))

    def layout(self, nx: int, nw: int) -> tuple[np.ndarray, np.ndarray]:
        """Positions in one variable vector of a state (nx rows) at every point and of nw more
        variables at every Radau point, stored point by point: (nx x K(d+1), nw x Kd) indices.
        (Stored point by point, MUMPS factorises the KKT matrix faster than stored blockwise.)"""
        d, per = self.degree, nx + self.degree * (nx + nw)
        k, j = np.meshgrid(np.arange(self.elements), np.arange(d + 1), indexing="ij")
        first = k * per + np.where(j == 0, 0, nx + (j - 1) * (nx + nw))  # first state entry of each point
        zi = first.ravel()[None, :] + np.arange(nx)[:, None]
        wi = first[:, 1:].ravel()[None, :] + nx + np.arange(nw)[:, None]
        return zi, wi


def coarser(point: NlpPoint | None, grid: CollocationGrid) -> CollocationGrid | None:
    """The grid of a collocation solution `point` (its `CollocationGrid.key`) when `grid` cuts its
    elements (`CollocationGrid.splits`), else None."""
    g = None if point is None else point.grid
    if not (isinstance(g, tuple) and len(g) in (2, 3) and all(isinstance(v, (int, np.integer)) for v in g[:2])):
        return None
    coarse = CollocationGrid(grid.period, int(g[0]), int(g[1]), g[2] if len(g) == 3 else None)
    return coarse if coarse.splits(grid) else None


def check_edges(edges, elements: int) -> tuple[float, ...]:
    """`edges` as a tuple of floats, checked: `elements` element starts as fractions of the period, the
    first 0, increasing, all below 1 (raises ValueError naming what is wrong)."""
    e = np.asarray(edges, float).ravel()
    if e.size != elements:
        raise ValueError(f"edges: {e.size} element starts given for {elements} elements")
    if e[0] != 0.0 or np.any(np.diff(e) <= 0.0) or e[-1] >= 1.0 or not np.all(np.isfinite(e)):
        raise ValueError("edges: element starts as fractions of the period must begin at 0, increase and stay "
                         f"below 1; got {e[:3].tolist()}...{e[-2:].tolist()}")
    return tuple(float(v) for v in e)


def point_function(model: PressModel, names: tuple[str, ...], jit: bool = False) -> ca.Function:
    """The model at one collocation point: ``(x [nx], crank [3], q) -> (dx/dt [nx], y [len(names)])``,
    the outputs `names` and ``q`` the carried press parameters (`PressModel.at_crank`). With `jit`, it
    and its derivatives are compiled by the system C compiler (`pressocp.compile_cache.jit_options`, whose
    on-disk cache serves any process that compiled the same code before). Kept in
    ``model.functions``, with the last compiled solve's solver (which holds the compiled derivatives
    alive): the next solve on the same model (a polish round) compiles nothing again."""
    key = ("collocation_point", tuple(names), bool(jit))
    if key not in model.functions:
        x, crank, q = ca.SX.sym("x", model.nx), ca.SX.sym("crank", 3), ca.SX.sym("q", len(model.symbols))
        out = model.at_crank(x, crank, q)
        y = ca.vertcat(*[out[1 + OUTPUT_NAMES.index(n)] for n in names])
        with compiling():
            model.functions[key] = ca.Function("point", [x, crank, q], [out[0], y], ["x", "crank", "q"],
                                               ["ode", "y"], function_options(jit, flags=NLP_FLAGS))
    return model.functions[key]


def collocation_residuals(model: PressModel, grid: CollocationGrid, names: tuple[str, ...], X, crank,
                          jit: bool = False, q=None) -> tuple:
    """Collocation defects, element end values and outputs of the whole grid.

    The model is evaluated point by point (one mapped `point_function`) and the Radau matrices act
    as sparse linear maps across the grid, so each nonlinear term depends on the variables of one
    point only (its nx states and 3 crank values).

    Parameters
    ----------
    X : ca.MX or array, nx x K(d+1)
        Scaled states at `CollocationGrid.points`.
    crank : ca.MX or array, 3 x Kd
        theta (rad), omega (rad/s), alpha (rad/s^2) at `CollocationGrid.times`.
    jit : bool
        Compile the point function (`point_function`).
    q : ca.MX or array, optional
        Values of the model's carried parameters (default `PressModel.nominal`).

    Returns
    -------
    defect (nx x Kd), xf (nx x K), y (len(names) x Kd)
        ``sum_j C[j, r] x_j - h f(x_r, crank_r)`` per Radau point, the end value of each element and
        the outputs at the Radau points.
    """
    _, C, D, _ = radau_matrices(grid.degree)
    K, d = grid.elements, grid.degree
    X = X if isinstance(X, ca.MX) else ca.DM(np.asarray(X, float))
    crank = crank if isinstance(crank, ca.MX) else ca.DM(np.asarray(crank, float))
    q = ca.DM(model.nominal) if q is None else q
    F, Y = point_function(model, names, jit).map(K * d)(X[:, grid.radau], crank, q)
    # block-diagonal C (K(d+1) x Kd) and D (K(d+1) x K) as sparse matrices
    k, j, m = (a.ravel() for a in np.meshgrid(np.arange(K), np.arange(d + 1), np.arange(d), indexing="ij"))
    Cb = ca.DM.triplet((k * (d + 1) + j).tolist(), (k * d + m).tolist(), C[j, m].tolist(), K * (d + 1), K * d)
    k, j = (a.ravel() for a in np.meshgrid(np.arange(K), np.arange(d + 1), indexing="ij"))
    Db = ca.DM.triplet((k * (d + 1) + j).tolist(), k.tolist(), D[j].tolist(), K * (d + 1), K)
    if grid.edges is None:
        hF = grid.h * F
    else:  # each Radau point's own element length
        hF = F * ca.repmat(ca.DM(np.repeat(grid.lengths, d)).T, F.size1(), 1)
    return ca.mtimes(X, Cb) - hF, ca.mtimes(X, Db), Y


def defects_by_element(model: PressModel, speed: FourierSpeed, states: np.ndarray,
                       grid: CollocationGrid) -> np.ndarray:
    """Largest collocation defect of ``states`` (scaled, nx x K(d+1)) in each element of the grid."""
    defect = np.abs(np.asarray(collocation_residuals(model, grid, ("torque",), states,
                                                     crank_motion(speed, grid.times))[0]))
    return defect.reshape(defect.shape[0], grid.elements, grid.degree).max(axis=(0, 2))


def collocation_defect(model: PressModel, speed: FourierSpeed, states: np.ndarray, grid: CollocationGrid) -> float:
    """Largest collocation defect of ``states`` (scaled, nx x K(d+1)) over the grid: near 0 when the
    polynomials reproduce the model's solution, i.e. when the elements resolve its dynamics."""
    return float(defects_by_element(model, speed, states, grid).max())


def element_defects(where: Resimulated, grid: CollocationGrid) -> np.ndarray:
    """Largest collocation defect of each element (scaled states) of the model's own response: the
    states `where` re-simulated (CVODES, rtol 1e-9) from its state at t = 0 over one period at the
    grid's points, put into the collocation equations. It is the local error of the element, large
    where the response changes faster than degree-d polynomials over the element follow."""
    model = for_repeated_use(where.model)
    return defects_by_element(model, where.speed, states_at(model, where.speed, where.x0, grid.points, 1e-9), grid)


#: How `Collocation.refined` cuts a grid.
REFINEMENTS = ("uniform", "local")
#: A local refinement cuts the elements whose defect is at least LOCAL_CUT^(d+1) of the largest. Cut
#: in two, an element's defect shrinks by up to 2^(d+1) (on the smooth case at 100-800 elements the
#: grid's largest fell by 1.2-11 x per uniform cut). At 2^-(d+1) the grid's largest defect fell as far
#: as a uniform cut's with a third of the elements cut, but each answer moved its impacts to the coarse
#: elements: the pin caps needed 4-6 rounds and ended 1.1 % and 0.14 % higher. At 2^-2(d+1) they
#: needed 2, as the uniform cut (docs/decisions/2026-11-29-local-refinement.md).
LOCAL_CUT = 0.25

#: Most IPOPT iterations of the `Collocation.relaxed` re-solve.
RELAX_ITERATIONS = 8


@dataclass(frozen=True, repr=False)
class Collocation(StateSettings):
    """Radau IIA direct collocation, exact Hessian, journals kept on their walls by default.

    Attributes
    ----------
    elements : int or None
        Elements per period, 10..100 000; None: `ELEMENTS_PER_SECOND` x T (2 ms elements on a rigid
        rod, 0.5 ms on a flexible one), at least `MIN_ELEMENTS`. Fewer are faster and less accurate;
        `refined` cuts them.
    degree : int
        Radau degree d, 1..9 (3: order 5).
    jit : bool or "auto"
        Compile the model's point function and its derivatives with the system C compiler (about 8 s
        at 1600 elements, then iterations about 3x faster). "auto": when a C compiler is found (a
        warning says so when it is not, and CasADi's virtual machine is used).
    min_eccentricity : float or None
        Keyword-only (`StateSettings`), default 1: contact kept at every Radau point. With free flight
        allowed the elements must resolve the impacts, and 1 ms elements do not.
    backoff : float
        Keyword-only (`StateSettings`), default 0.95: the share of the ram-speed tolerance held at the
        Radau points (on 2 ms elements the re-simulated ram strayed up to 4.5 % of the tolerance past
        the held value).
    edges : tuple of float or None
        Keyword-only: the start of each element as a fraction of the period (`CollocationGrid`);
        None: equal elements. `refined` sets them.
    refinement : {"uniform", "local"}
        Keyword-only: how `refined` cuts the grid. "uniform" (default): every element. "local": the
        elements whose collocation defect on the re-simulated response is within 2^-2(d+1) of the
        largest, where the response changes faster than the polynomials follow (the journals' gap
        crossings, contact transients), and those where the re-simulated objective is near its
        peak. On press75's hard scenes (pin caps, drive, counterbalances) it took 18-67 % less time,
        but its answers were 0.15-1.2 % higher on three, 0.19 % lower on one, and the gas-spring
        counterbalance's answer did not verify: the window, where the ram speed is held, stays
        coarse, and its ram strayed (docs/decisions/2026-11-29-local-refinement.md).
    periodic, omega_samples, ipopt
        Keyword-only, as in `StateSettings` (``ipopt`` on top of `IPOPT_COLLOCATION` too).
    """

    elements: int | None = None
    degree: int = 3
    jit: bool | str = "auto"
    min_eccentricity: float | None = field(default=1.0, kw_only=True)
    backoff: float = field(default=0.95, kw_only=True)
    edges: tuple[float, ...] | None = field(default=None, kw_only=True)
    refinement: str = field(default="uniform", kw_only=True)

    compiles_ahead: ClassVar[bool] = True
    gives_parametric_point: ClassVar[bool] = True

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.edges is not None:
            K = len(self.edges) if self.elements is None else self.elements
            object.__setattr__(self, "edges", check_edges(self.edges, K))
            object.__setattr__(self, "elements", K)
        if self.elements is not None:
            chk.integer("elements", self.elements, 10, 100_000)
        chk.integer("degree", self.degree, 1, 9)
        check_jit(self.jit)
        chk.choice("refinement", self.refinement, REFINEMENTS)

    def grid(self, period: float, rod: str = "rigid") -> CollocationGrid:
        """The element grid for a period and a model's rod ("rigid" or "flexible")."""
        if self.edges is not None:
            return CollocationGrid(period, len(self.edges), self.degree, self.edges)
        per_second = ELEMENTS_PER_SECOND.get(rod, MAX_ELEMENTS_PER_SECOND)
        K = max(round(per_second * period), MIN_ELEMENTS) if self.elements is None else self.elements
        return CollocationGrid(period, chk.integer("elements", max(K, 10), 10, 100_000), self.degree)

    def refined(self, period: float, rod: str = "rigid", where: Resimulated | None = None) -> "Collocation | None":
        """This transcription on a finer grid, or None when it has none. Elements are cut in two while
        they stay at least ``1 / MAX_ELEMENTS_PER_SECOND`` long (0.5 ms; an equal grid at most
        ``MAX_ELEMENTS_PER_SECOND`` x period elements, and `MIN_ELEMENTS`). Without `where`, or with
        ``refinement="uniform"``, every element that can be is cut (equal elements: twice as many).
        With `where` (a stage's answer re-simulated) and ``refinement="local"``, only the elements
        whose collocation defect on that response (`element_defects`) is at least `LOCAL_CUT`^(d+1)
        of the largest, and those that hold the times where the objective is near its peak
        (``where.near_peak``), which decide the NLP's objective."""
        grid = self.grid(period, rod)
        finest = max(round(MAX_ELEMENTS_PER_SECOND * period), MIN_ELEMENTS)
        if grid.edges is None and (where is None or self.refinement == "uniform"):
            K = grid.elements
            return None if K >= finest else replace(self, elements=min(2 * K, finest))
        cuttable = grid.lengths >= 2.0 * period / finest * (1.0 - 1e-9)
        if where is not None and self.refinement == "local":
            defects = element_defects(where, grid)
            wanted = defects >= defects.max() * LOCAL_CUT ** (self.degree + 1)
            holds = np.searchsorted(grid.starts, np.asarray(where.near_peak, float) % period, side="right") - 1
            wanted[np.clip(holds, 0, grid.elements - 1)] = True
            cuttable &= wanted
        if not cuttable.any():
            return None
        finer = grid.cut(cuttable)
        if np.allclose(finer.lengths, finer.lengths[0]):  # a uniform cut of equal ones
            return replace(self, elements=finer.elements, edges=None)
        return replace(self, elements=finer.elements, edges=finer.edges)

    def tightened(self, share: float) -> "Collocation":
        """The same transcription holding `share` less of the ram-speed tolerance (``backoff``), down
        to a tenth of it at least; started from a stage's `NlpPoint` on the same grid it is the same
        NLP with moved bounds."""
        return replace(self, backoff=max(self.backoff - share, 0.1))

    def relaxed(self, stage: StageResult) -> "Collocation | None":
        """`stage`'s NLP (its grid, from its details) holding the whole ram-speed tolerance; None when it
        held all of it already or has no `NlpPoint` to start from. Started from that point it is the
        same NLP with its ram-speed bounds moved out; IPOPT stops after `RELAX_ITERATIONS` (on
        large_press it needed 4 and 6, where a run that needs more has left the answer: 52 on the 75 spm
        seed, for nothing)."""
        d = stage.details
        if stage.nlp is None or d.get("backoff", 1.0) >= 1.0 or "elements" not in d:
            return None
        edges = tuple(d["edges"]) if d.get("edges") is not None else None
        return replace(self, elements=int(d["elements"]), degree=int(d.get("degree", self.degree)), edges=edges,
                       backoff=1.0, ipopt={**self.ipopt, "ipopt.max_iter": RELAX_ITERATIONS})

    def rescaled(self) -> "Collocation | None":
        """This transcription with MUMPS scaling the KKT matrix and IPOPT's acceptable level at 1e-3
        (`IPOPT_RESCALED`); None when its options set a MUMPS scaling already. Off by default (the
        scaling doubles the back-solves' cost on the 75 spm seed for the same optimum), it is what a
        stage that did not converge is solved with again."""
        if "ipopt.mumps_scaling" in self.ipopt:
            return None
        return replace(self, ipopt={**self.ipopt, **IPOPT_RESCALED})

    def use_jit(self) -> bool:
        """Whether this solve compiles (``jit``, or "auto" and a C compiler is present)."""
        return use_jit(self.jit, "collocation")

    def prepare(self, problem: SpeedProblem, model: PressModel, speed: FourierSpeed) -> float:
        """Compile what a solve of `problem` on `model` compiles (the point function and the
        derivatives the NLP builds of it) into the compile cache, without solving: a solve in any
        process afterwards compiles nothing. It builds the NLP of `solve` from `speed` with the
        model at rest at every point (no simulation: the states change no compiled code) and stops
        IPOPT before its first iteration. Returns the compile seconds (0 without `jit`)."""
        if not self.use_jit():
            return 0.0
        c0 = compile_seconds()
        rest = np.tile(np.asarray(model.x0, float)[:, None], (1, self.grid(problem.period, model.rod).points.size))
        replace(self, ipopt={**self.ipopt, "ipopt.max_iter": 0}).solve(problem, model, WarmStart(speed), "prepare",
                                                                       states=rest)
        return compile_seconds() - c0

    def solve(self, problem: SpeedProblem, model: PressModel, start: WarmStart, name: str = "target",
              progress: bool = False, *, states: np.ndarray | None = None) -> StageResult:
        """One collocation stage on `model`, warm-started at the start speed's periodic response, or at
        `states` (scaled, nx x the grid's points) when given, or at ``start.point``, a solution of
        this NLP on this grid or on a grid this one splits evenly: there its states are carried by
        their collocation polynomials (`CollocationGrid.interpolate`) and its multipliers group by
        group (`pressocp.ocp.prolong`), a primal-dual warm start either way, with no simulation. A
        model that carries press parameters (``build_model(..., parameters=...)``) puts them into the
        NLP's p, and the stage holds the NLP at its solution (``StageResult.point``)."""
        check_states(problem, model)
        grid = self.grid(problem.period, model.rod)
        K, d, n, T = grid.elements, grid.degree, problem.n_harmonics, problem.period
        jit = self.use_jit()
        t0 = time.perf_counter()
        names = sample_outputs(problem, model, self.min_eccentricity)
        c = ca.MX.sym("c", 2 * n)
        zi, wi = grid.layout(model.nx, 3)
        point = start.point if start.point is not None and start.point.grid == grid.key else None
        coarse = None if point is not None or states is not None else coarser(start.point, grid)
        carry = None
        if states is not None:
            warm = {"periodic_warm_start": False, "reason": "states given"}
        elif coarse is not None:  # a coarser grid's solution: its polynomials and multipliers, no simulation
            point = start.point
            states = coarse.interpolate(point.w[2 * n + 1 :][coarse.layout(model.nx, 3)[0]], grid)
            warm = {"carried_from_elements": coarse.elements}

            def carry(groups: list, band: np.ndarray) -> tuple[np.ndarray | None, str]:
                return carried_multipliers(point.groups, point.lam_g, coarse.samples(point.band), groups,
                                           grid.samples(band))
        elif point is None:
            states, warm = warm_states(model, start, grid.points, 1e-9)
        else:  # the same NLP's solution: its states, and no simulation
            states, warm = point.w[2 * n + 1 :][zi], {"primal_dual_warm_start": True}
        X = ca.MX.sym("X", zi.size + wi.size)
        Z, Wv = X[zi.ravel(order="F").tolist()].reshape(zi.shape), X[wi.ravel(order="F").tolist()].reshape(wi.shape)
        W = Wv * ca.DM(crank_scale(T))
        q = ca.MX.sym("q", len(model.symbols)) if model.symbols else None
        t1, c1 = time.perf_counter(), compile_seconds()  # the point function is built, and compiled, here
        defect, Xf, Y = collocation_residuals(model, grid, names, Z, W, jit, q)
        t_build, compiled = time.perf_counter() - t1, compile_seconds() - c1
        W0 = crank_motion(start.speed.padded(n), grid.times)
        y0 = np.asarray(collocation_residuals(model, grid, names, states, W0)[2])
        X0 = np.zeros(X.numel())
        X0[zi] = states
        X0[wi] = scaled_crank_start(start.speed.padded(n), grid.times)
        cons = Constraints()
        cons.add(defect, 0.0, 0.0, "collocation")
        y = {k: Y[i, :] for i, k in enumerate(names)}
        keep_contact(cons, y, model, self.min_eccentricity)
        tie(cons, W, c, T, grid.times)
        starts = Z[:, :: d + 1]
        nxt = ca.horzcat(starts[:, 1:], starts[:, :1]) if self.periodic else starts[:, 1:]
        cons.add((Xf if self.periodic else Xf[:, :-1]) - nxt, 0.0, 0.0, "continuity")
        details = {"elements": K, "degree": d, "min_eccentricity": self.min_eccentricity, "jit": jit,
                   "periodic": self.periodic, "backoff": self.backoff, "omega_samples": self.omega_samples,
                   "defect_start": collocation_defect(model, start.speed, states, grid), **warm}
        if grid.edges is not None:
            details.update(edges=list(grid.edges), shortest_element_s=float(grid.lengths.min()))
        t_start = time.perf_counter() - t0 - t_build
        nlp = StateNlp(c, X, X0, y, {k: y0[i : i + 1, :] for i, k in enumerate(names)}, grid.times, cons,
                       fixed=None if self.periodic else zi[:, 0],
                       parameters=None if q is None else (q, model.nominal), motion=W)
        run = StageRun(name, f"{name} ({K}x{d} radau{', jit' if jit else ''})", {**nlp_options(jit), **self.ipopt},
                       progress, details, grid=grid.key, keep=model.functions if jit else None, warm=point,
                       carry=carry)
        r = solve_states(problem, model, start.speed, nlp, run, self)
        r.states = r.states[zi]
        r.settings = replace(self, elements=K, edges=grid.edges).settings()  # the grid this stage solved on
        r.timing.update(start=t_start, build=r.timing.get("build", 0.0) + t_build - compiled,
                        compile=r.timing.get("compile", 0.0) + compiled,
                        total=r.timing.get("total", 0.0) + t_start + t_build)
        r.wall_time = r.timing["total"]
        return r
