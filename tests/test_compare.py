"""``pressocp compare A B`` (issue 32, item 7): the sizing figures of two designs side by side with
B/A, overlaid figures, from results folders, scenarios or speed files; bad arguments exit 2 naming
the argument. The designs are simulate jobs of constant speeds on the ideal press (closed form),
with two different drives; one test runs a scenario's rigid design (seconds)."""

import json

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

import pressocp as po  # noqa: E402
from pressocp.cli import main  # noqa: E402
from pressocp.jobs import simulate_job  # noqa: E402

#: Two motors behind different gears (SI).
DRIVE_A = {"drive.gear_ratio": 10.0, "drive.peak_torque": 40.0, "drive.continuous_torque": 15.0, "drive.max_speed": 314.0}
DRIVE_B = {"drive.gear_ratio": 16.0, "drive.peak_torque": 25.0, "drive.continuous_torque": 10.0, "drive.max_speed": 420.0}


def scenario(spm: float, drive: dict) -> po.Scenario:
    """press60 on the ideal press at `spm` strokes/min with `drive`."""
    return po.Scenario.load("press60").with_overrides({"model.clearance": [], "problem.stroke_rate_spm": spm, **drive})


def constant(spm: float, drive: dict, out):
    """The simulate job of the constant crank speed at `spm` into `out`."""
    return simulate_job(scenario(spm, drive), out, po.FourierSpeed.constant(60.0 / spm), "constant speed")


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    """Two simulate results folders: A at 60 spm with motor A, B at 75 spm with motor B."""
    a, b = tmp_path_factory.mktemp("a"), tmp_path_factory.mktemp("b")
    constant(60, DRIVE_A, a)
    constant(75, DRIVE_B, b)
    return a, b


@pytest.fixture(scope="module")
def compared(folders, tmp_path_factory):
    """``pressocp compare A B -o OUT`` of the two folders: exit code and folder."""
    out = tmp_path_factory.mktemp("cmp") / "compare"
    return main(["compare", str(folders[0]), str(folders[1]), "-o", str(out), "-q"]), out


def summaries(folders) -> list[dict]:
    return [json.loads((f / "summary.json").read_text()) for f in folders]


def test_the_table_holds_every_sizing_figure_of_both_with_the_ratio(folders, compared):
    code, out = compared
    assert code == 0
    table = pd.read_csv(out / "compare.csv").set_index("figure")
    sa, sb = summaries(folders)
    crank = ("peak_torque_N_m", "peak_slider_normal_force_N", "peak_crank_pin_force_N", "peak_wrist_pin_force_N",
             "max_ram_speed_error", "stroke_rate_spm")
    for key in crank:
        assert table.loc[key, "A"] == pytest.approx(sa[key], rel=1e-9)
        assert table.loc[key, "B"] == pytest.approx(sb[key], rel=1e-9)
        assert table.loc[key, "B/A"] == pytest.approx(sb[key] / sa[key], rel=1e-8)
    assert table.loc["stroke_rate_spm", "B/A"] == pytest.approx(75 / 60)
    motor = ("peak_torque", "rms_torque", "peak_torque_margin", "rms_margin", "max_speed", "speed_margin",
             "inertia_ratio", "peak_power", "energy_driving", "energy_regenerated", "bus_energy_swing")
    for key in motor:
        assert table.loc[f"motor_{key}", "A"] == pytest.approx(sa["drive"]["speed"][key], rel=1e-9)
        assert table.loc[f"motor_{key}", "B"] == pytest.approx(sb["drive"]["speed"][key], rel=1e-9)
    # the motors' top speeds: i x the crank's largest speed, each behind its own gear
    assert table.loc["motor_max_speed", "B/A"] > 16 / 10 * 75 / 60 * 0.5
    assert list(table.columns) == ["label", "unit", "A", "B", "B/A"]


def test_the_rms_crank_torque_is_the_cycle_mean_square_of_the_results(folders, compared):
    """Checked with numpy's mean over the (uniform) samples of results.csv, not the trapezoid."""
    _, out = compared
    table = pd.read_csv(out / "compare.csv").set_index("figure")
    for side, folder in zip("AB", folders):
        tau = pd.read_csv(folder / "results.csv")["speed torque [N m]"].to_numpy()
        assert table.loc["rms_torque_N_m", side] == pytest.approx(np.sqrt(np.mean(tau**2)), rel=2e-3)


def test_the_figures_and_the_report_are_written(compared):
    _, out = compared
    for png in ("compare.png", "motor.png"):
        assert (out / png).stat().st_size > 20_000
    report = (out / "report.txt").read_text(encoding="utf-8")
    assert report.startswith("A: ") and "peak motor torque, N m" in report and "B/A" in report
    assert set(json.loads((out / "manifest.json").read_text())["files"]) == {
        "compare.csv", "compare.png", "motor.png", "report.txt"}


def test_a_speed_file_is_simulated_on_the_scenario_like_the_folder(folders, tmp_path):
    """The folder against its own speed.json simulated on its scenario (a TOML file): the same
    design twice, so every ratio is 1."""
    toml = tmp_path / "a.toml"
    toml.write_text(scenario(60, DRIVE_A).to_toml(), encoding="utf-8")
    out = tmp_path / "cmp"
    assert main(["compare", str(folders[0]), str(folders[0] / "speed.json"), "--scenario", str(toml),
                 "-o", str(out), "-q"]) == 0
    table = pd.read_csv(out / "compare.csv").set_index("figure")
    assert "motor_rms_torque" in table.index and len(table) >= 15
    np.testing.assert_allclose(table["B/A"].dropna(), 1.0, rtol=1e-6)


@pytest.mark.slow  # 12-22 s; a simulated side by default: the speed-file test above
def test_a_scenario_is_its_rigid_design_simulated(folders, tmp_path, capsys):
    """A scenario file against a folder: the scenario's rigid design is simulated on its model (the
    simulate job, whose summary names the speed) and compared figure by figure."""
    toml = tmp_path / "a.toml"
    toml.write_text(scenario(60, DRIVE_A).to_toml(), encoding="utf-8")
    out = tmp_path / "cmp"
    assert main(["compare", str(toml), str(folders[0]), "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert f"A: {toml} (simulate;" in printed and "rigid design)" in printed and f"B: {folders[0]}" in printed
    table = pd.read_csv(out / "compare.csv").set_index("figure")
    assert table.loc["stroke_rate_spm", "B/A"] == 1.0 and "motor_peak_torque" in table.index
    # the design holds the ram speed in its window, the constant speed does not
    assert table.loc["max_ram_speed_error", "A"] < 0.01 < table.loc["max_ram_speed_error", "B"]


def test_without_a_drive_on_both_sides_there_is_no_motor_figure(folders, tmp_path):
    plain = tmp_path / "plain"
    plain.mkdir()
    constant(60, {}, plain)
    out = tmp_path / "cmp"
    assert main(["compare", str(plain), str(folders[1]), "-o", str(out), "-q"]) == 0
    table = pd.read_csv(out / "compare.csv")
    assert not table["figure"].str.startswith("motor_").any() and "peak_torque_N_m" in set(table["figure"])
    assert not (out / "motor.png").exists() and (out / "compare.png").is_file()


@pytest.mark.parametrize("which, make", [
    ("A", lambda tmp, good: [str(tmp / "no_such_folder"), str(good)]),
    ("B", lambda tmp, good: [str(good), str(tmp / "empty")]),
    ("B", lambda tmp, good: [str(good), str(tmp / "missing.json")]),
    ("A", lambda tmp, good: [str(tmp / "empty" / "x.csv"), str(good)]),
])
def test_a_bad_argument_exits_2_naming_it(folders, tmp_path, capsys, which, make):
    (tmp_path / "empty").mkdir()
    argv = make(tmp_path, folders[0])
    bad = argv[0 if which == "A" else 1]
    assert main(["compare", *argv, "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{which} {bad}" in err and err.startswith("pressocp: error:")
    assert not (tmp_path / "out").exists()  # nothing written


def test_a_folder_of_another_job_is_refused(folders, tmp_path, capsys):
    other = tmp_path / "impacts"
    other.mkdir()
    (other / "summary.json").write_text(json.dumps({"job": "impacts"}))
    (other / "results.csv").write_text("t [s]\n0\n")
    assert main(["compare", str(folders[0]), str(other), "-o", str(tmp_path / "out")]) == 2
    assert f"B {other}: a 'impacts' job's folder" in capsys.readouterr().err
