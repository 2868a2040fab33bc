"""The press as a CasADi DAE: a linkage (`pressocp.mechanism`) driven by a prescribed crank motion,
with journal-bearing contact in the joints that have clearance.

Coordinates
-----------
The linkage states its coordinates ``Q`` (the slider-crank's: crank angle, slider position across
the slide, the journals' eccentricities, the rod's elastic coordinates) and its energies.

* *Free* coordinates: the eccentricities of the joints with clearance and the elastic coordinates.
  They are the DAE states (with their rates), scaled by the clearance and reference sizes.
* *Locked* coordinates: theta (prescribed by the Fourier speed) and every other coordinate held
  at 0 (the ideal guide, the eccentricities of ideal joints). The Lagrange equation rows of locked
  coordinates give their reactions: the motor torque, the guide's normal force and the ideal pin
  forces.

CasADi derives the mass matrix and the velocity and potential forces from the kinetic and
potential energies (`pressocp.mechanics.lagrangian`); contact forces enter as generalised forces
through the Jacobian of the eccentricities, the process force through that of the ram height.

The DAE (semi-explicit, for IDAS) is ``x = [q/s_q, qd/s_v]``, ``z = qdd_free``,
``ode = [qd/s_q, z/s_v]``, ``alg = M_ff z - (F_f - M_fl qdd_locked)``; the explicit ODE used by
CVODES and the baselines eliminates z by a symbolic solve.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from . import checks as chk
from . import mechanics as mech
from .buffers import evaluate
from .contact import contact_force
from .mechanism import SLIDER_CRANK, Linkage, Mechanism, mechanism_from_dict, mechanism_to_dict
from .params import PressParams
from .speed import DEFAULT_HARMONICS, FourierSpeed, series

JOINTS = SLIDER_CRANK.joints
RODS = SLIDER_CRANK.rods

#: Reference speed of the eccentricity rates for state scaling: s_v = s_q * VELOCITY_SCALE_RATE.
VELOCITY_SCALE_RATE = 1.0e3  # 1/s

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
        Joints with clearance, of the mechanism's `Mechanism.joints` (``()``: the rigid press).
    n_elements : int
        Elements of a flexible rod.
    n_modes : int or None
        A flexible rod reduced to the first `n_modes` bending modes of its `n_elements`-element
        model (Craig-Bampton with the pinned ends as the interface; `pressocp.beam.modes`), 1..2
        `n_elements`; None: every element DOF.
    mechanism : Mechanism
        The linkage (`pressocp.mechanism`), the slider-crank by default.
    """

    rod: str = "rigid"
    clearance: tuple[str, ...] = JOINTS
    n_elements: int = 4
    n_modes: int | None = None
    mechanism: Mechanism = SLIDER_CRANK

    def __post_init__(self) -> None:
        chk.choice("rod", self.rod, self.mechanism.rods)
        clearance = (self.clearance,) if isinstance(self.clearance, str) else tuple(self.clearance)
        for j in clearance:
            chk.choice("clearance joint", j, self.mechanism.joints)
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
        return build_model(params, self.rod, self.clearance, self.n_elements, n_harmonics, n_modes=self.n_modes,
                           mechanism=self.mechanism)

    def describe(self) -> str:
        """E.g. "rigid rod, clearance in crank_pin and wrist_pin" or "rigid press (ideal joints)"."""
        n, m = self.n_elements, self.n_modes
        modes = "" if m is None else f", {m} mode{'s' * (m != 1)}"
        rod = f"flexible rod ({n} element{'s' * (n != 1)}{modes})" if self.rod == "flexible" else "rigid rod"
        press = "" if self.mechanism.name == SLIDER_CRANK.name else f"{self.mechanism.name.replace('_', '-')} press, "
        if not self.clearance:
            return f"{press}rigid press (ideal joints)" if self.rod == "rigid" else f"{press}{rod}, ideal joints"
        return f"{press}{rod}, clearance in {' and '.join(self.clearance)}"

    def to_dict(self) -> dict:
        """Plain data (``n_modes`` only when set)."""
        d = {"rod": self.rod, "clearance": list(self.clearance), "n_elements": self.n_elements}
        d = d if self.n_modes is None else {**d, "n_modes": self.n_modes}
        return d if self.mechanism == SLIDER_CRANK else {**d, "mechanism": mechanism_to_dict(self.mechanism)}

    @classmethod
    def from_dict(cls, data: dict) -> "ModelSpec":
        mechanism = mechanism_from_dict(data["mechanism"]) if "mechanism" in data else SLIDER_CRANK
        return cls(data.get("rod", "rigid"), tuple(data.get("clearance", mechanism.joints)),
                   data.get("n_elements", 4), data.get("n_modes"), mechanism)


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
        the rigid rod, whose one-off check costs less than its compile; callers that re-simulate one
        model many times (the optimiser's checks, `sensitivities`) compile it too
        (`pressocp.simulate.for_repeated_use`). Without a C compiler a warning says the virtual
        machine is used.
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
    mechanism: Mechanism = field(default=SLIDER_CRANK, repr=False)

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
        return ModelSpec(self.rod, self.clearance, self.n_elements, self.n_modes, self.mechanism)

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

    def ideal_series(self, speed: FourierSpeed, t: np.ndarray) -> dict[str, np.ndarray]:
        """The outputs (`OUTPUT_NAMES`) of a model without states (ideal joints, rigid rod) driven by
        `speed`, at the times `t` (s): no integration is needed."""
        if not self.is_rigid:
            raise ValueError(f"ideal_series needs a model without states (ideal joints, rigid rod); this one is "
                             f"{self.spec.describe()}")
        t = np.atleast_1d(np.asarray(t, float))
        out = evaluate(self.outputs.map(t.size), t, np.zeros((0, t.size)),
                       np.tile(self.parameters(speed)[:, None], (1, t.size)))
        return {name: v.ravel() for name, v in zip(OUTPUT_NAMES, out)}

    def z0(self, x: np.ndarray, p: np.ndarray, t: float = 0.0) -> np.ndarray:
        """Consistent algebraic state (free accelerations) for a state."""
        return np.asarray(self.accelerations(t, x, p)).ravel()


def build_model(
    params: PressParams,
    rod: str = "rigid",
    clearance: tuple[str, ...] | list[str] = JOINTS,
    n_elements: int = 4,
    n_harmonics: int = DEFAULT_HARMONICS,
    parameters: tuple[str, ...] = (),
    n_modes: int | None = None,
    mechanism: Mechanism = SLIDER_CRANK,
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
    mechanism : Mechanism
        The linkage (`pressocp.mechanism`): the slider-crank, `SixBar` or `KnuckleJoint`.

    Returns
    -------
    PressModel
    """
    chk.instance("params", params, PressParams)
    spec = ModelSpec(rod, clearance, n_elements, n_modes, mechanism)
    nh, parameters = chk.integer("n_harmonics", n_harmonics, 1, 50), tuple(parameters)
    P, phys = params.with_symbols(parameters) if parameters else (params, [])
    t, p = ca.SX.sym("t"), ca.vertcat(ca.SX.sym("p", 2 * nh + 2), *phys)
    crank = ca.SX.sym("crank", 3)  # theta, omega, alpha: the prescribed crank motion, set from p at the end
    lk = spec.mechanism.linkage(params, P, spec.rod, spec.n_elements, spec.n_modes)
    st = Locked(lk, params, spec.clearance, crank)
    lag = mech.lagrangian(lk.kinetic, lk.potential + mech.counterbalance_potential(P, lk.ram_height), lk.Q, lk.Qd)
    F_gen, contacts = with_contacts(lk, P, spec.clearance, lag.Q + lk.forces)
    f_proc = mech.process_force(P, lk.ram_height, lk.rate(lk.ram_height))
    F_gen = F_gen + ca.jacobian(lk.ram_height, lk.Q).T @ f_proc

    Mff, rhs, qdd_free, lam = st.solve(lag.M, F_gen)
    out_exprs = outputs_of(lk, st, lam, contacts, qdd_free, crank)
    quad = quadratures(lk, st, f_proc, lam, contacts, crank)
    motion = ca.vertcat(*series(t, p[:nh], p[nh : 2 * nh], p[2 * nh], p[2 * nh + 1]))

    def timed(exprs):  # the crank motion of the Fourier speed in p at time t
        return ca.substitute(exprs, [crank], [motion])

    ode_expl = ca.vertcat(st.qd_free / st.s_q, qdd_free / st.s_v) if st.nf else ca.SX(0, 1)
    at_crank = ca.Function("at_crank", [st.x, crank, ca.vertcat(*phys) if phys else ca.SX(0, 1)],
                           [ode_expl, *out_exprs], ["x", "crank", "q"], ["ode", *OUTPUT_NAMES])
    outputs = ca.Function("outputs", [t, st.x, p], timed(out_exprs), ["t", "x", "p"], list(OUTPUT_NAMES))
    energy = ca.Function("energy", [t, st.x, p], timed(st.at_state([lag.T, lag.V])), ["t", "x", "p"],
                         ["kinetic", "potential"])
    ode = ca.vertcat(st.qd_free / st.s_q, st.z / st.s_v) if st.nf else ca.SX(0, 1)
    alg = Mff @ st.z - rhs if st.nf else ca.SX(0, 1)
    ode_expl, ode, alg, quad, qdd_free = timed([ode_expl, ode, alg, quad, qdd_free])
    return PressModel(
        params=params, rod=spec.rod, clearance=spec.clearance, n_elements=spec.n_elements, n_harmonics=nh, t=t,
        x=st.x, z=st.z, p=p, ode=ode, alg=alg, quad=quad, ode_explicit=ode_expl, state_names=st.state_names,
        x_scale=st.x_scale, outputs=outputs, energy=energy, at_crank=at_crank, x0=np.zeros(2 * st.nf),
        accelerations=ca.Function("accelerations", [t, st.x, p], [qdd_free], ["t", "x", "p"], ["qdd"]),
        symbols=parameters, n_modes=spec.n_modes, rod_modes=lk.details.get("rod_modes"), mechanism=spec.mechanism,
    )


class Locked:
    """The split of a linkage's coordinates into free ones (the states: the eccentricities of the
    joints with clearance, then the elastic coordinates) and locked ones (the crank angle, held to
    the prescribed motion ``crank``, and the rest held at 0), with the scaled states.

    Attributes
    ----------
    free, locked : list of int
        Indices in ``Q``.
    s_q, s_v : ndarray
        Scales of the free coordinates (m, rad) and of their rates (`VELOCITY_SCALE_RATE` x s_q).
    x, z : ca.SX
        Scaled states ``[q_free / s_q, qd_free / s_v]`` and the free accelerations (the DAE's z).
    q_free, qd_free : ca.SX
        The free coordinates and rates in physical units, from x.
    qdd_locked : ca.SX
        Accelerations of the locked coordinates: alpha, then zeros.
    """

    def __init__(self, lk: Linkage, params: PressParams, clearance: tuple[str, ...], crank: ca.SX) -> None:
        ecc = [(i, getattr(params, j).clearance) for j, ij in lk.joints.items() if j in clearance for i in ij]
        free = ecc + list(lk.elastic.items())  # scales at the press's values
        self.free, self.lk = [i for i, _ in free], lk
        self.locked = [i for i in range(lk.Q.numel()) if i not in self.free]
        self.nf = nf = len(free)
        self.s_q = np.array([s for _, s in free])
        self.s_v = self.s_q * VELOCITY_SCALE_RATE
        self.x, self.z = ca.SX.sym("x", 2 * nf), ca.SX.sym("z", nf)
        self.q_free, self.qd_free = self.x[:nf] * self.s_q, self.x[nf:] * self.s_v
        zeros = ca.SX.zeros(len(self.locked) - 1)
        self.qdd_locked = ca.vertcat(crank[2], zeros)
        self.values = [self.assemble(self.q_free, ca.vertcat(crank[0], zeros)),
                       self.assemble(self.qd_free, ca.vertcat(crank[1], zeros))]

    @property
    def state_names(self) -> list[str]:
        names = [self.lk.names[i] for i in self.free]
        return names + [n + "_dot" for n in names]

    @property
    def x_scale(self) -> np.ndarray:
        return np.concatenate([self.s_q, self.s_v]) if self.nf else np.zeros(0)

    def assemble(self, free_values: ca.SX, locked_values: ca.SX) -> ca.SX:
        """The full coordinate vector from its free and locked parts."""
        out = [None] * (len(self.free) + len(self.locked))
        for idx, vals in ((self.free, free_values), (self.locked, locked_values)):
            for i, v in zip(idx, ca.vertsplit(vals)):
                out[i] = v
        return ca.vertcat(*out)

    def solve(self, M: ca.SX, F: ca.SX) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX]:
        """Lagrange's equations ``M Qdd = F + reactions`` at the states: the free rows
        ``M_ff qdd_free = rhs`` (returned as M_ff, rhs and the explicit solution) and the locked
        rows' reactions ``M_l Qdd - F_l``."""
        free, locked = self.free, self.locked
        if not self.nf:
            return ca.SX(0, 0), ca.SX(0, 1), ca.SX(0, 1), self.at_state([M[locked, locked] @ self.qdd_locked
                                                                        - F[locked]])[0]
        Mff, rhs = self.at_state([M[free, free], F[free] - M[free, locked] @ self.qdd_locked])
        qdd_free = ca.solve(Mff, rhs)
        lam = M[locked, free] @ qdd_free + M[locked, locked] @ self.qdd_locked - F[locked]
        return Mff, rhs, qdd_free, self.at_state([lam])[0]

    def at_state(self, exprs: list) -> list:
        """`exprs` (in Q, Qd) at the states and the prescribed crank motion."""
        return ca.substitute(exprs, [self.lk.Q, self.lk.Qd], self.values)


def with_contacts(lk: Linkage, P: PressParams, clearance: tuple[str, ...], F_gen: ca.SX) -> tuple[ca.SX, dict]:
    """The generalised forces `F_gen` on ``Q`` plus the contact forces of the joints with clearance,
    and each joint's `pressocp.contact.contact_force`."""
    contacts = {}
    for j in lk.joints:
        if j in clearance:
            e = lk.eccentricity(j)
            contacts[j] = contact_force(getattr(P, j), e, lk.rate(e))
            F_gen = F_gen + ca.jacobian(e, lk.Q).T @ contacts[j].vector_on_bearing
    return F_gen, contacts


def outputs_of(lk: Linkage, st: Locked, lam: ca.SX, contacts: dict, qdd_free: ca.SX, crank: ca.SX) -> list:
    """The `OUTPUT_NAMES` at the states and the crank motion: the motor torque is the crank angle's
    reaction, an ideal joint's pin force the norm of its eccentricity's reactions, a joint with
    clearance its contact force; the ram acceleration is d/dt of its velocity along the motion."""
    idx = {i: k for k, i in enumerate(st.locked)}

    def pin_force(j):
        if j in contacts:
            return st.at_state([contacts[j].force])[0]
        return ca.norm_2(lam[[idx[i] for i in lk.joints[j]]])

    def ecc(j):
        return st.at_state([contacts[j].eccentricity_ratio])[0] if j in contacts else ca.SX(0)

    h = lk.ram_height
    hd = lk.rate(h)
    Qdd = ca.SX.sym("Qdd", lk.Q.numel())
    hdd = ca.jtimes(hd, lk.Q, lk.Qd) + ca.jtimes(hd, lk.Qd, Qdd)
    hdd = ca.substitute(st.at_state([hdd])[0], Qdd, st.assemble(qdd_free, st.qdd_locked))
    values = {"theta": crank[0], "omega": crank[1], "torque": lam[idx[0]], "ram_height": st.at_state([h])[0],
              "ram_velocity": st.at_state([hd])[0], "ram_acceleration": hdd,
              **{n: lam[idx[i]] for n, i in lk.reactions.items()},
              **{f"{j}_force": pin_force(j) for j in lk.joints},
              **{f"{j}_eccentricity": ecc(j) for j in lk.joints},
              **{n: st.at_state([v])[0] for n, v in lk.outputs.items()}}
    return [values[n] for n in OUTPUT_NAMES]


def quadratures(lk: Linkage, st: Locked, f_proc: ca.SX, lam: ca.SX, contacts: dict, crank: ca.SX) -> ca.SX:
    """The integrands of `QUADRATURE_NAMES`: motor power, the power the contacts absorb and its
    elastic part, the power of the process force `f_proc` (N, along the ram height) and the power
    dissipated by the linkage's forces, W."""
    idx0 = st.locked.index(0)
    contact_power = sum((st.at_state([-ca.dot(cf.vector_on_bearing, lk.rate(lk.eccentricity(j)))])[0]
                         for j, cf in contacts.items()), ca.SX(0))
    elastic_power = sum((st.at_state([cf.elastic_force * cf.penetration_rate])[0] for cf in contacts.values()),
                        ca.SX(0))
    process_power = st.at_state([f_proc * lk.rate(lk.ram_height)])[0]
    return ca.vertcat(lam[idx0] * crank[1], contact_power, elastic_power, process_power,
                      st.at_state([lk.dissipated])[0])
