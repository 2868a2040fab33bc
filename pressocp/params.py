"""Press parameters: geometry, masses, bearings (with clearance) and an optional process force.

All quantities are SI. Conventions used throughout pressocp:

* y points along the slide *away* from the bed; the crank axis is at the origin, the ram below it.
* Crank angle theta = 0 at top dead centre (ram furthest from the bed, crank pin pointing away
  from the slider); theta increases with time. The crank pin is at ``r (sin theta, cos theta)``.
* h is the ram height above bottom dead centre, H = 2 r the stroke, ram velocity = dh/dt
  (negative on the downstroke).
* Motor torque is positive when it drives the crank in its direction of rotation.
* Gravity acts along the slide toward the bed (-y).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from . import checks as chk
from .laws import CONTACT_LAWS

#: Steel used for the Hertz contact stiffness when a bearing's stiffness is not given.
STEEL_YOUNGS_MODULUS = 2.1e11  # Pa
STEEL_POISSON = 0.3

#: Default smoothing width as a fraction of the radial clearance (see `Bearing.smoothing`).
SMOOTHING_FRACTION = 1e-3


#: Plausible ranges (SI) of press dimensions; a value outside names the likely unit slip.
LENGTH_RANGE = (1e-3, 5.0)  # m: crank radius, rod length, journal radius
MASS_RANGE = (1e-3, 1e5)  # kg
MODULUS_RANGE = (1e8, 1e14)  # Pa: polymers to 100 x steel (a rigid-limit check uses 2.1e13)
MAX_GRAVITY = 100.0  # m/s^2: 0 (a horizontal press) to well above 9.81
MAX_CRANK_INERTIA = 1e5  # kg m^2: crank, gear and reflected motor of the largest presses
AREA_MOMENT_RANGE = (1e-14, 1e-1)  # m^4: a 1 mm square rod (8e-14) to a 1 m one (8e-2)
MAX_COM_RATIO = 2.0  # |crank_com| / crank_radius (a counterweight puts it below 0)
#: A rod or crank heavier than this many slider masses is suspected of being in grams.
MAX_PART_RATIO = 10.0
#: A forming force above this many times the slider's weight is suspected of a unit slip (mN).
MAX_FORCE_RATIO = 1e5
#: A contact stiffness outside this factor of its journal's Hertz value is suspected of a unit slip
#: (the soft stage of multiple shooting divides it by 100).
HERTZ_FACTOR = 500.0
#: Largest radial clearance as a fraction of the journal radius.
MAX_CLEARANCE_FRACTION = 0.1
#: The rod must be at least this many crank radii long.
MIN_ROD_RATIO = 1.5
STIFFNESS_RANGE = (1e4, 1e16)  # N/m^n
#: Smallest radial clearance, m: the Hertz stiffness grows as 1/sqrt(c) (inf at 5e-324), and the
#: smallest clearance used (the rigid-limit test) is 1 um.
MIN_CLEARANCE = 1e-6


def plausible(name: str, value: float, lo: float, hi: float, unit: str) -> float:
    """`value` in [lo, hi] (a positive, finite number), else a ValueError that names the field, the
    value, the range and, for a value 1000x too large, the likely mm-for-m slip."""
    x = chk.positive(name, value, unit)
    if not lo <= x <= hi:
        slip = f": a value in mm? {x:g} mm is {x / 1000:g} {unit}" if unit == "m" and lo <= x / 1000 <= hi else \
            (f": a value in g? {x:g} g is {x / 1000:g} kg" if unit == "kg" and x > hi else "")
        raise ValueError(f"{name} must be in [{lo:g}, {hi:g}] {unit}, got {x!r}{slip}")
    return x


def hertz_internal_stiffness(
    journal_radius: float,
    clearance: float,
    youngs_modulus: float = STEEL_YOUNGS_MODULUS,
    poisson: float = STEEL_POISSON,
) -> float:
    """Hertz-type stiffness of a journal inside a bearing (internal cylindrical contact).

    ``K = 4 / (3 (h_b + h_j)) * sqrt(R_b R_j / (R_b - R_j))`` with ``h = (1 - nu^2) / E`` for
    both bodies of the same material and ``R_b = R_j + c``.

    Parameters
    ----------
    journal_radius : float
        Journal (pin) radius R_j, m.
    clearance : float
        Radial clearance c = R_b - R_j, m.
    youngs_modulus, poisson : float
        Material of journal and bearing, Pa and -.

    Returns
    -------
    float
        Stiffness K in N/m^1.5 (for the force law F = K delta^1.5).
    """
    rj = chk.positive("journal_radius", journal_radius, "m")
    c = chk.positive("clearance", clearance, "m")
    return hertz_formula(rj, c, youngs_modulus, poisson)


def hertz_formula(journal_radius, clearance, youngs_modulus: float = STEEL_YOUNGS_MODULUS,
                  poisson: float = STEEL_POISSON):
    """`hertz_internal_stiffness` without the checks: numbers or CasADi symbols (for derivatives)."""
    h = (1.0 - poisson**2) / youngs_modulus
    rb = journal_radius + clearance
    return 4.0 / (3.0 * 2.0 * h) * (rb * journal_radius / clearance) ** 0.5


#: Bearing fields that may be None, and the property that gives the value in use.
DERIVED = {"stiffness": "contact_stiffness", "damping": "damping_value", "smoothing": "smoothing_width",
           "rod_inertia": "rod_inertia_value"}


@dataclass(frozen=True)
class Bearing:
    """A revolute joint with radial clearance (journal in bearing).

    Parameters
    ----------
    clearance : float
        Radial clearance c, m; must be > 0.
    journal_radius : float
        Journal radius, m.
    stiffness : float or None
        Contact stiffness K in N/m^exponent. ``None``: the Hertz internal-contact formula
        (`hertz_internal_stiffness`) for steel, E = 2.1e11 Pa, nu = 0.3.
    exponent : float
        Exponent n of the force law F = K delta^n, in [1, 3].
    damping : float or None
        For ``law="hunt-crossley"``: hysteresis factor chi in s/m, F = K delta^n (1 + chi delta_dot),
        no tension. ``None`` -> 3.0 s/m (restitution 0.9 at a 0.05 m/s reference impact speed).
        For ``law="kelvin-voigt"`` (Dubowsky impact pair, F = K delta^n + c delta_dot, no tension):
        c in N s/m; ``None`` -> the value that equals the default Hunt-Crossley damping force at
        a penetration of 1 um.
    law : str
        Contact force law, a name in `pressocp.laws.CONTACT_LAWS`: "hunt-crossley" or "kelvin-voigt".
    smoothing : float or None
        Width (m) of the C1 smoothing of penetration and eccentricity; must be < clearance.
        ``None`` -> ``1e-3 * clearance``.
    tangential_damping : float
        Viscous damping of the journal's motion along the bearing surface while in contact
        (lubricant film), N s/m, >= 0. Without it the frictionless journal's tangential modes are
        undamped and the periodic steady state is neither attracting nor well conditioned; the
        default 1e3 N s/m damps them within about two cycles; in non-impact periodic states its force
        is 0.13-0.25 N (measured on the default press; see the README).
    """

    clearance: float = 1e-4
    journal_radius: float = 0.04
    stiffness: float | None = None
    exponent: float = 1.5
    damping: float | None = None
    law: str = "hunt-crossley"
    smoothing: float | None = None
    tangential_damping: float = 1e3

    def __post_init__(self) -> None:
        chk.convert_reals(self)
        c = chk.positive("clearance", self.clearance, "m")
        chk.nonnegative("tangential_damping", self.tangential_damping, "N s/m")
        rj = plausible("journal_radius", self.journal_radius, *LENGTH_RANGE, "m")
        allowed = f"[{MIN_CLEARANCE:g}, {MAX_CLEARANCE_FRACTION * rj:g}] m ({MAX_CLEARANCE_FRACTION:.0%} of journal_radius={rj:g} m)"
        if c > MAX_CLEARANCE_FRACTION * rj:
            # Just over the limit is a worn joint, not a slip; ten times over, in mm, is a plausible clearance.
            in_mm = c >= 10 * MAX_CLEARANCE_FRACTION * rj and c / 1000 <= MAX_CLEARANCE_FRACTION * rj
            slip = f": a clearance in mm? {c:g} mm is {c / 1000:g} m" if in_mm else ""
            raise ValueError(f"clearance must be in {allowed}, got {c!r}{slip}")
        if c < MIN_CLEARANCE:
            raise ValueError(f"clearance must be in {allowed}, got {c!r}: below a micrometre the joint is ideal "
                             "(build the model with clearance=() for ideal joints)")
        if self.stiffness is not None:
            k = chk.positive("stiffness", self.stiffness, "N/m^exponent")
            if not STIFFNESS_RANGE[0] <= k <= STIFFNESS_RANGE[1]:
                raise ValueError(f"stiffness must be in [{STIFFNESS_RANGE[0]:g}, {STIFFNESS_RANGE[1]:g}] N/m^exponent, "
                                 f"got {k!r} (steel journals are about 1e10 to 1e12)")
        n = chk.finite("exponent", self.exponent)
        if not 1.0 <= n <= 3.0:
            raise ValueError(f"exponent must be in [1, 3], got {n!r}")
        if self.stiffness is not None and n == 1.5:
            kh = hertz_formula(rj, c)
            if not kh / HERTZ_FACTOR <= k <= kh * HERTZ_FACTOR:
                chk.suspect(f"stiffness = {k:g} N/m^1.5 is {k / kh:.3g} x the Hertz stiffness of this journal "
                            f"({kh:.3g} N/m^1.5 for radius {rj:g} m and clearance {c:g} m): check its unit, N/m^1.5 "
                            "(1 N/mm^1.5 is 3.16e4 N/m^1.5)")
        if self.damping is not None:
            chk.nonnegative("damping", self.damping)
        chk.choice("law", self.law, tuple(CONTACT_LAWS))
        if self.smoothing is not None:
            s = chk.positive("smoothing", self.smoothing, "m")
            if s >= c:
                raise ValueError(f"smoothing must be in (0, clearance={c:g}) m, got {s!r}")

    # Resolved values -------------------------------------------------------------------------
    @property
    def contact_stiffness(self) -> float:
        """K in N/m^exponent (given, or Hertz for steel)."""
        if self.stiffness is not None:
            return self.stiffness
        return hertz_formula(self.journal_radius, self.clearance)

    @property
    def damping_value(self) -> float:
        """The law's damping (`pressocp.laws.ContactLaw.damping_unit`: chi in s/m for Hunt-Crossley, c
        in N s/m for Kelvin-Voigt), given or the law's default."""
        if self.damping is not None:
            return self.damping
        return CONTACT_LAWS[self.law].default_damping(self.contact_stiffness, self.exponent)

    @property
    def smoothing_width(self) -> float:
        """Smoothing width in m."""
        return self.smoothing if self.smoothing is not None else SMOOTHING_FRACTION * self.clearance

    @classmethod
    def from_restitution(
        cls,
        restitution: float,
        impact_speed: float,
        *,
        model: str = "hunt-crossley",
        **kwargs: float,
    ) -> "Bearing":
        """Hunt-Crossley bearing whose hysteresis factor matches a restitution coefficient.

        A smooth solver cannot store the impact speed, so chi = xi(e) / v_ref with a reference
        impact speed v_ref (Machado et al., Mech. Mach. Theory 53, 2012).

        Parameters
        ----------
        restitution : float
            Coefficient of restitution e in (0, 1].
        impact_speed : float
            Reference impact speed v_ref, m/s, > 0.
        model : {"hunt-crossley", "lankarani-nikravesh", "flores", "gonthier"}
            xi(e): 3(1-e)/2, 3(1-e^2)/4, 8(1-e)/(5e), (1-e^2)/e.
        **kwargs
            Other `Bearing` fields.
        """
        e = chk.finite("restitution", restitution)
        if not 0.0 < e <= 1.0:
            raise ValueError(f"restitution must be in (0, 1], got {e!r}")
        v = chk.positive("impact_speed", impact_speed, "m/s")
        xi = {
            "hunt-crossley": 1.5 * (1 - e),
            "lankarani-nikravesh": 0.75 * (1 - e * e),
            "flores": 8 * (1 - e) / (5 * e),
            "gonthier": (1 - e * e) / e,
        }
        chk.choice("model", model, tuple(xi))
        return cls(damping=xi[model] / v, law="hunt-crossley", **kwargs)


@dataclass(frozen=True)
class ProcessForce:
    """Forming force on the ram over a height window on the downstroke, with smooth edges.

    The force pushes the ram away from the bed (it resists the downstroke). It is either a constant
    ``force`` between ``h_bottom`` and ``h_top``, or a measured curve: ``heights`` and ``forces``,
    the force against the ram height (a deep-drawing or blanking curve), linear between the points
    and zero outside them. The constant is the curve ``[(h_bottom, force), (h_top, force)]``. Both
    are smoothed over ``edge`` (the corners and the steps at the ends are rounded over about
    +-edge) and switched off on the upstroke by ``s(-v/speed_edge)``, ``s(x) = (1 + tanh x) / 2``.

    Parameters
    ----------
    force : float
        Constant force, N, >= 0 (0: no constant force).
    h_top, h_bottom : float
        Ram heights above bottom dead centre where the constant force starts and ends, m.
    edge : float
        Smoothing length of the corners and ends, m.
    speed_edge : float
        Smoothing speed of the downstroke switch, m/s.
    heights : tuple of float
        Ram heights above bottom dead centre of the curve's points, m, increasing (empty: no curve).
        Not together with ``force``.
    forces : tuple of float
        The force at each height, N, >= 0.
    window : tuple of float
        Where the constant force starts and ends as h/H (ram height over the stroke, like
        `SpeedProblem.window`), start above end, each in [-1, 2]; empty: ``h_top`` and
        ``h_bottom`` in metres. Given, it sets them for the press's stroke (`PressParams`), so a
        press with another stroke keeps the force at the same share of its stroke.
    """

    force: float = 0.0
    h_top: float = 0.0127
    h_bottom: float = 0.0
    edge: float = 5e-4
    speed_edge: float = 1e-3
    heights: tuple[float, ...] = ()
    forces: tuple[float, ...] = ()
    window: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        chk.convert_reals(self)
        chk.nonnegative("force", self.force, "N")
        self._check_window()
        top = chk.finite("h_top", self.h_top)
        bottom = chk.finite("h_bottom", self.h_bottom)
        if bottom >= top:
            raise ValueError(f"h_bottom must be in (-inf, h_top={top:g}) m, got {bottom!r}")
        edge = chk.positive("edge", self.edge, "m")
        chk.positive("speed_edge", self.speed_edge, "m/s")
        h, f = chk.point_table(self, "heights", "forces")
        if not h:
            return
        if len(h) < 2:
            raise ValueError(f"heights must hold at least 2 points (a curve), got {len(h)}")
        if self.force > 0.0:
            raise ValueError(f"force must be 0 when a curve (heights, forces) is given, got {self.force!r} N: "
                             "give the constant force as the curve's points, or drop the curve")
        steps = np.diff(h)
        if np.any(steps <= 0.0):
            k = int(np.argmax(steps <= 0.0))
            raise ValueError(f"heights must increase, got {h[k]!r} then {h[k + 1]!r} m (points {k} and {k + 1})")
        if min(f) < 0.0:
            raise ValueError(f"forces must be >= 0 N (the force resists the downstroke), got {min(f)!r}")
        if steps.min() < edge:
            chk.suspect(f"process_force.heights are {steps.min():g} m apart somewhere, less than edge = {edge:g} m: "
                        "the smoothing rounds such detail away")

    def _check_window(self) -> None:
        w = tuple(float(v) for v in chk.finite_array("window", self.window))
        object.__setattr__(self, "window", w)
        if not w:
            return
        if len(w) != 2 or not -1.0 <= w[1] < w[0] <= 2.0:
            slip = f": values in %? {w[0]:g} % is {w[0] / 100:g}" if len(w) == 2 and 1.0 < w[0] <= 100.0 else ""
            raise ValueError(f"window must be (start, end) as h/H with -1 <= end < start <= 2 (the force starts "
                             f"higher on the downstroke), got {list(w)}{slip}")
        if self.heights:
            raise ValueError("window sets where a constant force acts; a curve (heights, forces) gives its own heights")

    def for_stroke(self, stroke: float) -> "ProcessForce":
        """The force with ``h_top`` and ``h_bottom`` set from its `window` for a press of `stroke` m;
        itself without a window."""
        if not self.window:
            return self
        return replace(self, h_top=self.window[0] * stroke, h_bottom=self.window[1] * stroke)

    @property
    def active(self) -> bool:
        """Whether any force acts."""
        return self.force > 0.0 or any(f > 0.0 for f in self.forces)

    @property
    def peak(self) -> float:
        """The largest force of the curve (or the constant), N; 0 when none acts."""
        return max(self.knots()[1]) if self.active else 0.0

    def knots(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """(heights m, forces N) of the piecewise-linear curve the force follows: the curve's points,
        or the constant's two."""
        if self.heights:
            return self.heights, self.forces
        return (self.h_bottom, self.h_top), (self.force, self.force)

    @classmethod
    def from_csv(cls, path: str | Path, **settings: float) -> "ProcessForce":
        """A curve from a CSV file with a header and two columns: ram height above bottom dead centre
        (m) and force (N), in any order of rows. ``settings``: ``edge``, ``speed_edge``."""
        import pandas as pd

        table = pd.read_csv(path)
        if table.shape[1] != 2:
            raise ValueError(f"{path}: a process-force curve needs 2 columns (height m, force N), got "
                             f"{table.shape[1]}: {list(table.columns)}")
        table = table.sort_values(table.columns[0])
        return cls(heights=tuple(table.iloc[:, 0]), forces=tuple(table.iloc[:, 1]), **settings)


@dataclass(frozen=True)
class Counterbalance:
    """Slide counterbalance: air cylinders that push the ram up, away from the bed.

    The force at ram height h (above bottom dead centre) is ``force * (1 + h / gas_length) **
    (-exponent)``: the gas is compressed as the ram goes down, polytropically. ``exponent`` 0 is a
    constant force (a large surge tank), 1 isothermal, 1.4 adiabatic. The force is conservative: its
    potential energy enters the press's, so it does no net work over a cycle.

    Parameters
    ----------
    force : float
        Upward force with the ram at bottom dead centre, N, >= 0 (0: none): the pre-charge pressure
        times the piston area, compressed to bottom dead centre.
    gas_length : float
        Gas volume (cylinders and surge tank) at bottom dead centre over the piston area, m.
    exponent : float
        Polytropic exponent, in [0, 2].
    """

    force: float = 0.0
    gas_length: float = 1.0
    exponent: float = 0.0

    def __post_init__(self) -> None:
        chk.convert_reals(self)
        chk.nonnegative("force", self.force, "N")
        chk.positive("gas_length", self.gas_length, "m")
        chk.in_closed_interval("exponent", self.exponent, 0.0, 2.0)

    def force_at(self, h):
        """Upward force at ram height h (m above bottom dead centre; a number, array or CasADi
        expression), N."""
        return self.force * (1.0 + h / self.gas_length) ** (-self.exponent)


@dataclass(frozen=True)
class PressParams:
    """A slider-crank press. ``PressParams()`` is the default press (stroke 0.1 m).

    Parameters
    ----------
    crank_radius : float
        Crank radius r, m (stroke H = 2 r).
    rod_length : float
        Connecting rod length l, centre to centre, m; at least `MIN_ROD_RATIO` (1.5) x ``crank_radius``.
    crank_inertia : float
        Moment of inertia about the crank axis, kg m^2 (crank, gear, reflected motor).
    crank_mass : float
        Crank mass, kg (enters through gravity and the crank's centre of mass).
    crank_com : float
        Distance of the crank's centre of mass from the axis, along the crank toward the pin, m.
    rod_mass : float
        Connecting rod mass (uniform rod), kg.
    rod_inertia : float or None
        Rod moment of inertia about its centre, kg m^2; ``None`` -> m l^2 / 12.
    rod_youngs_modulus : float
        Young's modulus of the rod, Pa.
    rod_area_moment : float
        Second moment of area of the rod section for bending, m^4.
    rod_damping_ratio : float
        Material damping of the flexible rod: stiffness-proportional (Rayleigh) damping with this
        damping ratio at the first pinned-pinned bending mode (higher modes are damped more), in
        [0, 1). 0 for an undamped rod (e.g. the Simeon benchmark).
    slider_mass : float
        Ram plus upper die, kg.
    gravity : float
        Acceleration of gravity along the slide toward the bed, m/s^2 (0 for a horizontal press).
    crank_pin, wrist_pin : Bearing
        The crank-pin (crank-rod) and wrist-pin (rod-slider) joints.
    process_force : ProcessForce
        Optional forming force on the ram (default off).
    counterbalance : Counterbalance
        Optional slide counterbalance (default off).
    """

    crank_radius: float = 0.05
    rod_length: float = 0.25
    crank_inertia: float = 0.5
    crank_mass: float = 20.0
    crank_com: float = 0.0
    rod_mass: float = 3.14
    rod_inertia: float | None = None
    rod_youngs_modulus: float = 2.1e11
    rod_area_moment: float = 2.13e-7
    rod_damping_ratio: float = 0.02
    slider_mass: float = 150.0
    gravity: float = 9.81
    crank_pin: Bearing = field(default_factory=lambda: Bearing(clearance=1e-4, journal_radius=0.04))
    wrist_pin: Bearing = field(default_factory=lambda: Bearing(clearance=1e-4, journal_radius=0.025))
    process_force: ProcessForce = field(default_factory=ProcessForce)
    counterbalance: Counterbalance = field(default_factory=Counterbalance)

    def __post_init__(self) -> None:
        chk.convert_reals(self)
        r = plausible("crank_radius", self.crank_radius, *LENGTH_RANGE, "m")
        l = plausible("rod_length", self.rod_length, *LENGTH_RANGE, "m")
        if l < MIN_ROD_RATIO * r * (1.0 - 1e-12):  # the bound itself is allowed, rounding aside
            raise ValueError(f"rod_length must be in [{MIN_ROD_RATIO:g} x crank_radius = {MIN_ROD_RATIO * r:g}, "
                             f"{LENGTH_RANGE[1]:g}] m, got {l!r}")
        J = chk.positive("crank_inertia", self.crank_inertia, "kg m^2")
        if J > MAX_CRANK_INERTIA:
            slip = (f": a value in kg mm^2? {J:g} kg mm^2 is {J / 1e6:g} kg m^2" if J / 1e6 <= MAX_CRANK_INERTIA
                    else "")
            raise ValueError(f"crank_inertia must be in (0, {MAX_CRANK_INERTIA:g}] kg m^2, got {J!r}{slip}")
        chk.nonnegative("crank_mass", self.crank_mass, "kg")
        com = chk.finite("crank_com", self.crank_com)
        if abs(com) > MAX_COM_RATIO * r:
            slip = f": a value in mm? {com:g} mm is {com / 1000:g} m" if abs(com / 1000) <= MAX_COM_RATIO * r else ""
            raise ValueError(f"crank_com must be in [-{MAX_COM_RATIO:g}, {MAX_COM_RATIO:g}] x crank_radius = "
                             f"[{-MAX_COM_RATIO * r:g}, {MAX_COM_RATIO * r:g}] m, got {com!r}{slip}")
        plausible("rod_mass", self.rod_mass, *MASS_RANGE, "kg")
        if self.rod_inertia is not None:
            chk.positive("rod_inertia", self.rod_inertia, "kg m^2")
        E = chk.positive("rod_youngs_modulus", self.rod_youngs_modulus, "Pa")
        if not MODULUS_RANGE[0] <= E <= MODULUS_RANGE[1]:
            slip = next((f": a value in {u}? {E:g} {u} is {E * f:g} Pa" for u, f in (("GPa", 1e9), ("MPa", 1e6))
                         if MODULUS_RANGE[0] <= E * f <= MODULUS_RANGE[1]), "") if E < MODULUS_RANGE[0] else ""
            raise ValueError(f"rod_youngs_modulus must be in [{MODULUS_RANGE[0]:g}, {MODULUS_RANGE[1]:g}] Pa, got "
                             f"{E!r}{slip}")
        I = chk.positive("rod_area_moment", self.rod_area_moment, "m^4")
        if not AREA_MOMENT_RANGE[0] <= I <= AREA_MOMENT_RANGE[1]:
            slips = [f"{I:g} {u} is {I * f:g} m^4" for u, f in (("mm^4", 1e-12), ("cm^4", 1e-8))
                     if AREA_MOMENT_RANGE[0] <= I * f <= AREA_MOMENT_RANGE[1]]
            raise ValueError(f"rod_area_moment must be in [{AREA_MOMENT_RANGE[0]:g}, {AREA_MOMENT_RANGE[1]:g}] m^4, "
                             f"got {I!r}" + (f": a value in other units? {'; '.join(slips)}" if slips else ""))
        zeta = chk.finite("rod_damping_ratio", self.rod_damping_ratio)
        if not 0.0 <= zeta < 1.0:
            raise ValueError(f"rod_damping_ratio must be in [0, 1), got {zeta!r}")
        plausible("slider_mass", self.slider_mass, *MASS_RANGE, "kg")
        g = chk.nonnegative("gravity", self.gravity, "m/s^2")
        if g > MAX_GRAVITY:
            slip = f": a value in mm/s^2? {g:g} mm/s^2 is {g / 1000:g} m/s^2" if g / 1000 <= MAX_GRAVITY else ""
            raise ValueError(f"gravity must be in [0, {MAX_GRAVITY:g}] m/s^2, got {g!r}{slip}")
        for name in ("crank_pin", "wrist_pin"):
            if not isinstance(getattr(self, name), Bearing):
                raise ValueError(f"{name} must be a Bearing, got {type(getattr(self, name)).__name__}")
        if not isinstance(self.process_force, ProcessForce):
            raise ValueError("process_force must be a ProcessForce")
        if not isinstance(self.counterbalance, Counterbalance):
            raise ValueError("counterbalance must be a Counterbalance")
        if self.process_force.window:  # symbolic copies (`with_symbols`) bypass this: theirs is resolved
            object.__setattr__(self, "process_force", self.process_force.for_stroke(self.stroke))
        self._suspect_units()
        H, pf = self.stroke, self.process_force
        heights, forces = pf.knots()
        if pf.active:
            for name, h in zip(("h_bottom", "h_top") if not pf.heights else ("heights",) * len(heights), heights):
                if not -H <= h <= 2 * H:
                    slip = f": a value in mm? {h:g} mm is {h / 1000:g} m" if -H <= h / 1000 <= 2 * H else ""
                    raise ValueError(f"process_force.{name} must be in [-stroke, 2 x stroke] = [{-H:g}, {2 * H:g}] m "
                                     f"(a height above bottom dead centre), got {h!r}{slip}")
            if heights[-1] <= 0.0 or heights[0] >= H:
                chk.suspect(f"process_force acts for heights in [{heights[0]:g}, {heights[-1]:g}] m, outside the "
                            f"stroke [0, {H:g}] m: it never acts. Heights are above bottom dead centre, in m")

    def _suspect_units(self) -> None:
        """`PlausibilityWarning` for values inside their ranges that do not fit the rest of the press:
        a rod or crank `MAX_PART_RATIO` x heavier than the slider (grams?), a forming force
        `MAX_FORCE_RATIO` x the slider's weight (mN?)."""
        m = self.slider_mass
        for name in ("rod_mass", "crank_mass"):
            v = getattr(self, name)
            if v > MAX_PART_RATIO * m:
                chk.suspect(f"{name} = {v:g} kg is {v / m:.3g} x slider_mass ({m:g} kg): a value in g? {v:g} g is "
                            f"{v / 1000:g} kg")
        W = m * max(self.gravity, 9.81)
        for name, F in (("process_force.force", self.process_force.peak),
                        ("counterbalance.force", self.counterbalance.force)):
            if F > MAX_FORCE_RATIO * W:
                chk.suspect(f"{name} = {F:g} N is {F / W:.3g} x the slider's weight ({W:.4g} N): a value in mN? "
                            f"{F:g} mN is {F / 1000:g} N")

    @property
    def stroke(self) -> float:
        """Stroke H = 2 r, m."""
        return 2.0 * self.crank_radius

    @property
    def rod_first_bending_frequency(self) -> float:
        """First pinned-pinned bending frequency (pi/l)^2 sqrt(EI/(rho A)), rad/s."""
        ratio = self.rod_youngs_modulus * self.rod_area_moment * self.rod_length / self.rod_mass
        # a carried parameter is a CasADi symbol, whose math.sqrt is a silent NaN
        root = math.sqrt(ratio) if isinstance(ratio, (int, float)) else ratio**0.5
        return (math.pi / self.rod_length) ** 2 * root

    @property
    def rod_inertia_value(self) -> float:
        """Rod moment of inertia about its centre, kg m^2."""
        if self.rod_inertia is not None:
            return self.rod_inertia
        return self.rod_mass * self.rod_length**2 / 12.0

    def replace(self, **changes) -> "PressParams":
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)

    # Parameters by dotted name (sensitivities, sweeps) -------------------------------------------
    def value(self, name: str) -> float:
        """The numeric value of a parameter by dotted name (`NUMERIC_PARAMETERS`); a field left None
        gives the value in use (Hertz stiffness, default damping, smoothing width)."""
        check_parameter(name)
        owner, field_name = self._owner(name)
        v = getattr(owner, field_name)
        if v is None:
            v = getattr(owner, DERIVED[field_name])
        return float(v)

    def with_value(self, name: str, value: float) -> "PressParams":
        """A copy with one parameter, by dotted name (`NUMERIC_PARAMETERS`), set to `value` (its SI
        unit; validated again)."""
        check_parameter(name)
        if "." in name:
            joint, field_name = name.split(".")
            return replace(self, **{joint: replace(getattr(self, joint), **{field_name: value})})
        return replace(self, **{name: value})

    def with_values(self, values: Mapping[str, float]) -> "PressParams":
        """A copy with every parameter of `values` (dotted name to value, SI) set, as `with_value`."""
        press = self
        for name, value in values.items():
            press = press.with_value(name, value)
        return press

    def _owner(self, name: str):
        if "." in name:
            joint, field_name = name.split(".")
            return getattr(self, joint), field_name
        return self, name

    def with_symbols(self, names: tuple[str, ...]) -> tuple["PressParams", list]:
        """A copy whose parameters `names` are CasADi SX symbols (named by the dotted name), for models
        differentiated with respect to them; the copy is not validated and only `build_model` uses it.
        Returns (press, symbols in the order of `names`)."""
        import casadi as ca

        def clone(obj, changes):
            new = object.__new__(type(obj))
            for f in fields(obj):
                object.__setattr__(new, f.name, changes.get(f.name, getattr(obj, f.name)))
            return new

        syms, top, nested = [], {}, {}
        for name in names:
            check_parameter(name)
            sym = ca.SX.sym(name)
            syms.append(sym)
            if "." in name:
                joint, field_name = name.split(".")
                nested.setdefault(joint, {})[field_name] = sym
            else:
                top[name] = sym
        for joint, changes in nested.items():
            top[joint] = clone(getattr(self, joint), changes)
        return clone(self, top), syms

    def to_dict(self) -> dict:
        """Plain-data form (JSON/TOML-safe), the `NESTED` parts as nested dicts (a curve's points as
        lists, left out without a curve)."""
        d = asdict(self)
        pf = d["process_force"]
        pf.update(heights=list(pf["heights"]), forces=list(pf["forces"]))
        if not pf["heights"]:
            del pf["heights"], pf["forces"]
        if pf["window"]:
            pf.update(window=list(pf["window"]))
            del pf["h_top"], pf["h_bottom"]  # the window gives them
        else:
            del pf["window"]
        return d

    @classmethod
    def from_dict(cls, data: dict) -> "PressParams":
        """Inverse of `to_dict`; missing keys take their defaults, unknown keys are an error."""
        nested = NESTED
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(data) - known)
        if unknown:
            raise ValueError(f"unknown press field(s) {unknown}; known: {sorted(known)}")
        d = dict(data)
        for key, kind in nested.items():
            if isinstance(d.get(key), dict):
                sub = d[key]
                bad = sorted(set(sub) - {f.name for f in fields(kind)})
                if bad:
                    raise ValueError(f"unknown {key} field(s) {bad}; known: {sorted(f.name for f in fields(kind))}")
                try:
                    d[key] = replace(getattr(cls(), key), **sub)  # missing keys: that joint's defaults
                except ValueError as err:
                    raise ValueError(f"{key}.{err}") from None
        return cls(**d)

    @classmethod
    def flores(cls, clearance: float = 5e-4) -> "PressParams":
        """The slider-crank of Flores & Ambrosio (Comput. Struct. 82, 2004), gravity neglected.

        Crank 0.05 m, 0.30 kg, 1.0e-4 kg m^2 about its centre of mass (taken at mid-crank);
        rod 0.12 m, 0.21 kg, 2.5e-4 kg m^2; slider 0.14 kg; journal radius 10 mm; the given
        clearance at both joints (the paper puts it at the wrist pin only). Run at 5000 rpm.
        """
        bearing = dict(clearance=clearance, journal_radius=0.01)
        return cls(
            crank_radius=0.05,
            rod_length=0.12,
            crank_mass=0.30,
            crank_com=0.025,
            crank_inertia=1.0e-4 + 0.30 * 0.025**2,
            rod_mass=0.21,
            rod_inertia=2.5e-4,
            slider_mass=0.14,
            gravity=0.0,
            crank_pin=Bearing(**bearing),
            wrist_pin=Bearing(**bearing),
        )

    @classmethod
    def simeon(cls) -> "PressParams":
        """Simeon's flexible slider crank (IVP test set "crank"): l1 0.15 m, l2 0.30 m, 8 x 8 mm steel rod
        (E = 2.0e11 Pa), slider 0.075552 kg, no gravity, undamped rod. Run at 150 rad/s from theta = pi."""
        return cls(
            crank_radius=0.15, rod_length=0.30, crank_inertia=0.002727, crank_mass=0.36, rod_mass=0.151104,
            slider_mass=0.075552, gravity=0.0, rod_youngs_modulus=2.0e11, rod_area_moment=0.008**4 / 12,
            rod_damping_ratio=0.0,
        )



#: Parameters a model can be differentiated with respect to, by dotted name.
NUMERIC_PARAMETERS = (
    "crank_radius", "rod_length", "crank_inertia", "crank_mass", "crank_com", "rod_mass", "rod_inertia",
    "slider_mass", "gravity",
    *(f"{j}.{f}" for j in ("crank_pin", "wrist_pin")
      for f in ("clearance", "journal_radius", "stiffness", "damping", "tangential_damping")),
    "counterbalance.force", "counterbalance.gas_length",
)

#: The press's parts that are dataclasses of their own, by field name.
NESTED = {"crank_pin": Bearing, "wrist_pin": Bearing, "process_force": ProcessForce, "counterbalance": Counterbalance}


def check_parameter(name: str) -> str:
    """Raise ValueError unless `name` is in `NUMERIC_PARAMETERS` (naming the nearest one)."""
    if name not in NUMERIC_PARAMETERS:
        import difflib

        near = difflib.get_close_matches(str(name), NUMERIC_PARAMETERS, n=1)
        hint = f" (did you mean {near[0]!r}?)" if near else ""
        raise ValueError(f"parameter {name!r} is not a numeric press parameter{hint}; valid: "
                         f"{', '.join(NUMERIC_PARAMETERS)}")
    return name
