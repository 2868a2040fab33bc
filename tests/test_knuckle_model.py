"""The knuckle-joint press (`pressocp.KnuckleJoint`) through the same public calls as the four-bar.

Reference: the toggle's positions written here from its description alone, in numpy: the input
axis at coupler + input_crank from the straight knee along drive_angle, the knee where the circles
about the crank pin (coupler) and the fixed pivot (upper link) cross, followed continuously from
the straight knee; top dead centre where that ram height is greatest (a root of its slope, not
the package's folded-crank closed form); the motor torque from the bodies' energy, tau = dE/dtheta at
constant input speed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pressocp import (FourierSpeed, KnuckleJoint, KnucklePress, ModelSpec, PressParams, Rigid, SpeedProblem, Strategy,
                      build_model, design_speed, optimize_speed, simulate)
from pressocp.mechanism import MECHANISMS, constant_speed_zone, mechanism_from_dict, mechanism_to_dict
from tests.references.power_balance import assert_torque_is_power_balance

OTHER = KnucklePress(input_crank=0.03, coupler=0.38, upper_link=0.12, lower_link=0.2, drive_angle=1.2)


def press_for(drive: KnucklePress, **changes) -> PressParams:
    return PressParams(crank_radius=drive.upper_link, rod_length=drive.lower_link, crank_com=0.5 * drive.upper_link,
                       **changes)


def positions(drive: KnucklePress, crank: np.ndarray) -> dict[str, np.ndarray]:
    """Joint positions (x, y) at input-crank clock angles `crank` (rad, any order)."""
    e, c, a, b = drive.input_crank, drive.coupler, drive.upper_link, drive.lower_link
    axis = np.array([0.0, -a]) + (c + e) * np.array([math.sin(drive.drive_angle), math.cos(drive.drive_angle)])
    pin = axis[None, :] + e * np.stack([np.sin(crank), np.cos(crank)], -1)
    d = np.linalg.norm(pin, axis=-1)
    along = (a * a + d * d - c * c) / (2 * d)
    across = np.sqrt(np.maximum(a * a - along**2, 0.0))
    u = pin / d[:, None]
    n = np.stack([-u[:, 1], u[:, 0]], -1)
    knees = [along[:, None] * u + s * across[:, None] * n for s in (1.0, -1.0)]
    straight = np.argmin([np.min(np.linalg.norm(k - [0.0, -a], axis=-1)) for k in knees])
    knee = knees[straight]  # the branch that passes the straight knee
    slide = np.stack([np.zeros(len(crank)), knee[:, 1] - np.sqrt(b * b - knee[:, 0] ** 2)], -1)
    return {"axis": axis, "pin": pin, "knee": knee, "slide": slide, "height": slide[:, 1] + a + b}


def top_dead_centre(drive: KnucklePress) -> float:
    """The input-crank clock angle of the greatest ram height: the root of its central-difference
    slope (step 1e-5 rad) next to the greatest of 3601 samples."""
    grid = np.linspace(-math.pi, math.pi, 3601)
    start = grid[np.argmax(positions(drive, grid)["height"])]

    def slope(x):
        return float(np.diff(positions(drive, np.array([x - 1e-5, x + 1e-5]))["height"])[0])

    return brentq(slope, start - 0.01, start + 0.01, xtol=1e-15)


@pytest.mark.parametrize("drive", [KnucklePress(), OTHER], ids=["default", "other"])
def test_knuckle_ram_motion_equals_the_toggle_geometry(drive):
    model = build_model(press_for(drive), clearance=(), mechanism=KnuckleJoint(drive))
    period = 1.5
    speed = FourierSpeed.constant(period, n_harmonics=model.n_harmonics)
    t = np.linspace(0.0, period, 121)
    y = model.ideal_series(speed, t)
    tdc = top_dead_centre(drive)
    ref = positions(drive, tdc + 2 * math.pi * t / period)["height"]
    assert np.allclose(y["ram_height"], ref, rtol=0, atol=1e-10)
    w, dt = 2 * math.pi / period, 1e-6
    v = (positions(drive, tdc + w * (t + dt))["height"] - positions(drive, tdc + w * (t - dt))["height"]) / (2 * dt)
    assert np.allclose(y["ram_velocity"], v, rtol=0, atol=1e-7)
    assert KnuckleJoint(drive).stroke(press_for(drive)) == pytest.approx(np.max(ref), abs=1e-12)
    bdc = KnuckleJoint(drive).bottom_dead_centre(press_for(drive))
    assert positions(drive, np.array([tdc + bdc]))["height"][0] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("drive", [KnucklePress(), OTHER], ids=["default", "other"])
def test_knuckle_motor_torque_is_the_power_balance_of_its_bodies(drive):
    p = press_for(drive)
    mech = KnuckleJoint(drive, input_inertia=0.05, coupler_mass=3.0, coupler_inertia=0.04)
    model = build_model(p, clearance=(), mechanism=mech)
    period = 1.5
    w = 2 * math.pi / period
    tdc = top_dead_centre(drive)

    def energy(theta):
        h = 1e-5
        q_m, q_0, q_p = (positions(drive, tdc + theta + s) for s in (-h, 0.0, h))

        def rate(f):
            return (f(q_p) - f(q_m)) / (2 * h) * w

        def angle(a, b):
            return lambda q: np.arctan2(*(q[b] - (q[a] if a != "pivot" else 0.0)).T)

        def centre(a, b):
            return lambda q: (q[a] + q[b]) / 2

        T = 0.5 * mech.input_inertia * w**2 + 0.5 * p.crank_inertia * rate(angle("pivot", "knee")) ** 2
        knee_dir = q_0["knee"] / drive.upper_link
        V = p.crank_mass * p.gravity * p.crank_com * knee_dir[:, 1]
        for (a, b), m, J in ((("pin", "knee"), mech.coupler_mass, mech.coupler_inertia),
                             (("knee", "slide"), p.rod_mass, p.rod_inertia_value)):
            T = T + 0.5 * m * np.sum(rate(centre(a, b)) ** 2, axis=-1) + 0.5 * J * rate(angle(a, b)) ** 2
            V = V + m * p.gravity * centre(a, b)(q_0)[:, 1]
        T = T + 0.5 * p.slider_mass * np.sum(rate(lambda q: q["slide"]) ** 2, axis=-1)
        return T + V + p.slider_mass * p.gravity * q_0["slide"][:, 1]

    assert_torque_is_power_balance(model, period, energy)


def test_a_knuckle_joint_reads_back_and_is_registered():
    mech = KnuckleJoint(OTHER, input_inertia=0.05)
    assert MECHANISMS["knuckle_joint"] is KnuckleJoint
    assert mechanism_from_dict(mechanism_to_dict(mech)) == mech
    spec = ModelSpec("rigid", ("crank_pin",), mechanism=mech)
    assert ModelSpec.from_dict(spec.to_dict()) == spec
    assert spec.describe().startswith("knuckle-joint press")


def test_a_crank_that_cannot_turn_full_circle_fails_with_its_range():
    with pytest.raises(ValueError, match=r"input_crank must be in \(0, .*\) m for the crank to turn full circle"):
        KnucklePress(input_crank=0.2)
    with pytest.raises(ValueError, match="crank_radius = 0.05 m of the press differs from the knuckle_joint"):
        build_model(PressParams(), mechanism=KnuckleJoint())


def test_input_angles_at_heights_invert_the_ram_height():
    drive = KnucklePress()
    mech, p = KnuckleJoint(drive), press_for(drive)
    H = mech.stroke(p)
    heights = np.linspace(0.0, H, 9)
    tdc = top_dead_centre(drive)
    for stroke in ("down", "up"):
        theta = mech.input_angle_at_height(p, heights, stroke)
        assert np.allclose(positions(drive, tdc + theta)["height"], heights, rtol=0, atol=5e-12)
        bdc = mech.bottom_dead_centre(p)
        assert np.all((theta <= bdc + 1e-12) if stroke == "down" else (theta >= bdc - 1e-12))
    with pytest.raises(ValueError, match=r"height must be in \[0, 0.0351"):
        mech.input_angle_at_height(p, 0.05)


@pytest.mark.slow  # 29 s; the knuckle's kinematics and dynamics by default
def test_the_knuckle_press_is_designed_optimised_and_simulated_like_the_four_bar():
    """design_speed, optimize_speed (ideal joints) and simulate with both clearances, as for the
    slider-crank: the design holds the ram speed in the window by the reference geometry, the
    optimum is verified and below the design's peak torque, and the clearance run impacts."""
    drive = KnucklePress()
    mech = KnuckleJoint(drive, input_inertia=0.05, coupler_mass=3.0)
    problem = SpeedProblem(press_for(drive), period=1.5, ram_speed=-0.02, mechanism=mech)
    d = design_speed(problem)
    assert d.converged
    tw = np.linspace(d.t1, d.t2, 801)
    theta = d.speed.theta(tw)
    tdc, dt = top_dead_centre(drive), 1e-6
    v = (positions(drive, tdc + d.speed.theta(tw + dt))["height"]
         - positions(drive, tdc + d.speed.theta(tw - dt))["height"]) / (2 * dt)
    assert np.max(np.abs(v - problem.ram_speed)) <= 0.5 * problem.tol * (1 + 1e-3)
    assert positions(drive, tdc + theta[[0]])["height"][0] == pytest.approx(problem.window_heights[0], abs=1e-9)

    model = build_model(problem.press, clearance=(), mechanism=mech)
    r = optimize_speed(problem, model, strategy=Strategy(rigid=Rigid(samples=400)), progress=False)
    assert r.success and r.verified
    t = np.linspace(0.0, problem.period, 4001)
    assert r.peak_torque < 0.97 * np.max(np.abs(model.ideal_series(d.speed, t)["torque"]))

    zone = constant_speed_zone(problem.press, mech, problem.period, problem.window)
    assert 0 < zone.t_start < zone.t_end < problem.period
    run = simulate(build_model(problem.press, mechanism=mech), d.speed, cycles=1)
    assert run.peak("crank_pin_force") > 2 * np.max(np.abs(model.ideal_series(d.speed, t)["crank_pin_force"]))
