"""Sensitivities of peaks to press parameters: AD (forward sensitivities of the periodic response)
against central finite differences of separately run periodic simulations."""

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import pressocp as po
from pressocp.sensitivity import peak_times, sensitivities

OPTIMUM = Path(__file__).parent / "references" / "press75_optimum_speed.json"
PARAMETERS = ("slider_mass", "wrist_pin.clearance", "crank_pin.stiffness")


def with_value(press, name, value):
    if "." in name:
        joint, field = name.split(".")
        return replace(press, **{joint: replace(getattr(press, joint), **{field: value})})
    return replace(press, **{name: value})


def refined_peak_torque(press, speed, rtol):
    """Peak |torque| of the periodic response, the parabola's vertex through the top three samples
    (written here, apart from the package's peak search)."""
    r = po.simulate(po.build_model(press), speed, periodic=True, method="cvodes", rtol=rtol, n_out=20001)
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


def test_peak_times_find_rivals_and_the_vertex():
    t = np.linspace(0, 1, 1001)
    y = np.cos(2 * np.pi * 2 * (t - 0.1234))  # two equal maxima, between samples
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


@pytest.mark.slow
@pytest.mark.parametrize("case", ["constant", "optimum"])
def test_ad_matches_central_differences(case):
    """Slider mass on the smooth case (constant speed, 75 spm) and on the optimum at 75 spm (four
    nearly equal torque peaks: the change of J is predicted from each peak's derivative), rtol 1e-10,
    steps of 1 %."""
    press = po.PressParams()
    speed = (po.FourierSpeed.constant(0.8) if case == "constant"
             else po.FourierSpeed.from_dict(json.loads(OPTIMUM.read_text())))
    s = sensitivities(po.build_model(press), speed, PARAMETERS, rtol=1e-10)
    n = "slider_mass"
    h = 0.01 * press.value(n)
    fd = (refined_peak_torque(with_value(press, n, press.value(n) + h), speed, 1e-10)
          - refined_peak_torque(with_value(press, n, press.value(n) - h), speed, 1e-10)) / (2 * h)
    ad = (s.change("peak_torque", n, h) - s.change("peak_torque", n, -h)) / (2 * h)
    assert fd == pytest.approx(ad, rel=0.02)
