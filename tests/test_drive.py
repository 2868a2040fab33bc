"""The servo drive (`pressocp.drive`): its figures against a hand calculation on the ideal press, the
power balance of a cycle, the envelope and the refusals of bad data.

References: the crank torque of the Newton-Euler free bodies (`tests/references/newton_euler.py`,
written apart from the package), the gear and the motor written here from their definitions, and
the process force's work from the formula in its docstring, integrated here.
"""

from __future__ import annotations

import math

import warnings

import numpy as np
import pytest

from pressocp import FourierSpeed, PressParams, ProcessForce, SpeedProblem, design_speed
from pressocp.drive import Drive, motor_cycle
from pressocp.mechanism import SLIDER_CRANK
from pressocp.mechanism.ideal import ideal_inverse_dynamics, ideal_response
from tests.references.newton_euler import slider_crank_kinematics
from tests.references.press import newton_euler

DRIVE = Drive(gear_ratio=12.0, peak_torque=25.0, continuous_torque=9.0, max_speed=120.0, power_limit=2000.0,
              gear_efficiency=0.93, motor_inertia=3e-3, gear_inertia=1e-3)


def small_ideal_press(window_samples: int = 50):
    """The default press on ideal joints at 0.8 s, 8 harmonics, -0.1 m/s: its problem, model and a
    quick rigid-stage strategy (300 samples, `window_samples` in the window, no compiling)."""
    from pressocp import Rigid, Strategy, build_model

    press = PressParams()
    return (SpeedProblem(press, period=0.8, ram_speed=-0.1, n_harmonics=8),
            build_model(press, clearance=(), n_harmonics=8),
            Strategy(rigid=Rigid(samples=300, window_samples=window_samples, jit=False)))


def load_inertia(press, theta):
    """Twice the ideal press's kinetic energy at 1 rad/s, kg m^2."""
    return 2 * ideal_inverse_dynamics(press, SLIDER_CRANK, theta, 1.0, 0.0)["kinetic_energy"]


def test_motor_figures_equal_a_hand_calculation_at_constant_speed():
    """RMS torque, energy out and back per stroke, peak torque and speed of the motor behind the
    gear, against the Newton-Euler crank torque on a fine grid (within 0.5 %, as the issue asks;
    they agree to about 1e-6)."""
    press, period = PressParams(), 0.8
    w = 2 * math.pi / period
    t = np.linspace(0.0, period, 2001)
    sim = ideal_response(press, SLIDER_CRANK, FourierSpeed.constant(period), t)
    got = motor_cycle(DRIVE, sim.t, sim.omega, np.zeros_like(t), sim.torque, load_inertia(press, sim.theta))

    theta = np.linspace(0.0, 2 * math.pi, 200_001)
    tau = newton_euler(press, theta, w, 0.0)["torque"]
    i, eta = DRIVE.gear_ratio, DRIVE.gear_efficiency
    motor = np.where(tau >= 0, tau / (i * eta), tau * eta / i)
    power = motor * i * w
    dt = period / (len(theta) - 1)
    rms = math.sqrt(np.mean(motor[:-1] ** 2))
    out, back = np.sum(np.maximum(power[:-1], 0)) * dt, np.sum(np.maximum(-power[:-1], 0)) * dt
    assert got.rms_torque == pytest.approx(rms, rel=5e-3)
    assert got.energy_driving == pytest.approx(out, rel=5e-3)
    assert got.energy_regenerated == pytest.approx(back, rel=5e-3)
    assert got.peak_torque == pytest.approx(np.max(np.abs(motor)), rel=5e-3)
    assert got.max_speed == pytest.approx(i * w, rel=1e-12)
    assert got.rms_margin == pytest.approx(1 - rms / DRIVE.continuous_torque, rel=5e-3)
    envelope = np.minimum(DRIVE.peak_torque, DRIVE.power_limit / (i * w))  # below the top speed
    assert got.peak_torque_margin == pytest.approx(np.min(envelope - np.abs(motor)) / DRIVE.peak_torque, rel=5e-3)
    # the largest reflected inertia: twice the bodies' kinetic energy at 1 rad/s, from the reference's velocities
    k = slider_crank_kinematics(press.crank_radius, press.rod_length, theta, 1.0, 0.0)
    inertia = (press.crank_inertia + press.rod_mass * np.sum(k["vG"] ** 2, -1) + press.rod_inertia_value * k["phid"] ** 2
               + press.slider_mass * np.sum(k["vB"] ** 2, -1))
    assert got.inertia_ratio == pytest.approx(
        (np.max(inertia) / i**2 + DRIVE.gear_inertia) / DRIVE.motor_inertia, rel=1e-5)


@pytest.mark.slow  # 15 s (200 001 samples); motor_cycle by default: the hand calculations
def test_a_cycle_balances_the_motor_work_against_the_process_work_and_the_losses():
    """Over one period of a varying speed with a forming force: the motor's net work equals the
    work done against the process force (the ideal press's energy returns to its start) plus the
    gear's losses, to 1e-6 of the motor work; the rotor's own kinetic energy nets to zero."""
    press = PressParams(process_force=ProcessForce(force=3000.0, h_top=0.03, h_bottom=0.005))
    problem = SpeedProblem(press, period=0.8, ram_speed=-0.1)
    speed = design_speed(problem).speed
    t = np.linspace(0.0, problem.period, 200_001)
    sim = ideal_response(press, SLIDER_CRANK, speed, t)
    _, omega, alpha = speed.evaluate(t)
    got = motor_cycle(DRIVE, t, omega, alpha, sim.torque, load_inertia(press, sim.theta))

    pf = press.process_force

    def s(x):
        return 0.5 * (1 + np.tanh(x))

    h, v = sim.ram_height, sim.ram_velocity
    force = pf.force * s((h - pf.h_bottom) / pf.edge) * s((pf.h_top - h) / pf.edge) * s(-v / pf.speed_edge)
    against_process = -np.sum(0.5 * ((force * v)[1:] + (force * v)[:-1]) * np.diff(t))
    net = got.energy_driving - got.energy_regenerated
    assert against_process > 10.0  # the forming force takes real work
    assert net == pytest.approx(against_process + got.gear_losses, rel=1e-6)


def test_the_envelope_is_flat_to_the_corner_then_constant_power_and_zero_past_max_speed():
    corner = DRIVE.power_limit / DRIVE.peak_torque
    speeds = np.array([0.0, 0.5 * corner, corner, 1.5 * corner, DRIVE.max_speed, 1.01 * DRIVE.max_speed])
    expected = [25.0, 25.0, 25.0, 2000.0 / (1.5 * corner), 2000.0 / DRIVE.max_speed, 0.0]
    assert np.allclose(DRIVE.peak_torque_at(speeds), expected, rtol=1e-12)
    assert np.allclose(DRIVE.peak_torque_at(-speeds), expected, rtol=1e-12)


def test_the_envelope_of_data_sheet_points_is_linear_between_them():
    d = Drive(gear_ratio=10.0, peak_torque=15.0, continuous_torque=10.0, max_speed=300.0,
              curve_speeds=(0.0, 200.0, 300.0), curve_torques=(15.0, 15.0, 9.0))
    speeds = np.array([0.0, 150.0, 200.0, 250.0, 300.0, 301.0])
    assert np.allclose(d.peak_torque_at(speeds), [15.0, 15.0, 15.0, 12.0, 9.0, 0.0], rtol=1e-12)
    assert np.allclose(d.peak_torque_at(-speeds), d.peak_torque_at(speeds))


CURVE = {"curve_speeds": (0.0, 200.0, 314.0), "curve_torques": (25.0, 25.0, 12.0), "max_speed": 314.0,
         "power_limit": None}


@pytest.mark.parametrize("changes, match", [
    ({**CURVE, "curve_torques": (25.0, 12.0, 15.0)}, r"curve_torques must not rise with speed .* 12 N m at 200 rad/s, "
                                                     r"then 15 N m at 314 rad/s"),
    ({**CURVE, "curve_speeds": (0.0, 2000.0, 3000.0)}, r"curve_speeds must run from 0 to max_speed = 314 rad/s.*in rpm\? "
                                                       r"3000 rpm is 314.2 rad/s"),
    ({**CURVE, "curve_torques": (20.0, 20.0, 12.0)}, r"curve_torques must start at peak_torque = 25 N m"),
    ({**CURVE, "power_limit": 2000.0}, r"power_limit must be None with a peak-torque curve"),
    ({**CURVE, "curve_torques": (25.0, 12.0)}, "same length"),
    ({"gear_ratio": -5.0}, r"gear_ratio must be in \(0, inf\)"),
    ({"max_speed": 3000 * 2 * math.pi / 60 * 60 / (2 * math.pi) * 2}, r"max_speed must be in \(0, 3200\] rad/s.*in rpm"),
    ({"continuous_torque": 30.0}, r"continuous_torque must be in \(0, peak_torque = 25\] N m"),
    ({"gear_efficiency": 95.0}, r"gear_efficiency must be in \(0, 1\].*in %\? 95 % is 0.95"),
    ({"motor_inertia": 0.0}, r"motor_inertia must be in \(0, inf\)"),
])
def test_bad_drive_data_is_refused_naming_the_field(changes, match):
    with pytest.raises(ValueError, match=match):
        Drive(**{**DRIVE.to_dict(), **changes})


def test_a_crank_that_stops_has_no_motor_figures():
    with pytest.raises(ValueError, match=r"omega must be in \(0, inf\) rad/s"):
        motor_cycle(DRIVE, [0.0, 1.0], [1.0, 0.0], [0.0, 0.0], [1.0, 1.0], 1.0)


@pytest.mark.slow  # 26 s (press75 simulated)
def test_a_scenario_with_a_drive_reports_the_motor(tmp_path):
    """[drive] in a scenario: it round-trips through TOML, and a simulation job writes the motor's
    figures into summary.json, its speed and torque into results.csv (the torque equal to
    motor_cycle's on the same response) and the torque-speed figure."""
    import json

    import pandas as pd

    from pressocp import Scenario
    from pressocp.jobs import simulate_job

    data = Scenario.load("press75").to_dict()
    data["model"]["clearance"] = []
    data["drive"] = DRIVE.to_dict()
    scenario = Scenario.from_dict(data)
    assert scenario.problem.drive == DRIVE
    path = tmp_path / "drive.toml"
    path.write_text(scenario.to_toml())
    assert Scenario.load(path) == scenario
    assert scenario.with_overrides({"drive.gear_ratio": 15.0}).problem.drive.gear_ratio == 15.0

    report = simulate_job(scenario, tmp_path / "out")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    figures = summary["drive"]["speed"]
    assert summary["drive"]["gear_ratio"] == DRIVE.gear_ratio and figures["rms_torque"] > 0
    table = pd.read_csv(tmp_path / "out" / "results.csv")
    speed = design_speed(scenario.problem).speed
    _, omega, alpha = speed.evaluate(table["t [s]"].to_numpy())
    assert np.allclose(table["speed motor_speed [rad/s]"], DRIVE.gear_ratio * omega, rtol=1e-9)
    assert np.max(np.abs(table["speed motor_torque [N m]"])) == pytest.approx(figures["peak_torque"], rel=1e-6)
    assert (tmp_path / "out" / "motor.png").stat().st_size > 20_000
    assert "DC-bus energy swing" in report.text


@pytest.mark.parametrize("line, match", [
    ("gear_ratio = -10.0", r"drive: gear_ratio must be in \(0, inf\)"),
    ("max_speed = 30000.0", r"drive: max_speed must be in \(0, 3200\] rad/s, got 30000.0: a value in rpm"),
    ("gear_eficiency = 0.9", r"unknown key drive\.gear_eficiency \(did you mean 'gear_efficiency'\?\)"),
    ("peak_torque = \"high\"", r"drive\.peak_torque must be a number"),
    ("max_speed = 314.0\npower_limit = 0.0\ncurve_speeds = [0.0, 314.0]\ncurve_torques = [10.0, 12.0]",
     r"drive: power_limit must be in \(0, inf\)"),
    ("peak_torque = 20.0\nmax_speed = 314.0\ncurve_speeds = [0.0, 200.0, 314.0]\ncurve_torques = [20.0, 9.0, 12.0]",
     r"drive: curve_torques must not rise with speed"),
])
def test_bad_drive_tables_are_refused_naming_the_key(line, match):
    from pressocp import Scenario, ScenarioError

    text = Scenario.load("press75").to_toml() + "\n[drive]\n" + line + "\n"
    with pytest.raises(ScenarioError, match=match):
        Scenario.from_toml(text, source="my.toml")


def test_a_scenario_round_trips_a_data_sheet_curve_and_a_bad_one_exits_2(tmp_path, capsys):
    from pressocp import Scenario
    from pressocp.cli import main

    data = Scenario.load("press75").to_dict()
    data["drive"] = Drive(gear_ratio=10.0, peak_torque=15.0, continuous_torque=10.0, max_speed=314.0,
                          curve_speeds=(0.0, 200.0, 314.0), curve_torques=(15.0, 15.0, 9.0)).to_dict()
    scenario = Scenario.from_dict(data)
    path = tmp_path / "curve.toml"
    path.write_text(scenario.to_toml())
    assert Scenario.load(path).problem.drive == scenario.problem.drive
    code = main(["design", str(path), "--set", "drive.curve_torques=[15.0, 9.0, 12.0]", "-q",
                 "--out", str(tmp_path / "o")])
    assert code == 2 and "curve_torques must not rise with speed" in capsys.readouterr().err


def test_a_data_sheet_curve_holds_on_the_optimum():
    """The ideal press's optimum under a curve that falls above 100 rad/s at the motor: the torque
    where the motor turns fast is held under the falling line (the flat-curve optimum is not)."""
    from pressocp import optimize_speed
    from pressocp.verify import motor_cycle_of

    base, model, strategy = small_ideal_press()
    flat = Drive(gear_ratio=10.0, peak_torque=30.0, continuous_torque=20.0, max_speed=314.0, motor_inertia=8e-4)
    free = optimize_speed(base.replace(drive=flat), model, strategy=strategy, progress=False)
    c = motor_cycle_of(base.replace(drive=flat), free.speed, free.simulation)
    falling = Drive(**{**flat.to_dict(), "curve_speeds": (0.0, 100.0, 250.0, 314.0),
                       "curve_torques": (30.0, 30.0, 8.0, 5.0)})
    over = np.abs(c.torque) - np.interp(np.abs(c.speed), falling.curve_speeds, falling.curve_torques)
    assert np.max(over) > 0.1  # the flat-curve optimum is over the falling line somewhere
    problem = base.replace(drive=falling)
    r = optimize_speed(problem, model, strategy=strategy, progress=False)
    assert r.success and r.verified
    held = motor_cycle_of(problem, r.speed, r.simulation)
    line = np.interp(np.abs(held.speed), falling.curve_speeds, falling.curve_torques)
    assert np.all(np.abs(held.torque) <= line * (1 + 1e-3))


@pytest.mark.slow  # 71 s; the drive's limits in the NLP by default: test_a_data_sheet_curve_holds_on_the_optimum
def test_the_drive_limits_hold_on_the_optimum_and_a_weak_motor_is_named():
    """optimize_speed on the ideal press with a drive whose peak torque lies between what the
    unconstrained optimum needs and what the problem needs at least: verified, the motor's figures
    (recomputed by motor_cycle on the verifying simulation) inside the envelope and under the top
    speed. A motor far too weak ends unconverged after the rigid stage, its status quoting what the
    unconstrained optimum asks of the motor against drive.peak_torque; a motor too
    slow for the window is refused before any solve."""
    from pressocp import Rigid, Strategy, build_model, optimize_speed
    from pressocp.verify import motor_cycle_of

    press = PressParams()
    base = SpeedProblem(press, period=0.8, ram_speed=-0.1)
    model = build_model(press, clearance=())
    strategy = Strategy(rigid=Rigid(samples=400))
    free = optimize_speed(base, model, strategy=strategy, progress=False)
    slow = Drive(gear_ratio=10.0, peak_torque=60.0, continuous_torque=20.0, max_speed=200.0, motor_inertia=4e-3)
    needs = motor_cycle_of(base.replace(drive=slow), free.speed, free.simulation)
    assert needs.speed_margin < 0  # the unconstrained optimum turns the motor faster than 200 rad/s
    problem = base.replace(drive=slow)
    r = optimize_speed(problem, model, strategy=strategy, progress=False)
    assert r.success and r.verified
    held = motor_cycle_of(problem, r.speed, r.simulation)
    assert held.speed_margin >= 0 and held.peak_torque_margin >= 0
    assert r.peak_torque >= free.peak_torque * (1 - 1e-6)  # a limit costs crank torque, never saves it

    weak = problem.replace(drive=Drive(**{**slow.to_dict(), "peak_torque": 5.0, "continuous_torque": 5.0}))
    r = optimize_speed(weak, model, strategy=strategy, progress=False)
    assert not r.success and "the drive is too weak for this problem" in r.status
    # the message quotes what the ideal press's optimum without the drive asks of the motor
    import re
    asked = float(re.search(r"needs ([0-9.]+) N m peak at the motor", r.status).group(1))
    assert asked == pytest.approx(needs.peak_torque, rel=1e-3) and "drive.peak_torque = 5 N m" in r.status
    with pytest.raises(ValueError, match=r"drive.max_speed must be in \[.*\) rad/s at gear_ratio 10, got 50.0"):
        base.replace(drive=Drive(**{**slow.to_dict(), "max_speed": 50.0}))


def test_periodic_weights_give_the_mean_on_uneven_samples_in_any_order():
    """The periodic weights of `trapezoid_weights` (over the period) against means known in closed
    form: 1 for a constant, 0 for cos over the period, 1/2 for cos^2 (periodic trapezoid rule on
    uneven samples: exact for a constant, close for a smooth function), whatever order the samples
    come in."""
    from pressocp.objectives import trapezoid_weights

    T = 0.8
    rng = np.random.default_rng(3)
    t = np.sort(rng.uniform(0.0, T, 400))
    shuffled = rng.permutation(t.size)
    w = trapezoid_weights(t[shuffled], T) / T
    phase = 2 * np.pi * t[shuffled] / T
    assert w.sum() == pytest.approx(1.0, abs=1e-12)
    assert w @ np.cos(phase) == pytest.approx(0.0, abs=1e-3)
    assert w @ np.cos(phase) ** 2 == pytest.approx(0.5, abs=1e-3)


def test_the_running_sum_equals_the_weighted_sum_and_starts_consistent():
    """`running_sum` on symbols: its rows vanish at the start values it gives its variables, and
    its last entry there equals weights @ terms computed with numpy."""
    import casadi as ca

    from pressocp.ocp.nlp import Constraints, running_sum

    x = ca.MX.sym("x", 5)
    weights = np.array([0.1, 0.3, 0.2, 0.25, 0.15])
    cons = Constraints()
    last = running_sum(cons, (x**2).T, weights)[-1]
    (r, start, _, _), = cons.lifted
    x0 = np.array([1.0, -2.0, 0.5, 3.0, -1.5])
    f = ca.Function("f", [x, r], [cons.g, last])
    r0 = np.asarray(ca.Function("s", [x], [start])(x0)).ravel()
    g, end = (np.asarray(v).ravel() for v in f(x0, r0))
    assert np.max(np.abs(g)) < 1e-14
    assert end[0] == pytest.approx(float(weights @ x0**2), rel=1e-14)


@pytest.mark.slow  # 21 s (four solves)
def test_the_rms_limit_holds_on_the_optimum_and_a_motor_too_weak_for_it_is_named():
    """The ideal press with a motor whose continuous rating lies between the RMS motor torque of
    the peak-torque optimum and that of the RMS optimum: the optimum under the rating is verified,
    its RMS motor torque (recomputed by motor_cycle on the verifying simulation) is under the
    rating and under the unlimited optimum's, and its peak no lower. A rating below what the RMS
    optimum needs is named in the status."""
    from pressocp import Rigid, Strategy, optimize_speed
    from pressocp.verify import motor_cycle_of

    base, model, strategy = small_ideal_press()
    big = Drive(gear_ratio=10.0, peak_torque=60.0, continuous_torque=60.0, max_speed=314.0, motor_inertia=8e-4)
    free = optimize_speed(base.replace(drive=big), model, strategy=strategy, progress=False)
    needs = motor_cycle_of(base.replace(drive=big), free.speed, free.simulation).rms_torque
    low = optimize_speed(base.replace(drive=big, objective="rms_torque"), model, strategy=strategy, progress=False)
    least = motor_cycle_of(base.replace(drive=big), low.speed, low.simulation).rms_torque
    assert least < 0.98 * needs  # room for a rating between them
    rating = 0.5 * (least + needs)
    problem = base.replace(drive=Drive(**{**big.to_dict(), "continuous_torque": rating}))
    r = optimize_speed(problem, model, strategy=strategy, progress=False)
    assert r.success and r.verified
    held = motor_cycle_of(problem, r.speed, r.simulation)
    assert held.rms_torque <= rating * (1 + 1e-3) and held.rms_torque < needs
    assert r.peak_torque >= free.peak_torque * (1 - 1e-6)

    weak = base.replace(drive=Drive(**{**big.to_dict(), "continuous_torque": 0.8 * least}))
    short = Strategy(rigid=Rigid(samples=300, window_samples=50, jit=False, ipopt={"ipopt.max_iter": 40}))
    r = optimize_speed(weak, model, strategy=short, progress=False)
    assert not r.success and "drive.continuous_torque" in r.status


def test_the_drive_objectives_equal_a_hand_calculation_at_constant_speed():
    """RMS motor torque, energy drawn per stroke (with a regeneration efficiency) and the DC-bus
    energy swing as objectives (`pressocp.objectives`) on the ideal press at constant speed, against
    the Newton-Euler torque on a fine grid through the gear written here: on the response's closed
    grid and on one period's samples without its end (the NLP's periodic weights)."""
    from dataclasses import replace

    from pressocp.objectives import get

    drive = replace(DRIVE, regeneration_efficiency=0.6)
    press, period = PressParams(), 0.8
    w = 2 * math.pi / period
    t = np.linspace(0.0, period, 2001)
    sim = ideal_response(press, SLIDER_CRANK, FourierSpeed.constant(period), t)

    theta = np.linspace(0.0, 2 * math.pi, 200_001)
    tau = newton_euler(press, theta, w, 0.0)["torque"]
    i, eta = drive.gear_ratio, drive.gear_efficiency
    power = np.where(tau >= 0, tau / (i * eta), tau * eta / i) * i * w
    dt = period / (len(theta) - 1)
    rms = math.sqrt(np.mean((power[:-1] / (i * w)) ** 2))
    drawn = np.sum(np.maximum(power[:-1], 0) - 0.6 * np.maximum(-power[:-1], 0)) * dt
    stored = np.concatenate([[0.0], np.cumsum(power[:-1] - np.mean(power[:-1])) * dt])
    expected = {"rms_motor_torque": rms, "energy_per_stroke": drawn, "bus_energy_swing": np.ptp(stored)}
    samples = {"t": t[:-1], "torque": sim.torque[:-1], "omega": sim.omega[:-1]}
    for name, value in expected.items():
        objective = get(name)
        assert objective.value(sim, drive) == pytest.approx(value, rel=5e-3), name
        assert objective.value(samples, drive, period=period, alpha=np.zeros(t.size - 1)) == pytest.approx(
            value, rel=5e-3), name
    with pytest.raises(ValueError, match="needs a drive"):
        SpeedProblem(press, period=period, ram_speed=-0.1, objective="energy_per_stroke")


@pytest.mark.slow  # 23 s (four solves); the objectives by default: the hand calculation
def test_each_drive_objective_beats_the_peak_optimum_at_its_own_figure():
    """The ideal press with a drive, each drive objective optimised: verified, the NLP's value equal to
    the verifying simulation's (0.5 %), and the motor figure it minimises (recomputed by
    motor_cycle) lower than at the peak-torque optimum, whose peak torque is in turn the lowest."""
    from pressocp import optimize_speed
    from pressocp.verify import motor_cycle_of

    drive = Drive(gear_ratio=10.0, peak_torque=60.0, continuous_torque=60.0, max_speed=314.0, motor_inertia=8e-4)
    plain, model, strategy = small_ideal_press(window_samples=200)
    base = plain.replace(drive=drive)
    peak = optimize_speed(base, model, strategy=strategy, progress=False)
    at_peak = motor_cycle_of(base, peak.speed, peak.simulation)
    figure = {"rms_motor_torque": "rms_torque", "energy_per_stroke": "energy_drawn",
              "bus_energy_swing": "bus_energy_swing"}
    for name, field in figure.items():
        problem = base.replace(objective=name)
        r = optimize_speed(problem, model, strategy=strategy, progress=False)
        assert r.success and r.verified, name
        assert r.objective_value == pytest.approx(r.verified_objective, rel=5e-3), name
        own = motor_cycle_of(problem, r.speed, r.simulation)
        assert getattr(own, field) == pytest.approx(r.verified_objective, rel=5e-3), name
        assert getattr(own, field) < 0.97 * getattr(at_peak, field), name
        assert r.peak_torque > peak.peak_torque, name


@pytest.mark.parametrize("rpm", [1500.0, 2000.0, 3000.0])
def test_a_motor_speed_in_rpm_is_suspected(rpm):
    """Rated speeds in rpm typed as rad/s: below the hard limit (3200 rad/s), but warned about (``--strict``
    refuses them); a motor at its rated speed in rad/s is not."""
    from pressocp.checks import PlausibilityWarning

    with pytest.warns(PlausibilityWarning, match=rf"a value in rpm\? {rpm:g} rpm is {rpm * 2 * np.pi / 60:.4g} rad/s"):
        Drive(max_speed=rpm)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Drive(max_speed=rpm * 2 * np.pi / 60)


def test_with_a_drive_the_reports_torque_row_is_the_cranks():
    """With a drive the motor has a torque of its own (the report's motor table), so the load table's
    torque row says it is the torque at the crank."""
    from pressocp.mechanism.ideal import ideal_response
    from pressocp.report import load_table

    sim = ideal_response(PressParams(), SLIDER_CRANK, FourierSpeed.constant(0.8))
    assert load_table([("design", sim)])[1][0] == "peak motor torque, N·m"
    assert load_table([("design", sim)], geared=True)[1][0] == "peak torque at the crank, N·m"
