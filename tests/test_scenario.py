"""Scenario files: the bundled ones load and round-trip through TOML, overrides by dotted key, and every
bad file or value is refused before anything is solved, with a message that names the key."""

import pytest

from pressocp.scenario import Scenario, ScenarioError, bundled

GOOD = Scenario.bundled("press75").to_toml()


def test_bundled_scenarios_load_and_round_trip(tmp_path):
    assert set(bundled()) >= {"press75", "press60", "large_press"}
    for name in bundled():
        s = Scenario.load(name)
        path = tmp_path / f"{name}.toml"
        path.write_text(s.to_toml())
        assert Scenario.load(path) == s
    s = Scenario.load("press75")
    assert s.problem.period == pytest.approx(0.8) and s.problem.ram_speed == -0.1
    assert s.press.wrist_pin.journal_radius == 0.025 and s.model.clearance == ("crank_pin", "wrist_pin")


def test_overrides_by_dotted_key():
    s = Scenario.load("press75").with_overrides({"problem.stroke_rate_spm": 60, "wrist_pin.clearance": 5e-5,
                                                 "press.slider_mass": 200.0, "model.rod": "flexible"})
    assert s.problem.period == pytest.approx(1.0) and s.press.wrist_pin.clearance == 5e-5
    assert s.press.slider_mass == 200.0 and s.model.rod == "flexible"
    assert s.press.wrist_pin.journal_radius == 0.025  # the rest of the joint kept


def edit(old, new):
    assert old in GOOD, old
    return GOOD.replace(old, new, 1)


BAD = [
    (edit("slider_mass = 150.0", "slider_mas = 150.0"), r"unknown key press\.slider_mas \(did you mean 'slider_mass'\?\)"),
    (edit("[problem]", "[problem]\nram_sped = -0.1"), r"problem\.ram_sped .*did you mean 'ram_speed'"),
    (edit("[model]", "[modle]"), r"unknown key modle \(did you mean 'model'\?\)"),
    (edit("slider_mass = 150.0", 'slider_mass = "heavy"'), r"press\.slider_mass must be a number"),
    (edit("n_harmonics = 15", "n_harmonics = 15.5"), r"problem\.n_harmonics must be an integer"),
    (edit("window = [0.7, 0.3]", "window = [0.3, 0.7]"), r"problem: window must be \(h1/H, h2/H\) with h2/H < h1/H"),
    (edit("window = [0.7, 0.3]", "window = 0.7"), r"problem\.window must be a list of two numbers"),
    (edit("ram_speed = -0.1", "ram_speed = -0.001"), r"problem: ram_speed must be in \[.*cannot deliver"),
    (edit("ram_speed = -0.1", "ram_speed = 0.1"), r"ram_speed must be negative"),
    (edit("rod_length = 0.25", "rod_length = 0.04"), r"press: rod_length must be in \[1.5 x crank_radius = 0.075"),
    (edit('objective = "peak_torque"', 'objective = "peak_torq"'), r"objective must be one of"),
    (edit('transcription = "auto"', 'transcription = "colocation"'), r"did you mean 'collocation'"),
    (edit('rod = "rigid"', 'rod = "elastic"'), r"model: rod must be one of 'rigid', 'flexible'"),
    (edit("period_s = 0.8", "stroke_rate_spm = 75\nperiod_s = 0.8"), r"stroke_rate_spm or period_s, not both"),
    (edit("period_s = 0.8", "stroke_rate_spm = -75"), r"stroke_rate_spm must be in \(0, 2000\)"),
    (edit("period_s = 0.8", ""), r"problem\.stroke_rate_spm \(strokes per minute\) or problem\.period_s \(s per "
                                 r"stroke\) is missing: a scenario has no default cycle"),
    (edit("[press.crank_pin]", "[press.crank_pin]\nradius = 0.04"), r"press\.crank_pin\.radius .*journal_radius"),
    (edit("clearance = 0.0001", "clearance = -0.0001"), r"press: crank_pin.clearance must be in \(0, inf\) m"),
    (edit("clearance = 0.0001", "clearance = 0.1"), r"press: crank_pin.clearance must be in \[1e-06, 0.004\] m .*0.1 mm is 0.0001 m"),
    (GOOD + "\n[solver\n", r"not valid TOML: .*line"),
    ('name = 3\n', r"name must be a string"),
]


@pytest.mark.parametrize("text, match", BAD)
def test_bad_scenarios_are_refused_naming_the_key(text, match):
    with pytest.raises(ScenarioError, match=match):
        Scenario.from_toml(text, source="my.toml")


def test_missing_file_and_unknown_bundled_name(tmp_path):
    with pytest.raises(ScenarioError, match=r"no such scenario file .*press75"):
        Scenario.load(tmp_path / "nothere.toml")
    with pytest.raises(ScenarioError, match=r"did you mean 'press75'"):
        Scenario.bundled("press57")


KNUCKLE = Scenario.bundled("knuckle40").to_toml()


def test_a_scenario_names_its_mechanism():
    """[mechanism] builds the linkage for the problem and the model alike; the drive gives the press's
    crank radius and rod length; a slider-crank scenario writes no [mechanism] table."""
    from pressocp import KnuckleJoint, SixBar

    s = Scenario.load("knuckle40")
    assert isinstance(s.problem.mechanism, KnuckleJoint) and s.model.mechanism == s.problem.mechanism
    assert (s.press.crank_radius, s.press.rod_length) == (0.16, 0.25)  # not in its [press] table
    assert s.build_model().mechanism == s.problem.mechanism
    assert s.problem.stroke == pytest.approx(0.03511, abs=1e-5)
    assert "[mechanism]" not in GOOD
    six = Scenario.load("press75").with_overrides({"mechanism.name": "six_bar", "mechanism.coupler_mass": 4.0})
    assert six.problem.mechanism == SixBar(coupler_mass=4.0) == six.model.mechanism


def knuckle_edit(old, new):
    assert old in KNUCKLE, old
    return KNUCKLE.replace(old, new, 1)


@pytest.mark.parametrize("text, match", [
    (knuckle_edit('name = "knuckle_joint"', 'name = "knuckle"'),
     r"mechanism\.name must be one of slider_crank, six_bar, knuckle_joint; got 'knuckle' \(did you mean 'knuckle_joint'"),
    (knuckle_edit("input_inertia = 0.05", "input_inertial = 0.05"),
     r"unknown key mechanism\.input_inertial \(did you mean 'input_inertia'\?\)"),
    (knuckle_edit("upper_link = 0.16", "upper_lnk = 0.16"), r"unknown key mechanism\.drive\.upper_lnk"),
    (knuckle_edit("input_crank = 0.04", "input_crank = 0.4"), r"input_crank must be in \(0, .*\) m for the crank"),
    (knuckle_edit("coupler_mass = 3.0", 'coupler_mass = "light"'), r"mechanism\.coupler_mass must be a number"),
    (knuckle_edit("crank_radius = 0.16", "crank_radius = 0.05"),
     r"crank_radius = 0.05 m of the press differs from the knuckle_joint drive's 0.16 m"),
    (GOOD.replace("[model]", "[model]\nmechanism = \"six_bar\""), r"unknown key model\.mechanism"),
])
def test_bad_mechanisms_are_refused_naming_the_key(text, match):
    with pytest.raises(ScenarioError, match=match):
        Scenario.from_toml(text, source="my.toml")


def test_the_flexible_starts_are_a_solver_key(tmp_path):
    """[solver] flexible_backoffs reaches the strategy, round-trips through a file, and [] means none."""
    s = Scenario.load("slender_rod").with_overrides({"solver.flexible_backoffs": [0.9, 0.8]})
    assert s.solver.make_strategy().flexible_backoffs == (0.9, 0.8)
    path = tmp_path / "s.toml"
    path.write_text(s.to_toml())
    assert "flexible_backoffs = [0.9, 0.8]" in path.read_text()
    assert Scenario.load(path).solver.make_strategy().flexible_backoffs == (0.9, 0.8)
    assert Scenario.load("slender_rod").with_overrides({"solver.flexible_backoffs": []}).solver.make_strategy() \
        .flexible_backoffs == ()


@pytest.mark.parametrize("key, table", [("stroke_rate_spm", "problem"), ("ram_speed", "problem"),
                                        ("verify_rtol", "solver"), ("gear_ratio", "drive"), ("n_elements", "model"),
                                        ("clearance", "crank_pin"), ("clearance", "wrist_pin")])
def test_a_key_set_without_its_table_names_the_table(key, table):
    """An override without a table's name is a press field; one of another table's fields (or of a joint's)
    is refused naming that table (not with the press's keys)."""
    with pytest.raises(ScenarioError, match=rf"{key} is not a press field \(did you mean [^)]*'{table}\.{key}'[^)]*\?\)"):
        Scenario.load("press60").with_overrides({key: 1.0})
