"""Sensitivities of peaks to press parameters: AD (forward sensitivities of the periodic response)
against central finite differences of separately run periodic simulations."""

import json
from pathlib import Path

import numpy as np
import pytest

import pressocp as po
from pressocp.sensitivity import peak_times, sensitivities

# |torque| of the periodic response at given times, settled cycle by cycle (written apart from the
# package's periodic search and sensitivities, in the benchmark that measures them)
from benchmarks.bench_sensitivity import torque_at  # noqa: E402

OPTIMUM = Path(__file__).parent / "references" / "press75_optimum_speed.json"
PARAMETERS = ("slider_mass", "wrist_pin.clearance", "crank_pin.stiffness")


def refined_peak_torque(press, speed, rtol):
    """Peak |torque| of the periodic response, the parabola's vertex through the top three samples
    (written here, apart from the package's peak search)."""
    integ = po.Integrator(method="cvodes", rtol=rtol, periodic_tol=1000 * rtol)  # periodic to about rtol
    r = po.simulate(po.build_model(press), speed, periodic=True, integrator=integ, n_out=20001)
    y = np.abs(r.torque)
    k = int(np.argmax(y))
    y0, y1, y2 = y[k - 1], y[k], y[k + 1]
    return y1 - (y0 - y2) ** 2 / (8 * (y0 - 2 * y1 + y2))


def test_bad_requests_fail_before_integrating():
    model = po.build_model(po.PressParams())
    speed = po.FourierSpeed.constant(0.8)
    with pytest.raises(ValueError, match="slider_mas.*slider_mass"):
        sensitivities(model, speed, ("slider_mas",))
    with pytest.raises(ValueError, match="quantity"):
        sensitivities(model, speed, ("slider_mass",), ("peak_power",))
    with pytest.raises(ValueError, match="no states"):
        sensitivities(po.build_model(po.PressParams(), clearance=()), speed, ("slider_mass",))
    for rtol in (0.0, 1e-3, 1.0):  # the error estimate runs at ten times it: a looser one means nothing
        with pytest.raises(ValueError, match=rf"rtol must be in \(0, 0\.001\), got {rtol!r}"):
            sensitivities(model, speed, ("slider_mass",), rtol=rtol)


def test_peak_times_find_rivals_and_the_vertex():
    t = np.linspace(0, 1, 1001)
    y = 2.0 + np.cos(2 * np.pi * 2 * (t - 0.1234))  # two equal maxima, between samples
    times = peak_times(t, y, 1.0)
    assert len(times) == 2
    assert min(abs(times[0] - 0.1234), abs(times[0] - 0.6234)) < 1e-6
    assert len(peak_times(t, y * (1 + 0.1 * (t < 0.5)), 1.0)) == 1


def test_symbolic_parameters_leave_the_model_unchanged():
    press = po.PressParams()
    speed = po.FourierSpeed.constant(0.8)
    plain = po.build_model(press)
    symbolic = po.build_model(press, parameters=PARAMETERS)
    x = plain.x0 + 0.3
    assert np.allclose(np.asarray(plain.outputs(0.1, x, plain.parameters(speed))).ravel(),
                       np.asarray(symbolic.outputs(0.1, x, symbolic.parameters(speed))).ravel(), rtol=1e-12, atol=1e-9)
    assert symbolic.parameters(speed)[-3:].tolist() == [150.0, 1e-4, press.crank_pin.contact_stiffness]


@pytest.fixture(scope="module")
def ad():
    """AD sensitivities on both cases (rtol 1e-10), computed once."""
    press = po.PressParams()
    out = {}
    for case, speed in (("constant", po.FourierSpeed.constant(0.8)),
                        ("optimum", po.FourierSpeed.from_dict(json.loads(OPTIMUM.read_text())))):
        out[case] = (speed, sensitivities(po.build_model(press), speed, PARAMETERS, rtol=1e-10))
    return out


@pytest.mark.slow
@pytest.mark.parametrize("case, name, step", [
    ("constant", "slider_mass", 0.01),
    ("optimum", "slider_mass", 0.01),
    ("optimum", "wrist_pin.clearance", 0.0025),
    ("optimum", "crank_pin.stiffness", 0.0025),
])
def test_ad_matches_central_differences(ad, case, name, step):
    """Peak torque at 75 spm, rtol 1e-10: the smooth case (constant speed) and the optimum (four
    nearly equal torque peaks: the change of J over a step is predicted from each peak's derivative).

    At constant speed the clearance and stiffness derivatives are below what rtol 1e-10 resolves
    (their rows are not ``resolved``); they are compared at rtol 1e-13 below."""
    press = po.PressParams()
    speed, s = ad[case]
    h = step * press.value(name)
    fd = (refined_peak_torque(press.with_value(name, press.value(name) + h), speed, 1e-10)
          - refined_peak_torque(press.with_value(name, press.value(name) - h), speed, 1e-10)) / (2 * h)
    predicted = (s.change("peak_torque", name, h) - s.change("peak_torque", name, -h)) / (2 * h)
    assert fd == pytest.approx(predicted, rel=0.02)


@pytest.mark.slow
def test_ad_matches_central_differences_for_a_worn_wrist_pin_at_constant_speed():
    """The smooth case's clearance derivative, where central differences can resolve it.

    At constant speed a journal on its wall moves along the joint force's line when the clearance
    grows, which leaves the crank's torque arm unchanged to first order: dJ/dc is about -17 N m/m
    from 0.1 to 2 mm, and the peak carries a contact ripple of about 1e-4 N m. At 0.1 mm a ±5 %
    step moves J by 9e-5 N m, inside that ripple; on a 2 mm (worn) wrist pin a ±20 % step moves it
    by 1.4e-2 N m, and J is linear in c over that range (AD: -17.09, -16.76, -16.85 N m/m at 0.1,
    1, 2 mm), so the large step costs no truncation error. The differences need cycles periodic to
    about rtol (`Integrator.periodic_tol` 1e-7): periodic to the default 1e-4 only, the slowly dying
    contact transient moved the peak by 1e-2 N m and the difference to -18.8."""
    press = po.PressParams().with_value("wrist_pin.clearance", 2e-3)
    speed = po.FourierSpeed.constant(0.8)
    name = "wrist_pin.clearance"
    s = sensitivities(po.build_model(press), speed, (name,), rtol=1e-10)
    h = 0.2 * press.value(name)
    fd = (refined_peak_torque(press.with_value(name, press.value(name) + h), speed, 1e-10)
          - refined_peak_torque(press.with_value(name, press.value(name) - h), speed, 1e-10)) / (2 * h)
    predicted = (s.change("peak_torque", name, h) - s.change("peak_torque", name, -h)) / (2 * h)
    assert fd == pytest.approx(predicted, rel=0.02)


@pytest.fixture(scope="module")
def smooth_fine():
    """AD at rtol 1e-13 on the smooth case (constant speed, 75 spm)."""
    return sensitivities(po.build_model(po.PressParams()), po.FourierSpeed.constant(0.8), PARAMETERS, rtol=1e-13)


@pytest.mark.slow
@pytest.mark.parametrize("name", PARAMETERS)
def test_ad_matches_central_differences_on_the_smooth_case_at_rtol_1e_13(smooth_fine, name):
    """The smooth case's derivatives at the default bearings (0.1 mm).

    At constant speed a journal on its wall moves along the joint force when the clearance or the
    contact stiffness changes, so its effect on the torque cancels to 1e-5 (clearance) and 1e-7
    (stiffness) of its parts: at rtol 1e-10 both AD and differences are noise. At rtol 1e-13 both
    resolve it. |torque| has two rival maxima (the slider's weight lifted and lowered, 1e-6 apart);
    each is differenced at its own time, which is the peak's derivative (the peak's time moves with p,
    but d|torque|/dt = 0 there). Steps of +-5 %: the stiffness enters as (F/K)^(2/3), whose central
    difference at +-20 % is 3 % off by truncation."""
    press = po.PressParams()
    speed = po.FourierSpeed.constant(0.8)
    rows = smooth_fine.per_peak[smooth_fine.per_peak["parameter"] == name]
    assert len(rows) == 2
    h = 0.05 * press.value(name)
    times = rows["time"].to_numpy()
    fd = (torque_at(press.with_value(name, press.value(name) + h), speed, times, 1e-13)
          - torque_at(press.with_value(name, press.value(name) - h), speed, times, 1e-13)) / (2 * h)
    assert fd == pytest.approx(rows["derivative"].to_numpy(), rel=0.02)


def test_a_derivative_below_the_integrators_resolution_is_flagged():
    """At constant speed and rtol 1e-9 the contact stiffness's derivative of the peak torque (normalised
    1e-7, a cancellation) is noise and flagged; the slider mass's (normalised 0.98) is resolved."""
    s = sensitivities(po.build_model(po.PressParams()), po.FourierSpeed.constant(0.8),
                      ("slider_mass", "crank_pin.stiffness"), rtol=1e-9)
    t = s.table.set_index("parameter")
    assert t.loc["slider_mass", "resolved"] and t.loc["slider_mass", "error_estimate"] < 1e-2
    assert not t.loc["crank_pin.stiffness", "resolved"] and t.loc["crank_pin.stiffness", "error_estimate"] > 0.1


def test_without_a_looser_run_every_derivative_is_unverified(monkeypatch):
    """When the run at ten times rtol finds no periodic state (through impacts its periodic search can
    stall above its tolerance), the derivatives stand, each with an infinite error estimate, and the
    result says why."""
    import pressocp.sensitivity as sens

    found = sens.sensitivity_cycle

    def stalls_when_loose(model, msym, fsa, speed, rtol, periodic, **kwargs):
        if rtol > 1e-8:
            raise po.SimulationError("periodic steady state not found: residual 3e-05 (tol 1e-05)")
        return found(model, msym, fsa, speed, rtol, periodic, **kwargs)

    monkeypatch.setattr(sens, "sensitivity_cycle", stalls_when_loose)
    model = po.build_model(po.PressParams(), clearance=("wrist_pin",))
    s = sensitivities(model, po.FourierSpeed.constant(0.8), ("slider_mass",), rtol=1e-8)
    row = s.table.iloc[0]
    assert np.isinf(row["error_estimate"]) and not row["resolved"] and 0.4 < row["derivative"] < 0.6
    assert "failed" in s.unverified and "residual 3e-05" in s.unverified


def test_without_the_estimate_the_derivatives_are_the_same_and_unverified(monkeypatch):
    """``error_estimate=False`` runs nothing at ten times rtol (no second periodic search), gives the
    same derivatives to the bit, and every row says it is not verified."""
    import pressocp.sensitivity as sens

    model = po.build_model(po.PressParams(), clearance=("wrist_pin",))
    speed = po.FourierSpeed.constant(0.8)
    full = sensitivities(model, speed, ("slider_mass",), rtol=1e-8)

    found, tolerances = sens.sensitivity_cycle, []

    def recorded(model, msym, fsa, speed, rtol, periodic, **kwargs):
        tolerances.append(rtol)
        return found(model, msym, fsa, speed, rtol, periodic, **kwargs)

    monkeypatch.setattr(sens, "sensitivity_cycle", recorded)
    bare = sensitivities(model, speed, ("slider_mass",), rtol=1e-8, error_estimate=False)
    assert tolerances == [1e-8]  # no periodic search at ten times rtol
    assert bare.table["derivative"].tolist() == full.table["derivative"].tolist()
    assert full.table["resolved"].all() and not bare.table["resolved"].any()
    assert np.isinf(bare.table["error_estimate"]).all() and "error_estimate=False" in bare.unverified
    assert full.unverified == ""


@pytest.mark.slow  # 19 s with the compile cache warm, 74 s cold
def test_a_second_call_on_one_model_reuses_its_derivatives_and_answers_the_same():
    """What a call builds is kept with the model (the parameterised model, keyed by the parameters):
    a second call gives the same numbers, and another parameter set on the same model gets its own
    model, not the first's."""
    press = po.PressParams()
    speed = po.FourierSpeed.constant(0.8)
    model = po.build_model(press)
    first = sensitivities(model, speed, ("slider_mass",), rtol=1e-8)
    kept = [k for k in model.functions if k[0] == "sensitivity_model"]
    second = sensitivities(model, speed, ("slider_mass",), rtol=1e-8)
    assert [k for k in model.functions if k[0] == "sensitivity_model"] == kept
    cols = ["derivative", "value", "time", "error_estimate"]
    assert second.table[cols].to_numpy().tolist() == first.table[cols].to_numpy().tolist()
    both = sensitivities(model, speed, ("wrist_pin.clearance", "slider_mass"), rtol=1e-8)
    assert len([k for k in model.functions if k[0] == "sensitivity_model"]) == 2
    assert both.derivative("peak_torque", "slider_mass") == pytest.approx(first.derivative("peak_torque", "slider_mass"),
                                                                          rel=1e-6)


def test_the_seed_optimums_derivatives_at_loose_rtol_match_central_differences():
    """On the 75 spm optimum (four rival torque peaks) AD at rtol 3e-8 is within 1 % of central
    differences at rtol 1e-12 (`tests/references/press75_peak_torque_derivatives.json`, written by the
    benchmark's own differences). Each derivative is read at the peak of the run that carries the
    directions: read at a plain run's peaks, 1-4 µs away, the same call was 4.8 % off."""
    ref = json.loads((Path(__file__).parent / "references" / "press75_peak_torque_derivatives.json").read_text())
    speed = po.FourierSpeed.from_dict(json.loads(OPTIMUM.read_text()))
    s = sensitivities(po.build_model(po.PressParams()), speed, PARAMETERS, rtol=3e-8, error_estimate=False)
    for name in PARAMETERS:
        rows = s.per_peak[s.per_peak["parameter"] == name].sort_values("time")
        assert rows["time"].to_numpy() == pytest.approx(ref["peak_times_s"], abs=2e-5)
        assert rows["derivative"].to_numpy() == pytest.approx(ref["derivatives"][name], rel=0.01)


@pytest.mark.slow  # about 20 s
def test_an_impacting_response_falls_back_to_the_periodic_search():
    """The 75 spm kinematic design impacts: Newton steps from the sensitivity cycle's own monodromy
    do not lower its residual there, and the package's periodic search (settling, difference Newton
    with a line search) finds the state from the best of them. The peak is that of a periodic
    simulation found apart (`po.simulate`, CVODES, periodic to 1e-6: at 1e-7 its own search stalls at
    2e-7 on this response, whose per-cycle peaks wander) to 0.5 %."""
    scenario = po.Scenario.load("press75")
    model = scenario.build_model()
    speed = po.design_speed(scenario.problem).speed
    # the tornado's parameters (benchmarks/bench_studies.py), with which the monodromy's steps diverged
    names = ("slider_mass", "rod_mass", "crank_inertia", "wrist_pin.clearance", "crank_pin.clearance",
             "wrist_pin.stiffness", "crank_pin.stiffness")
    s = sensitivities(model, speed, names, rtol=1e-10, error_estimate=False)
    r = po.simulate(model, speed, periodic=True, n_out=20001, work=False,
                    integrator=po.Integrator("cvodes", rtol=1e-10, periodic_tol=1e-6))
    assert np.isfinite(s.table["derivative"]).all()
    assert s.table["value"].iloc[0] == pytest.approx(np.max(np.abs(r.torque)), rel=5e-3)
