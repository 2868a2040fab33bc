"""The press as a CasADi DAE: rigid crank (prescribed speed), rigid or flexible rod, slider,
journal-bearing contact in the joints that have clearance.

Coordinates
-----------
The full coordinate set is ``Q = [theta, x_S, e_A (2), e_B (2), w (2N)]``: crank angle, slider
position across the slide, the eccentricities of the crank-pin and wrist-pin journals (bearing
centre in the rod minus journal centre) and the rod's elastic DOFs (`pressocp.beam`). The slider
position along the slide follows from the rod-length closure, so no index-3 constraint is left.

* *Free* coordinates: the eccentricities of the joints with clearance and the elastic DOFs.
  They are the DAE states (with their rates), scaled by the clearance and reference sizes.
* *Locked* coordinates: theta (prescribed by the Fourier speed), x_S = 0 (ideal guide) and the
  eccentricities of ideal joints (zero). The Lagrange equation rows of locked coordinates give
  their reactions: the motor torque, the guide's normal force and the ideal pin forces.

CasADi derives the mass matrix and the velocity and potential forces from the kinetic and
potential energies (`pressocp.mechanics.lagrangian`); contact forces enter as generalised forces
through the Jacobian of the eccentricities.

The DAE (semi-explicit, for IDAS) is ``x = [q/s_q, qd/s_v]``, ``z = qdd_free``,
``ode = [qd/s_q, z/s_v]``, ``alg = M_ff z - (F_f - M_fl qdd_locked)``; the explicit ODE used by
CVODES and the baselines eliminates z by a symbolic solve.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from . import checks as chk
from . import beam
from . import mechanics as mech
from .contact import contact_force
from .params import PressParams
from .speed import DEFAULT_HARMONICS, FourierSpeed, series

JOINTS = ("crank_pin", "wrist_pin")
RODS = ("rigid", "flexible")

#: Reference speed of the eccentricity rates for state scaling: s_v = s_q * VELOCITY_SCALE_RATE.
VELOCITY_SCALE_RATE = 1.0e3  # 1/s
#: Transverse acceleration (m/s^2) whose static deflection of the pinned-pinned rod sets the scale of
#: the elastic states: w_s = rho A a l^4 / (76.8 EI) (midspan deflection under a uniform load),
#: slopes w_s * 3.2 / l (end slope of the same load case).
ELASTIC_SCALE_ACCELERATION = 1.0e3

OUTPUT_NAMES = (
    "theta", "omega", "torque", "ram_height", "ram_velocity", "ram_acceleration", "slider_normal_force",
    "crank_pin_force", "wrist_pin_force", "crank_pin_eccentricity", "wrist_pin_eccentricity",
    "rod_midspan_deflection",
)
#: Power terms integrated as quadratures: motor power, power absorbed by the contacts (normal and
#: tangential), its elastic part K delta^n d|e|/dt, power of the process force on the ram, power
#: dissipated by the rod's material damping.
QUADRATURE_NAMES = ("motor_work", "contact_work", "contact_elastic_work", "process_work", "rod_damping_work")


@dataclass(frozen=True)
class ModelSpec:
    """Which model level: the arguments of `build_model` other than the press.

    Attributes
    ----------
    rod : {"rigid", "flexible"}
    clearance : tuple of str
        Joints with clearance (``()``: the rigid press).
    n_elements : int
        Elements of a flexible rod.
    n_modes : int or None
        A flexible rod reduced to the first `n_modes` bending modes of its `n_elements`-element
        model (Craig-Bampton with the pinned ends as the interface; `pressocp.beam.modes`), 1..2
        `n_elements`; None: every element DOF.
    """

    rod: str = "rigid"
    clearance: tuple[str, ...] = JOINTS
    n_elements: int = 4
    n_modes: int | None = None

    def __post_init__(self) -> None:
        chk.choice("rod", self.rod, RODS)
        clearance = (self.clearance,) if isinstance(self.clearance, str) else tuple(self.clearance)
        for j in clearance:
            chk.choice("clearance joint", j, JOINTS)
        if len(set(clearance)) != len(clearance):
            raise ValueError(f"clearance names a joint twice: {clearance!r}")
        object.__setattr__(self, "clearance", clearance)
        chk.integer("n_elements", self.n_elements, 1, 64)
        if self.n_modes is not None:
            if self.rod != "flexible":
                raise ValueError(f"n_modes reduces a flexible rod; rod is {self.rod!r}: leave n_modes unset")
            chk.integer("n_modes", self.n_modes, 1, 2 * self.n_elements)

    def build(self, params: PressParams, n_harmonics: int = DEFAULT_HARMONICS) -> "PressModel":
        """`build_model` of this level for a press."""
        return build_model(params, self.rod, self.clearance, self.n_elements, n_harmonics, n_modes=self.n_modes)

    def describe(self) -> str:
        """E.g. "rigid rod, clearance in crank_pin and wrist_pin" or "rigid press (ideal joints)"."""
        n, m = self.n_elements, self.n_modes
        modes = "" if m is None else f", {m} mode{'s' * (m != 1)}"
        rod = f"flexible rod ({n} element{'s' * (n != 1)}{modes})" if self.rod == "flexible" else "rigid rod"
        if not self.clearance:
            return "rigid press (ideal joints)" if self.rod == "rigid" else f"{rod}, ideal joints"
        return f"{rod}, clearance in {' and '.join(self.clearance)}"

    def to_dict(self) -> dict:
        """Plain data (``n_modes`` only when set)."""
        d = {"rod": self.rod, "clearance": list(self.clearance), "n_elements": self.n_elements}
        return d if self.n_modes is None else {**d, "n_modes": self.n_modes}

    @classmethod
    def from_dict(cls, data: dict) -> "ModelSpec":
        return cls(data.get("rod", "rigid"), tuple(data.get("clearance", JOINTS)), data.get("n_elements", 4),
                   data.get("n_modes"))


@dataclass
class PressModel:
    """A press model as a symbolic DAE plus its output and energy functions.

    Attributes
    ----------
    params : PressParams
        The press.
    rod : str
        ``"rigid"`` or ``"flexible"``.
    clearance : tuple of str
        Joints with clearance.
    n_elements : int
        Rod elements (flexible rod).
    n_harmonics : int
        Harmonics of the Fourier speed carried in p.
    t, x, z, p : ca.SX
        Time, scaled differential states, algebraic states (free accelerations) and parameters
        ``p = [a (n), b (n), period, theta0]``.
    ode, alg, quad : ca.SX
        Right-hand sides: dx/dt, the algebraic residual, the quadrature integrands (`QUADRATURE_NAMES`).
    ode_explicit : ca.SX
        dx/dt with z eliminated (for CVODES and the baselines).
    state_names : list of str
        Names of the (unscaled) states.
    x_scale : ndarray
        x = x_physical / x_scale.
    outputs : ca.Function
        (t, x, p) -> the outputs named in `OUTPUT_NAMES`.
    energy : ca.Function
        (t, x, p) -> (kinetic, potential) energy, J.
    accelerations : ca.Function
        (t, x, p) -> accelerations of the free coordinates (the consistent z of the DAE).
    at_crank : ca.Function
        (x, crank, q) -> (dx/dt, the outputs named in `OUTPUT_NAMES`) at a given crank motion
        ``crank = [theta (rad), omega (rad/s), alpha (rad/s^2)]`` instead of the Fourier speed in p: the
        form a transcription uses when it carries the crank motion as its own variables. ``q`` holds
        the values of the carried press parameters `symbols` (empty without them; `nominal`).
    x0 : ndarray
        Consistent scaled initial state: journals centred, no elastic deformation, no rates.
    symbols : tuple of str
        Press parameters carried at the end of p (``build_model(..., parameters=...)``).
    n_modes : int or None
        Bending modes of a reduced flexible rod (None: every element DOF).
    rod_modes : ndarray or None
        A reduced rod's mode shapes: its element DOFs per modal coordinate, 2 n_elements x n_modes
        (`pressocp.beam.modes`).
    jit : bool or "auto"
        Integrate with SUNDIALS (``"idas"``, ``"cvodes"``) through compiled code
        (`pressocp.simulate.integrator_dae`): 1.3-2.4 x faster per cycle on the rigid rod, 2.3 x on the
        4-element rod with IDAS, after a compile the first time for each press and DAE form (the rigid
        rod 1.6 s with IDAS, 2.7 s with CVODES; the 4-element rod 5 s and 23 s), which the compile cache
        keeps for later processes. "auto" (the default): compiled for a flexible rod, interpreted for
        the rigid rod, whose one-off check costs less than its compile. Without a C compiler a warning
        says the virtual machine is used.
    functions : dict
        Functions built from this model by a transcription, kept for its later solves: collocation's
        point function and the solver of its last compiled solve, so that the point function and its
        derivatives are compiled once per model, not once per stage.
    """

    params: PressParams
    rod: str
    clearance: tuple[str, ...]
    n_elements: int
    n_harmonics: int
    t: ca.SX
    x: ca.SX
    z: ca.SX
    p: ca.SX
    ode: ca.SX
    alg: ca.SX
    quad: ca.SX
    ode_explicit: ca.SX
    state_names: list[str]
    x_scale: np.ndarray
    outputs: ca.Function
    energy: ca.Function
    accelerations: ca.Function
    at_crank: ca.Function
    x0: np.ndarray = field(repr=False)
    symbols: tuple[str, ...] = ()
    n_modes: int | None = None
    rod_modes: np.ndarray | None = field(default=None, repr=False, compare=False)
    jit: bool | str = field(default="auto", compare=False)
    functions: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def nx(self) -> int:
        """Number of differential states."""
        return int(self.x.numel())

    @property
    def is_rigid(self) -> bool:
        """True when the model has no states (ideal joints, rigid rod)."""
        return self.nx == 0

    @property
    def spec(self) -> ModelSpec:
        """The model level (`ModelSpec`)."""
        return ModelSpec(self.rod, self.clearance, self.n_elements, self.n_modes)

    @property
    def ram_drop(self) -> float:
        """How much lower the ram can hang than on the ideal press, m: the sum of the clearances of
        the joints that have one (the rod in tension rests the journals on their bearing walls)."""
        return float(sum(getattr(self.params, j).clearance for j in self.clearance))

    @property
    def nominal(self) -> np.ndarray:
        """The press's values of the carried parameters `symbols` (the ``q`` of ``at_crank``)."""
        return np.array([self.params.value(n) for n in self.symbols], float)

    def parameters(self, speed: FourierSpeed) -> np.ndarray:
        """The parameter vector p for a speed (harmonics padded with zeros)."""
        s = speed.padded(self.n_harmonics)
        return np.concatenate([s.a, s.b, [s.period, s.theta0], self.nominal])

    def dae(self, explicit: bool = False, work: bool = True) -> dict:
        """The DAE dict for `casadi.integrator`, with the work quadratures (`QUADRATURE_NAMES`) when
        `work` (they cost 30-48 % of an integration, so a run that reads no work leaves them out)."""
        dae = {"t": self.t, "x": self.x, "p": self.p, "ode": self.ode_explicit} if explicit else \
            {"t": self.t, "x": self.x, "z": self.z, "p": self.p, "ode": self.ode, "alg": self.alg}
        return {**dae, "quad": self.quad} if work else dae

    def z0(self, x: np.ndarray, p: np.ndarray, t: float = 0.0) -> np.ndarray:
        """Consistent algebraic state (free accelerations) for a state."""
        return np.asarray(self.accelerations(t, x, p)).ravel()


def _rod_kinematics(params: PressParams, theta, xs, eA, eB):
    """Bearing centres, slider position and rod frame from the coordinates."""
    l = params.rod_length
    A_rod = mech.crank_pin(params, theta) + eA  # big-end bearing centre
    dx = A_rod[0] - xs - eB[0]
    ys = A_rod[1] - eB[1] - ca.sqrt(l**2 - dx**2)  # slider pin on the slide
    S = ca.vertcat(xs, ys)
    B_rod = S + eB  # small-end bearing centre
    d = (A_rod - B_rod) / l  # unit vector from B to A
    normal = ca.vertcat(-d[1], d[0])  # rod's transverse direction
    return A_rod, B_rod, S, d, normal


def flexible_rod_energies(P: PressParams, n_elements: int, A, A_dot, d, phi_dot, u, u_dot) -> tuple:
    """Kinetic, gravitational and strain energy of the flexible rod in its chord frame (J), from the
    rod integrals (`pressocp.beam.integrals`) instead of sums over quadrature points.

    A point at xi from the big-end bearing centre A sits at r = A - xi d + w n (d the unit chord
    from B to A, n = (-d_y, d_x), w = N(xi) . u). With d' = -phi' n and n' = phi' d its velocity is
    A' + (xi phi' + w') n + w phi' d, so with rho A the mass per length, a = int N, b = int xi N and
    M = int N N^T:  2 T / (rho A) = l |A'|^2 + 2 A'.n (phi' l^2/2 + a.u') + 2 A'.d phi' a.u
    + phi'^2 (l^3/3 + u.M u) + 2 phi' b.u' + u'.M u',  V_g / (rho A g) = l A_y - l^2/2 d_y + a.u n_y,
    and the strain energy EI u.K u / 2. These are the quadrature sums' own values (the Gauss rule is
    exact on these polynomials) as expressions whose size does not grow with the quadrature points:
    on the 4-element rod with both clearances the right-hand side has 6 318 nodes instead of 14 712.

    Parameters
    ----------
    P : PressParams
        The press (its rod's length, mass, bending stiffness; the gravity), numbers or CasADi symbols.
    n_elements : int
        Hermite elements of the rod.
    A, A_dot : ca.SX or array (2,)
        Big-end bearing centre (m) and its velocity (m/s).
    d : ca.SX or array (2,)
        Unit vector of the chord from the small end to the big end.
    phi_dot : ca.SX or float
        The chord's angular velocity, rad/s (d = (sin phi, cos phi)).
    u, u_dot : ca.SX or array (2 N,)
        The element DOFs (`pressocp.beam`) and their rates.

    Returns
    -------
    T, V_g, strain
        Kinetic, gravitational and strain energy, J (CasADi expressions).
    """
    l, rho_a, g = P.rod_length, P.rod_mass / P.rod_length, P.gravity
    normal = ca.vertcat(-d[1], d[0])
    rod = beam.integrals(l, n_elements)
    a, b, M, K = (v if isinstance(v, ca.SX) else ca.DM(v) for v in (rod.first, rod.moment, rod.mass, rod.stiffness))
    au, Mu = ca.dot(a, u), ca.mtimes(M, u)
    twice_t = (l * ca.dot(A_dot, A_dot) + 2 * ca.dot(A_dot, normal) * (phi_dot * l**2 / 2 + ca.dot(a, u_dot))
               + 2 * ca.dot(A_dot, d) * phi_dot * au + phi_dot**2 * (l**3 / 3 + ca.dot(u, Mu))
               + 2 * phi_dot * ca.dot(b, u_dot) + ca.dot(u_dot, ca.mtimes(M, u_dot)))
    V_g = rho_a * g * (l * A[1] - l**2 / 2 * d[1] + au * normal[1])
    strain = 0.5 * P.rod_youngs_modulus * P.rod_area_moment * ca.dot(u, ca.mtimes(K, u))
    return 0.5 * rho_a * twice_t, V_g, strain


def build_model(
    params: PressParams,
    rod: str = "rigid",
    clearance: tuple[str, ...] | list[str] = JOINTS,
    n_elements: int = 4,
    n_harmonics: int = DEFAULT_HARMONICS,
    parameters: tuple[str, ...] = (),
    n_modes: int | None = None,
) -> PressModel:
    """Build the press DAE.

    Parameters
    ----------
    params : PressParams
        The press; its bearings give clearance, contact law, stiffness, damping and smoothing.
    rod : {"rigid", "flexible"}
        Rigid connecting rod, or an Euler-Bernoulli rod (Hermite elements, chord frame, axially
        rigid) whose midspan deflection is an output.
    clearance : sequence of {"crank_pin", "wrist_pin"}
        Joints with clearance; the others are ideal. ``rod="rigid", clearance=()`` is the rigid press.
    n_elements : int
        Elements of the flexible rod, 1..64.
    n_harmonics : int
        Harmonics of the Fourier speed in p, 1..50.
    parameters : tuple of str
        Press parameters by dotted name (`pressocp.params.NUMERIC_PARAMETERS`, e.g. ``"slider_mass"``,
        ``"wrist_pin.clearance"``) carried as symbols at the end of p, so that integrators and
        functions of the model can be differentiated with respect to them (`pressocp.sensitivities`).
        The state scaling stays at the press's values. ``at_crank`` takes them as its input ``q``,
        so that an NLP can carry them as its parameters (`pressocp.optimum_sensitivities`).
    n_modes : int, optional
        Reduce the flexible rod to its first `n_modes` bending modes (`ModelSpec.n_modes`): the
        elastic coordinates are then modal, each the largest deflection of its mode (m), and the
        energies are those of the element model at w = shapes @ eta. The mode shapes come from
        the press's values, also when the rod's parameters are carried as symbols.

    Returns
    -------
    PressModel
    """
    chk.instance("params", params, PressParams)
    spec = ModelSpec(rod, clearance, n_elements, n_modes)
    clearance, ne = spec.clearance, spec.n_elements
    nh = chk.integer("n_harmonics", n_harmonics, 1, 50)
    flexible = rod == "flexible"
    parameters = tuple(parameters)
    P, phys = params.with_symbols(parameters) if parameters else (params, [])
    l, g = P.rod_length, P.gravity

    # --- coordinates --------------------------------------------------------------------------
    t = ca.SX.sym("t")
    p_speed = ca.SX.sym("p", 2 * nh + 2)
    p = ca.vertcat(p_speed, *phys)
    a, b, period, theta0 = p[:nh], p[nh : 2 * nh], p[2 * nh], p[2 * nh + 1]
    crank = ca.SX.sym("crank", 3)  # theta, omega, alpha: the prescribed crank motion, set from p at the end
    theta_t, omega_t, alpha_t = crank[0], crank[1], crank[2]
    shapes = None
    if spec.n_modes is not None:
        shapes, _ = beam.modes(params.rod_length, ne, params.rod_mass / params.rod_length,
                               params.rod_youngs_modulus * params.rod_area_moment, spec.n_modes)
    nw = (2 * ne if shapes is None else spec.n_modes) if flexible else 0
    Q = ca.SX.sym("Q", 6 + nw)
    Qd = ca.SX.sym("Qd", 6 + nw)
    theta, xs, eA, eB, w = Q[0], Q[1], Q[2:4], Q[4:6], Q[6:]
    names = ["theta", "x_slider", "crank_pin_ex", "crank_pin_ey", "wrist_pin_ex", "wrist_pin_ey"]
    if flexible and shapes is not None:  # modal coordinates: each mode's largest deflection
        names += [f"eta_{k + 1}" for k in range(nw)]
    elif flexible:  # beam DOF order: w'_0, w_1, w'_1, ..., w_{N-1}, w'_{N-1}, w'_N
        names += ["w'_0"] + [n for i in range(1, ne) for n in (f"w_{i}", f"w'_{i}")] + [f"w'_{ne}"]
    free = []
    scale = []
    for j, sl in (("crank_pin", (2, 3)), ("wrist_pin", (4, 5))):
        if j in clearance:
            free += list(sl)
            scale += [getattr(params, j).clearance] * 2  # scaling at the press's values
    if flexible:
        ln = params.rod_length
        w_s = (params.rod_mass / ln) * ELASTIC_SCALE_ACCELERATION * ln**4 / (
            76.8 * params.rod_youngs_modulus * params.rod_area_moment)
        for k in range(nw):
            free.append(6 + k)
            scale.append(w_s * 3.2 / ln if names[6 + k].startswith("w'") else w_s)
    locked = [i for i in range(6 + nw) if i not in free]
    nf = len(free)

    # --- energies -----------------------------------------------------------------------------
    A_rod, B_rod, S, d, normal = _rod_kinematics(P, theta, xs, eA, eB)

    def rate(expr):
        return ca.jtimes(expr, Q, Qd)

    T_c, V_c = mech.crank_energy(P, theta, Qd[0])
    T_s, V_s = mech.body_energy(P.slider_mass, 0.0, g, S, rate(S), 0)
    phi = ca.atan2(d[0], d[1])  # rod angle: A - B = l (sin phi, cos phi)
    if flexible:
        w_dofs = w if shapes is None else ca.mtimes(ca.DM(shapes), w)  # the element DOFs
        T_r, V_r, strain = flexible_rod_energies(P, ne, A_rod, rate(A_rod), d, rate(phi), w_dofs, rate(w_dofs))
        V_r += strain
        # a rod inertia other than m l^2/12 is kept as a rigid-body correction
        T_r += 0.5 * (P.rod_inertia_value - P.rod_mass * l**2 / 12) * rate(phi) ** 2
        midspan = beam.deflection_at(l, ne, w_dofs, 0.5 * l)
        beta = 2 * P.rod_damping_ratio / P.rod_first_bending_frequency  # Rayleigh: D = beta K
        rod_damping = -beta * ca.jtimes(ca.gradient(strain, w), w, Qd[6:])
    else:
        G = 0.5 * (A_rod + B_rod)
        T_r, V_r = mech.body_energy(P.rod_mass, P.rod_inertia_value, g, G, rate(G), rate(phi))
        midspan = ca.SX(0)
        rod_damping = ca.SX(0, 1)
    lag = mech.lagrangian(T_c + T_r + T_s, V_c + V_r + V_s, Q, Qd)

    # --- applied forces: contact and process --------------------------------------------------
    F_gen = lag.Q + ca.vertcat(ca.SX.zeros(6), rod_damping)
    contacts = {}
    for j, e in (("crank_pin", eA), ("wrist_pin", eB)):
        if j in clearance:
            cf = contact_force(getattr(P, j), e, rate(e))
            contacts[j] = cf
            F_gen = F_gen + ca.jacobian(e, Q).T @ cf.vector_on_bearing
    h = S[1] + P.crank_radius + l
    hd = rate(h)
    f_proc = mech.process_force(P, h, hd)
    F_gen = F_gen + ca.jacobian(S[1], Q).T @ f_proc

    # --- split free / locked, solve accelerations, reactions ----------------------------------
    M = lag.M
    Mff, Mfl = M[free, free], M[free, locked]
    Mlf, Mll = M[locked, free], M[locked, locked]
    # locked values: theta(t) and its rates; x_S and ideal eccentricities zero
    q_locked = ca.vertcat(theta_t, ca.SX.zeros(len(locked) - 1))
    qd_locked = ca.vertcat(omega_t, ca.SX.zeros(len(locked) - 1))
    qdd_locked = ca.vertcat(alpha_t, ca.SX.zeros(len(locked) - 1))
    s_q = np.array(scale)
    s_v = s_q * VELOCITY_SCALE_RATE
    x = ca.SX.sym("x", 2 * nf)
    z = ca.SX.sym("z", nf)
    q_free, qd_free = x[:nf] * s_q, x[nf:] * s_v

    def assemble(free_vals, locked_vals):
        out = [None] * (6 + nw)
        for k, i in enumerate(free):
            out[i] = free_vals[k]
        for k, i in enumerate(locked):
            out[i] = locked_vals[k]
        return ca.vertcat(*out)

    Q_val = assemble(ca.vertsplit(q_free), ca.vertsplit(q_locked))
    Qd_val = assemble(ca.vertsplit(qd_free), ca.vertsplit(qd_locked))

    def at_state(exprs):
        return ca.substitute(exprs, [Q, Qd], [Q_val, Qd_val])

    Ff, Fl = F_gen[free], F_gen[locked]
    rhs = Ff - Mfl @ qdd_locked
    Mff_v, rhs_v = at_state([Mff, rhs]) if nf else (ca.SX(0, 0), ca.SX(0, 1))
    qdd_free_expl = ca.solve(Mff_v, rhs_v) if nf else ca.SX(0, 1)
    ode_expl = ca.vertcat(qd_free / s_q, qdd_free_expl / s_v) if nf else ca.SX(0, 1)

    def reactions(qdd_free):
        lam = Mlf @ qdd_free + Mll @ qdd_locked - Fl if nf else Mll @ qdd_locked - Fl
        return at_state([lam])[0]

    lam_expl = reactions(qdd_free_expl)
    idx = {i: k for k, i in enumerate(locked)}
    torque = lam_expl[idx[0]]
    normal_force = lam_expl[idx[1]]

    def pin_force(j, sl):
        if j in contacts:
            return at_state([contacts[j].force])[0]
        return ca.norm_2(lam_expl[[idx[sl[0]], idx[sl[1]]]])

    def ecc(j):
        return at_state([contacts[j].eccentricity_ratio])[0] if j in contacts else ca.SX(0)

    # ram acceleration: d/dt of h_dot along the motion
    Qdd_expl = assemble(ca.vertsplit(qdd_free_expl), ca.vertsplit(qdd_locked))
    Qdd_sym = ca.SX.sym("Qdd_all", 6 + nw)
    hdd = ca.jtimes(hd, Q, Qd) + ca.jtimes(hd, Qd, Qdd_sym)
    hdd = ca.substitute(at_state([hdd])[0], Qdd_sym, Qdd_expl)

    out_exprs = [
        theta_t, omega_t, torque, at_state([h])[0], at_state([hd])[0], hdd, normal_force,
        pin_force("crank_pin", (2, 3)), pin_force("wrist_pin", (4, 5)), ecc("crank_pin"), ecc("wrist_pin"),
        at_state([midspan])[0],
    ]
    at_crank = ca.Function("at_crank", [x, crank, ca.vertcat(*phys) if phys else ca.SX(0, 1)],
                           [ode_expl, *out_exprs], ["x", "crank", "q"], ["ode", *OUTPUT_NAMES])
    motion = ca.vertcat(*series(t, a, b, period, theta0))

    def timed(exprs):  # the crank motion of the Fourier speed in p at time t
        return ca.substitute(exprs, [crank], [motion])

    outputs = ca.Function("outputs", [t, x, p], timed(out_exprs), ["t", "x", "p"], list(OUTPUT_NAMES))
    energy = ca.Function("energy", [t, x, p], timed(at_state([lag.T, lag.V])), ["t", "x", "p"],
                         ["kinetic", "potential"])

    # --- quadratures: motor, contact and process power ----------------------------------------
    e_of = {"crank_pin": eA, "wrist_pin": eB}
    contact_power = sum((at_state([-ca.dot(cf.vector_on_bearing, rate(e_of[j]))])[0] for j, cf in contacts.items()),
                        ca.SX(0))
    elastic_power = sum((at_state([cf.elastic_force * cf.penetration_rate])[0] for cf in contacts.values()), ca.SX(0))
    damping_power = at_state([-ca.dot(rod_damping, Qd[6:])])[0] if flexible else ca.SX(0)
    quad = ca.vertcat(torque * omega_t, contact_power, elastic_power, at_state([f_proc * hd])[0], damping_power)

    # --- DAE ----------------------------------------------------------------------------------
    ode = ca.vertcat(qd_free / s_q, z / s_v) if nf else ca.SX(0, 1)
    alg = Mff_v @ z - rhs_v if nf else ca.SX(0, 1)
    ode_expl, ode, alg, quad, qdd_free_expl = timed([ode_expl, ode, alg, quad, qdd_free_expl])
    state_names = [names[i] for i in free] + [names[i] + "_dot" for i in free]
    x_scale = np.concatenate([s_q, s_v]) if nf else np.zeros(0)

    return PressModel(
        params=params, rod=rod, clearance=clearance, n_elements=ne, n_harmonics=nh, t=t, x=x, z=z, p=p,
        ode=ode, alg=alg, quad=quad, ode_explicit=ode_expl, state_names=state_names, x_scale=x_scale,
        outputs=outputs, energy=energy, at_crank=at_crank, x0=np.zeros(2 * nf),
        accelerations=ca.Function("accelerations", [t, x, p], [qdd_free_expl], ["t", "x", "p"], ["qdd"]),
        symbols=parameters, n_modes=spec.n_modes, rod_modes=shapes,
    )
