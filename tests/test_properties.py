"""Property tests (hypothesis): every generated press, bearing and problem is either refused at the
door, with a ValueError or TypeError whose message names one of the fields it was given, or gives a
finite kinematic design and a finite rigid response. The same for a scenario's TOML text and the
command line's ``--set`` overrides: refused with exit 2 and a message naming the key, never a
traceback."""

import math

import numpy as np
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import pressocp as po
from pressocp.cli import main

#: Numeric fields and their defaults (SI): generated as default x 10^u, u in [-5, 5], either sign.
PRESS = {"crank_radius": 0.05, "rod_length": 0.25, "crank_inertia": 0.5, "crank_mass": 20.0, "crank_com": 0.01,
         "rod_mass": 3.14, "rod_youngs_modulus": 2.1e11, "rod_area_moment": 2.13e-7, "rod_damping_ratio": 0.02,
         "slider_mass": 150.0, "gravity": 9.81}
BEARING = {"clearance": 1e-4, "journal_radius": 0.04, "stiffness": 1e10, "damping": 1e3, "tangential_damping": 1e3}
PROBLEM = {"period": 0.8, "ram_speed": -0.1, "omega_max": 20.0, "max_pin_force": 1e4}

SPECIAL = st.sampled_from([0.0, -0.0, math.nan, math.inf, -math.inf, True, "0.1", "x", None, [1.0]])


def around(default: float):
    """A value near `default` by orders of magnitude, of either sign, or a special value."""
    scaled = st.builds(lambda u, s: s * default * 10.0 ** u, st.floats(-5, 5), st.sampled_from([1.0, 1.0, 1.0, -1.0]))
    return st.one_of(scaled, st.just(default), SPECIAL)


def some_of(fields: dict):
    """A dict of some of `fields` (name -> generated value)."""
    return st.fixed_dictionaries({}, optional={k: around(v) for k, v in fields.items()})


def names_a_field(err: Exception, given: list[str]) -> bool:
    text = str(err)
    return any(name in text for name in given) or any(name.split(".")[-1] in text for name in given)


# the number of examples is the profile's (tests/conftest.py): a few in the default run (each designed
# press costs a design and a response, about 5 s), many with HYPOTHESIS_PROFILE=thorough (the slow_tests job)
@settings(deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(press=some_of(PRESS), pin=some_of(BEARING), problem=some_of(PROBLEM))
def test_a_generated_press_and_problem_is_refused_by_name_or_gives_finite_results(press, pin, problem):
    given_names = [*press, *(f"wrist_pin.{k}" for k in pin), *problem]
    try:
        params = po.PressParams(**press, wrist_pin=po.Bearing(**pin))
        sp = po.SpeedProblem(params, **problem)
    except (ValueError, TypeError) as err:
        assert names_a_field(err, given_names), (given_names, str(err))
        event("refused at the door")
        return
    try:
        design = po.design_speed(sp)
    except ValueError as err:  # a problem the crank cannot meet: refused by the design, naming why
        assert str(err), given_names
        event("refused by the design")
        return
    t = np.linspace(0.0, sp.period, 501)
    response = po.rigid_response(params, design.speed, t)
    for name in ("torque", "slider_normal_force", "crank_pin_force", "wrist_pin_force"):
        assert np.all(np.isfinite(getattr(response, name))), (name, given_names)
    assert design.speed.min_speed() > 0.0
    event("designed")


TOML_VALUES = st.one_of(st.floats(allow_nan=False, allow_infinity=False, width=32).map(repr),
                        st.integers(-10**6, 10**6).map(str), st.sampled_from(['"abc"', "true", "[1, 2]", "{}", "nan",
                                                                                "inf", "-0.0", '""']))
TOML_KEYS = st.sampled_from([f"press.{k}" for k in PRESS] + [f"press.wrist_pin.{k}" for k in BEARING]
                            + ["problem.stroke_rate_spm", "problem.ram_speed", "problem.window", "problem.n_harmonics",
                               "problem.objective", "solver.elements", "solver.verify_rtol", "solver.jit", "solver.flexible_backoffs",
                               "model.rod", "model.clearance", "press.no_such_key"])


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=TOML_KEYS, value=TOML_VALUES)
def test_a_generated_set_override_is_shown_or_refused_by_name(key, value, capsys):
    """``pressocp scenario show press75 --set KEY=VALUE``: exit 0 (the value accepted and shown) or 2
    with one message naming the key, never a traceback."""
    code = main(["scenario", "show", "press75", "--set", f"{key}={value}"])
    err = capsys.readouterr().err
    assert code in (0, 2) and "Traceback" not in err
    if code == 2:
        assert err.startswith("pressocp: error:")
        assert key.split(".")[-1] in err, (key, value, err)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(text=st.text(max_size=200))
def test_a_generated_scenario_file_is_loaded_or_refused_with_its_name(text, tmp_path_factory):
    path = tmp_path_factory.mktemp("toml") / "generated.toml"
    path.write_text(text, encoding="utf-8")
    try:
        po.Scenario.load(str(path))
    except (ValueError, TypeError) as err:
        assert "generated.toml" in str(err), str(err)

