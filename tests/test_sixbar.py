"""The six-bar drag-link press's geometry (`pressocp.mechanism.SixBarPress`) and the numpy reference
kinematics (`tests/references/sixbar.py`) that the CasADi six-bar is tested against.

The checks are independent of the implementation's own formulas: loop closure
from joint positions, analytic derivatives against centred finite differences,
dead-centre and stroke-range properties, a full output revolution per input
revolution, and the working-zone speed recomputed from a sampled stroke.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pressocp import PressParams
from pressocp.mechanism import SixBar, SixBarPress, constant_speed_zone
from tests.references.sixbar import (
    sixbar_kinematics,
    sixbar_positions,
    sixbar_stroke,
    working_zone_interval,
    working_zone_speed,
)

TWO_PI = 2.0 * math.pi
DEFAULT = SixBarPress()
# A few other valid drag-links (both assembly branches, other ground directions).
OTHERS = [
    SixBarPress(),
    SixBarPress(ground_length=0.03, ground_angle=0.4, input_crank=0.12, coupler=0.11, output_link=0.09,
                arm_phase=2.0, assembly=-1),
    SixBarPress(ground_length=0.05, ground_angle=-1.2, input_crank=0.09, coupler=0.16, output_link=0.13,
                arm_phase=-0.7, assembly=1),
    SixBarPress(ground_length=0.02, ground_angle=math.pi / 2, input_crank=0.2, coupler=0.21, output_link=0.05,
                arm_phase=4.0, assembly=-1, crank_radius=0.03, rod_length=0.2),
]


def _dist(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    return np.hypot(*(p - q).T)


@pytest.mark.parametrize("press", OTHERS)
def test_loop_closure(press: SixBarPress) -> None:
    th = np.linspace(-7.0, 7.0, 1001)
    pos = sixbar_positions(press, th)
    r, l = press.crank_radius, press.rod_length
    assert np.allclose(pos["O4"], 0.0, atol=0.0)
    assert np.allclose(_dist(pos["O2"], pos["O4"]), press.ground_length, rtol=0, atol=1e-12)
    assert np.allclose(_dist(pos["A"], pos["O2"]), press.input_crank, rtol=0, atol=1e-12)
    assert np.allclose(_dist(pos["B"], pos["A"]), press.coupler, rtol=0, atol=1e-12)
    assert np.allclose(_dist(pos["B"], pos["O4"]), press.output_link, rtol=0, atol=1e-12)
    assert np.allclose(_dist(pos["C"], pos["O4"]), r, rtol=0, atol=1e-12)
    assert np.allclose(_dist(pos["D"], pos["C"]), l, rtol=0, atol=1e-12)
    # Ram on the slide line through the output axis, below the axis.
    assert np.all(pos["D"][:, 0] == 0.0)
    assert np.all(pos["D"][:, 1] < 0.0)
    # Ground direction: clock angle (from +y, clockwise) of O2 -> O4.
    gvec = pos["O4"][0] - pos["O2"][0]
    assert math.atan2(gvec[0], gvec[1]) == pytest.approx(math.remainder(press.ground_angle, TWO_PI), abs=1e-12)
    # Arm sits at arm_phase (clockwise) from the output link.
    ang_b = np.arctan2(pos["B"][:, 0], pos["B"][:, 1])
    ang_c = np.arctan2(pos["C"][:, 0], pos["C"][:, 1])
    diff = np.mod(ang_c - ang_b - press.arm_phase + math.pi, TWO_PI) - math.pi
    assert np.allclose(diff, 0.0, atol=1e-12)
    # Ram height from the joint position: h = y_D - y_BDC with y_BDC = -(r + l).
    k = sixbar_kinematics(press, th)
    assert np.allclose(k["ram_height"], pos["D"][:, 1] + r + l, rtol=0, atol=1e-13)


@pytest.mark.parametrize("press", OTHERS)
def test_psi_matches_joint_positions(press: SixBarPress) -> None:
    """psi is the clock angle of the press-crank pin, and h follows the slider-crank formula."""
    th = np.linspace(0.0, TWO_PI, 721)
    k = sixbar_kinematics(press, th)
    c = sixbar_positions(press, th)["C"]
    ang = np.arctan2(c[:, 0], c[:, 1])
    assert np.allclose(np.mod(k["psi"] - ang + math.pi, TWO_PI) - math.pi, 0.0, atol=1e-12)
    r, l, psi = press.crank_radius, press.rod_length, k["psi"]
    h_ref = r * np.cos(psi) - np.sqrt(l**2 - r**2 * np.sin(psi) ** 2) + r + l
    assert np.allclose(k["ram_height"], h_ref, rtol=0, atol=1e-14)


@pytest.mark.parametrize("press", OTHERS)
def test_derivatives_against_finite_differences(press: SixBarPress) -> None:
    th = np.linspace(-1.0, TWO_PI + 1.0, 397)
    eps = 1e-5
    k = sixbar_kinematics(press, th)
    kp = sixbar_kinematics(press, th + eps)
    km = sixbar_kinematics(press, th - eps)

    def fd(key: str) -> np.ndarray:
        return (kp[key] - km[key]) / (2.0 * eps)

    scale_psi = np.max(np.abs(k["dpsi_dtheta"]))
    scale_h = np.max(np.abs(k["dh_dtheta"]))
    assert np.allclose(k["dpsi_dtheta"], fd("psi"), rtol=0, atol=1e-8 * scale_psi)
    assert np.allclose(k["dh_dtheta"], fd("ram_height"), rtol=0, atol=1e-8 * scale_h)
    # Second derivatives against differences of the (already verified) first derivatives.
    scale_psi2 = np.max(np.abs(k["d2psi_dtheta2"]))
    scale_h2 = np.max(np.abs(k["d2h_dtheta2"]))
    assert np.allclose(k["d2psi_dtheta2"], fd("dpsi_dtheta"), rtol=0, atol=1e-7 * scale_psi2)
    assert np.allclose(k["d2h_dtheta2"], fd("dh_dtheta"), rtol=0, atol=1e-7 * scale_h2)


@pytest.mark.parametrize("press", OTHERS)
def test_tdc_at_zero_input_angle(press: SixBarPress) -> None:
    k = sixbar_kinematics(press, np.array([0.0, TWO_PI, -TWO_PI]))
    assert np.allclose(k["ram_height"], press.stroke, rtol=0, atol=1e-12)
    assert k["psi"][0] == pytest.approx(0.0, abs=1e-12)
    assert np.allclose(k["dh_dtheta"], 0.0, atol=1e-12)
    c = sixbar_positions(press, 0.0)["C"]
    assert np.allclose(c, [0.0, press.crank_radius], atol=1e-12)  # crank pin straight up


@pytest.mark.parametrize("press", OTHERS)
def test_height_range_is_zero_to_stroke(press: SixBarPress) -> None:
    th = np.linspace(0.0, TWO_PI, 20001)
    k = sixbar_kinematics(press, th)
    h = k["ram_height"]
    assert h.max() == pytest.approx(press.stroke, abs=1e-12)
    assert h.min() >= -1e-15
    assert h.max() <= press.stroke + 1e-15
    # Exactly one downstroke then one upstroke: dh/dtheta changes sign once inside (0, 2 pi).
    i = int(np.argmin(h))
    assert np.all(k["dh_dtheta"][1:i] < 0.0) and np.all(k["dh_dtheta"][i + 1 : -1] > 0.0)
    # Bottom dead centre: root of dh/dtheta, where h = 0.
    def f(x: float) -> float:
        return float(sixbar_kinematics(press, x)["dh_dtheta"])

    th_bdc = brentq(f, th[i - 1], th[i + 1], xtol=1e-15)
    assert float(sixbar_kinematics(press, th_bdc)["ram_height"]) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("press", OTHERS)
def test_output_turns_once_per_input_revolution(press: SixBarPress) -> None:
    th = np.linspace(0.0, TWO_PI, 4001)
    k = sixbar_kinematics(press, th)
    psi = k["psi"]
    assert psi[-1] - psi[0] == pytest.approx(TWO_PI, abs=1e-12)
    assert np.all(np.diff(psi) > 0.0)  # monotonic: the output crank fully rotates, never reverses
    assert np.all(k["dpsi_dtheta"] > 0.0)
    # Independent count from the output-link joint B: its angle unwraps through exactly one turn.
    b = sixbar_positions(press, th)["B"]
    ang = np.unwrap(np.arctan2(b[:, 0], b[:, 1]))
    assert ang[-1] - ang[0] == pytest.approx(TWO_PI, abs=1e-9)
    # Periodicity and unwrapping for arbitrary (unsorted, multi-turn) inputs.
    x = np.array([[5.1, -3.3], [0.2, 17.0]])
    k1, k2 = sixbar_kinematics(press, x), sixbar_kinematics(press, x + TWO_PI)
    assert k1["psi"].shape == x.shape
    assert np.allclose(k2["psi"] - k1["psi"], TWO_PI, atol=1e-12)
    k3 = sixbar_kinematics(press, x - 3 * TWO_PI)
    assert np.allclose(k1["psi"] - k3["psi"], 3 * TWO_PI, atol=1e-11)
    for key in ("ram_height", "dh_dtheta", "d2h_dtheta2", "dpsi_dtheta"):
        assert np.allclose(k1[key], k2[key], rtol=0, atol=1e-12)


def test_ground_rotation_equivalent_to_arm_phase() -> None:
    """Rotating the four-bar by delta and the arm phase by -delta leaves h(theta) unchanged."""
    delta = 0.8
    p = DEFAULT
    q = SixBarPress(ground_length=p.ground_length, ground_angle=p.ground_angle + delta, input_crank=p.input_crank,
                    coupler=p.coupler, output_link=p.output_link, arm_phase=p.arm_phase - delta,
                    assembly=p.assembly)
    th = np.linspace(0.0, TWO_PI, 181)
    kp, kq = sixbar_kinematics(p, th), sixbar_kinematics(q, th)
    for key in ("psi", "ram_height", "dh_dtheta", "d2h_dtheta2"):
        assert np.allclose(kp[key], kq[key], rtol=0, atol=1e-11)


def test_stroke_sampling() -> None:
    period = 0.8
    t, h, v = sixbar_stroke(DEFAULT, period, n=4001)
    assert t[0] == 0.0 and t[-1] == period and t.shape == h.shape == v.shape == (4001,)
    assert h[0] == pytest.approx(DEFAULT.stroke, abs=1e-12) and h[-1] == pytest.approx(DEFAULT.stroke, abs=1e-12)
    # Velocity is dh/dt: compare with a finite-difference derivative of the sampled heights.
    dt = t[1] - t[0]
    v_fd = (h[2:] - h[:-2]) / (2 * dt)
    assert np.allclose(v[1:-1], v_fd, rtol=0, atol=1e-4 * np.abs(v).max())
    # Downstroke first: velocity negative just after TDC.
    assert v[1] < 0.0


def _zone_from_samples(press: SixBarPress, period: float, hi: float, lo: float) -> tuple[float, float, float, float]:
    """Zone crossing times, mean speed and max deviation from a densely sampled stroke (no zone helpers)."""
    t, h, v = sixbar_stroke(press, period, n=200001)
    H = press.stroke
    i_bdc = int(np.argmin(h))
    td, hd = t[: i_bdc + 1], h[: i_bdc + 1]  # downstroke, h decreasing
    t1 = float(np.interp(hi * H, hd[::-1], td[::-1]))
    t2 = float(np.interp(lo * H, hd[::-1], td[::-1]))
    mean = (hi - lo) * H / (t2 - t1)
    inside = (t >= t1) & (t <= t2)
    dev = float(np.max(np.abs(-v[inside] - mean)) / mean)
    return t1, t2, mean, dev


def test_working_zone_speed_nearly_constant() -> None:
    period = 1.0
    mean, dev = working_zone_speed(DEFAULT, period)
    assert mean > 0.0
    assert dev <= 0.05  # requirement: within ±5 %
    assert dev <= 0.03  # design target: within ±3 %
    t1, t2, mean_ref, dev_ref = _zone_from_samples(DEFAULT, period, 0.35, 0.1)
    assert mean == pytest.approx(mean_ref, rel=1e-6)
    assert dev == pytest.approx(dev_ref, abs=2e-4)
    assert working_zone_interval(DEFAULT, period) == pytest.approx((t1, t2), abs=1e-8)
    # Zone order is irrelevant; speed scales with 1 / period.
    assert working_zone_speed(DEFAULT, period, zone=(0.1, 0.35))[0] == pytest.approx(mean, rel=1e-12)
    assert working_zone_speed(DEFAULT, 2 * period)[0] == pytest.approx(mean / 2, rel=1e-12)


def test_working_zone_slower_than_crank_press() -> None:
    """The zone is much slower than in a plain crank press (psi = theta) with the same stroke and period."""
    r, l = DEFAULT.crank_radius, DEFAULT.rod_length
    H = DEFAULT.stroke
    psi = np.linspace(0.0, math.pi, 200001)
    h = r * np.cos(psi) - np.sqrt(l**2 - r**2 * np.sin(psi) ** 2) + r + l
    p1, p2 = np.interp([0.35 * H, 0.1 * H], h[::-1], psi[::-1])
    v_crank = 0.25 * H / ((p2 - p1) / TWO_PI)  # at period 1 s
    mean, _ = working_zone_speed(DEFAULT, 1.0)
    assert mean / v_crank < 0.5
    t1, t2 = working_zone_interval(DEFAULT, 1.0)
    assert 0.0 < t1 < t2 < 1.0 and t2 - t1 > 0.18  # share of the cycle spent in the zone


def test_default_transmission_angle_within_limits() -> None:
    k = sixbar_kinematics(DEFAULT, np.linspace(0.0, TWO_PI, 20001))
    mu = np.degrees(k["transmission_angle"])
    assert mu.min() >= 30.0 and mu.max() <= 150.0
    # Independent: angle at joint B between coupler and output link from the joint positions.
    pos = sixbar_positions(DEFAULT, np.linspace(0.0, TWO_PI, 721))
    u, w = pos["A"] - pos["B"], pos["O4"] - pos["B"]
    cosmu = np.sum(u * w, axis=1) / (np.hypot(*u.T) * np.hypot(*w.T))
    k2 = sixbar_kinematics(DEFAULT, np.linspace(0.0, TWO_PI, 721))
    assert np.allclose(np.arccos(cosmu), k2["transmission_angle"], atol=1e-9)


def test_default_dimensions_practical() -> None:
    p = DEFAULT
    assert 0.02 <= p.ground_length <= 0.2
    for name in ("input_crank", "coupler", "output_link"):
        assert 0.0 < getattr(p, name) < 0.5
    assert p.crank_radius == 0.05 and p.rod_length == 0.25 and p.stroke == pytest.approx(0.1)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"ground_length": -0.01}, "ground_length"),
        ({"input_crank": 0.0}, "input_crank"),
        ({"coupler": float("nan")}, "coupler"),
        ({"output_link": float("inf")}, "output_link"),
        ({"crank_radius": -0.05}, "crank_radius"),
        ({"rod_length": 0.0}, "rod_length"),
        ({"rod_length": 0.04}, "rod_length"),  # rod shorter than crank
        ({"ground_length": 0.1}, "ground_length"),  # ground not the shortest link
        ({"ground_length": 0.0861}, "ground_length"),  # longer than output link 0.086
        ({"coupler": 0.23}, "ground_length"),  # violates g + l < p + q
        ({"coupler": 0.5}, "coupler"),  # longest link longer than sum of the other two
        ({"arm_phase": float("nan")}, "arm_phase"),
        ({"ground_angle": float("inf")}, "ground_angle"),
        ({"assembly": 0}, "assembly"),
        ({"assembly": True}, "assembly"),
    ],
)
def test_invalid_dimensions_raise(kwargs: dict, field: str) -> None:
    with pytest.raises(ValueError, match=field):
        SixBarPress(**kwargs)


def test_grashof_message_gives_range() -> None:
    with pytest.raises(ValueError, match=r"ground_length must be in \(0, 0.0216\) m"):
        SixBarPress(coupler=0.23)
    # Change-point (s + l = p + q) is rejected as singular; just inside is accepted.
    g, a, c = 0.05, 0.1656, 0.086
    with pytest.raises(ValueError):
        SixBarPress(ground_length=g, input_crank=a, coupler=a + c - g, output_link=c)
    SixBarPress(ground_length=g, input_crank=a, coupler=a + c - g - 1e-4, output_link=c)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: sixbar_stroke(DEFAULT, 0.0), "period"),
        (lambda: sixbar_stroke(DEFAULT, 1.0, n=1), "n"),
        (lambda: constant_speed_zone(PressParams(), SixBar(), 1.0, zone=(0.35, 1.2)), r"zone\[1\]"),
        (lambda: constant_speed_zone(PressParams(), SixBar(), 1.0, zone=(0.2, 0.2)), "zone"),
        (lambda: constant_speed_zone(PressParams(), SixBar(), -1.0), "period"),
        (lambda: constant_speed_zone(PressParams(), SixBar(), 1.0, n=1), "n"),
    ],
)
def test_invalid_call_arguments(call, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        call()
