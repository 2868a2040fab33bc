"""The knuckle-joint (toggle) press: a crank-rocker four-bar drives the knee of a toggle.

A crank on the input axis drives, through a connecting rod, the knee joint of two links: the upper
link turns about a fixed pivot on the slide line above the ram, the lower link carries the slide.
Near bottom dead centre the two links straighten, and the ram creeps to a standstill under a large
mechanical advantage (coining, embossing, sizing).

On the slider-crank: the upper link is the slider-crank's crank (its length the press's
``crank_radius``, its pivot the press frame's origin, its mass, centre of mass and inertia the
press's ``crank_*``), the lower link is the rod (``rod_length``, its mass and rod model, rigid or
flexible), the knee is the crank pin and the slide joint the wrist pin: both may have clearance.
The upper link is also the crank-rocker's output link (`pressocp.mechanism.six_bar.fourbar` with
``arm_phase`` 0), and it rocks between the four-bar's two extremes: crank and connecting rod folded
(top dead centre) and stretched (bottom dead centre, the toggle straight: psi = pi). The input crank
and the connecting rod add their energies as the six-bar's input crank and coupler do.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar

import numpy as np

from .. import checks as chk
from .. import rigid
from ..params import PressParams
from .six_bar import SixBar, press_crank_function


def clock(x: float, y: float) -> float:
    """Clock angle of the vector (x, y): from +y, clockwise positive, rad."""
    return math.atan2(x, y)


@dataclass(frozen=True)
class KnucklePress:
    """Dimensions of a knuckle-joint press (lengths in m, angles in rad).

    Attributes
    ----------
    input_crank : float
        Crank radius on the input axis, m: the shortest link of the crank-rocker.
    coupler : float
        Connecting rod from the crank pin to the knee, m.
    upper_link : float
        Fixed pivot to knee, m (the press's ``crank_radius``).
    lower_link : float
        Knee to slide, m (the press's ``rod_length``: at least 1.5 x upper_link).
    drive_angle : float
        Clock angle (from +y, clockwise positive) of the line from the knee at bottom dead centre
        to the input axis, rad: pi / 2 puts the input axis level with the straight knee, to +x.
    """

    input_crank: float = 0.04
    coupler: float = 0.45
    upper_link: float = 0.16
    lower_link: float = 0.25
    drive_angle: float = math.pi / 2
    arm_phase: ClassVar[float] = 0.0  # the upper link is the four-bar's output link

    def __post_init__(self) -> None:
        for name in ("input_crank", "coupler", "upper_link", "lower_link"):
            chk.positive(name, getattr(self, name), "m")
        chk.finite("drive_angle", self.drive_angle)
        links = {"coupler": self.coupler, "upper_link": self.upper_link, "ground (pivot to input axis)": self.ground_length}
        longest = max(links, key=links.get)
        room = sum(links.values()) - 2 * links[longest]  # Grashof: shortest + longest < the other two
        if not 0 < self.input_crank < min(min(links.values()), room):
            raise ValueError(f"input_crank must be in (0, {max(0.0, min(min(links.values()), room)):g}) m for the "
                             f"crank to turn full circle (the shortest link, and with the longest, {longest} = "
                             f"{links[longest]:g} m, shorter than the other two), got {self.input_crank!r}")

    # Geometry in the press frame (x across, y up the slide line; the fixed pivot at the origin) -----
    @property
    def crank_radius(self) -> float:
        """The upper link, m (the slider-crank part's crank)."""
        return self.upper_link

    @property
    def rod_length(self) -> float:
        """The lower link, m (the slider-crank part's rod)."""
        return self.lower_link

    @property
    def output_link(self) -> float:
        """The four-bar's output link: the upper link, m."""
        return self.upper_link

    @cached_property
    def input_axis(self) -> np.ndarray:
        """(x, y) of the input axis, m: coupler + input_crank from the straight knee along drive_angle."""
        reach = self.coupler + self.input_crank
        return np.array([reach * math.sin(self.drive_angle), -self.upper_link + reach * math.cos(self.drive_angle)])

    @property
    def ground_length(self) -> float:
        """Fixed pivot to input axis, m."""
        return float(np.hypot(*self.input_axis))

    @property
    def ground_angle(self) -> float:
        """Clock angle of the line from the input axis to the fixed pivot, rad."""
        return clock(*(-self.input_axis))

    @cached_property
    def top_dead_centre_angle(self) -> float:
        """The upper link's clock angle psi at top dead centre (crank and coupler folded), rad: of
        the two knee positions coupler - input_crank from the input axis, the one on the straight
        knee's side of the line from the pivot to the input axis."""
        o, a, d = self.input_axis, self.upper_link, self.coupler - self.input_crank
        g = self.ground_length
        along = (a * a + g * g - d * d) / (2 * g)  # the knee's distance along the pivot-to-axis line
        across = math.sqrt(max(a * a - along * along, 0.0))
        u = o / g
        n = np.array([-u[1], u[0]])
        side = math.copysign(1.0, float(np.dot(np.array([0.0, -a]), n)))
        return clock(*(along * u + side * across * n)) % (2 * math.pi)

    def crank_clock_angle(self, knee: np.ndarray, folded: bool) -> float:
        """The input crank's clock angle (rad) with the knee at `knee` (x, y) and the crank and
        coupler folded or stretched."""
        to_knee = knee - self.input_axis
        return clock(*(-to_knee if folded else to_knee))

    @cached_property
    def input_at_top_dead_centre(self) -> float:
        """The input crank's clock angle at top dead centre, rad (the input angle theta is measured from it)."""
        psi = self.top_dead_centre_angle
        return self.crank_clock_angle(self.upper_link * np.array([math.sin(psi), math.cos(psi)]), folded=True)

    @property
    def input_at_bottom_dead_centre(self) -> float:
        """The input angle theta at bottom dead centre, rad in (0, 2 pi): the downstroke's share of a
        turn of the crank (clockwise) times 2 pi."""
        straight = self.crank_clock_angle(np.array([0.0, -self.upper_link]), folded=False)
        return (straight - self.input_at_top_dead_centre) % (2 * math.pi)

    @cached_property
    def assembly(self) -> int:
        """The four-bar's branch (`pressocp.mechanism.six_bar.fourbar`): the sign that puts the knee
        straight below the pivot at bottom dead centre."""
        theta = self.input_at_top_dead_centre + self.input_at_bottom_dead_centre
        pin = self.input_axis + self.input_crank * np.array([math.sin(theta), math.cos(theta)])
        d = float(np.hypot(*pin))
        turn = math.acos(min(1.0, (self.upper_link**2 + d * d - self.coupler**2) / (2 * self.upper_link * d)))
        miss = [abs(math.remainder(clock(*pin) + s * turn - math.pi, 2 * math.pi)) for s in (1, -1)]
        return 1 if miss[0] <= miss[1] else -1

    @property
    def stroke(self) -> float:
        """Ram travel, m: the slider-crank's height at the top dead centre angle."""
        psi, a, b = self.top_dead_centre_angle, self.upper_link, self.lower_link
        return float(a * math.cos(psi) - math.sqrt(b * b - (a * math.sin(psi)) ** 2) + a + b)


@dataclass(frozen=True)
class KnuckleJoint(SixBar):
    """The knuckle-joint press (`pressocp.mechanism.Mechanism`): the six-bar's model with a
    crank-rocker toggle drive (`KnucklePress`); the press's crank_radius and rod_length must be
    its upper and lower link. `input_inertia`, `coupler_mass` and `coupler_inertia` are the input
    crank's and the connecting rod's, as in `SixBar`."""

    drive: KnucklePress = field(default_factory=KnucklePress)
    name: ClassVar[str] = "knuckle_joint"
    geometry: ClassVar[type] = KnucklePress

    def stroke(self, params: PressParams) -> float:
        """The toggle's ram travel, m (less than 2 x upper link)."""
        return self.drive.stroke

    def bottom_dead_centre(self, params: PressParams) -> float:
        """The input angle with the toggle straight, rad."""
        return self.drive.input_at_bottom_dead_centre

    def input_angle_at_height(self, params: PressParams, height, stroke: str = "down") -> np.ndarray:
        """Input angle (rad) with the ram at `height` (m, in [0, stroke]) on the "down" ([0, BDC]) or
        "up" ([BDC, 2 pi]) stroke: the upper link's angle from the slider-crank's closed form, then
        the input angle by bisection on the upper link's distance from the straight toggle (it
        shrinks to 0 on the downstroke and grows on the upstroke), to round-off. The dead centres
        themselves are returned exactly: the ram height is flat there (of fourth order in theta at
        bottom dead centre), so round-off would move them by up to 1e-3 rad."""
        chk.choice("stroke", stroke, ("down", "up"))
        h = chk.finite_array("height", height, ndim=None)
        H = self.drive.stroke
        if np.any(h < -1e-12) or np.any(h > H + 1e-12):
            raise ValueError(f"height must be in [0, {H:g}] m (the stroke)")
        target = math.pi - rigid.crank_angle_at_height(params, np.clip(h, 0.0, H), "down")
        f = press_crank_function(self.drive)
        lo = np.full(h.shape, 0.0 if stroke == "down" else self.drive.input_at_bottom_dead_centre)
        hi = np.full(h.shape, self.drive.input_at_bottom_dead_centre if stroke == "down" else 2 * math.pi)
        for _ in range(56):
            mid = 0.5 * (lo + hi)
            bent = np.abs(np.angle(np.exp(1j * (rigid.evaluate_elementwise(f, mid)["psi"] - math.pi))))
            above = bent > target
            lo, hi = (np.where(above, mid, lo), np.where(above, hi, mid)) if stroke == "down" else \
                (np.where(above, lo, mid), np.where(above, mid, hi))
        theta = 0.5 * (lo + hi)
        theta = np.where(h <= 0.0, self.drive.input_at_bottom_dead_centre, theta)
        return np.where(h >= H, 0.0 if stroke == "down" else 2 * math.pi, theta)
