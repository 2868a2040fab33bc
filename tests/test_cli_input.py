"""Bad scenario files and arguments: exit code 2, one message that names the key, nothing solved."""

import json
import os

import pytest

from pressocp.cli import main, parse_set
from pressocp.scenario import Scenario

GOOD = """
name = "my press"
[press]
crank_radius = 0.08
rod_length = 0.40
slider_mass = 600.0
[press.crank_pin]
clearance = 1.5e-4
[press.wrist_pin]
clearance = 1.5e-4
[problem]
stroke_rate_spm = 50
ram_speed = -0.12
window = [0.6, 0.25]
"""

# (what is wrong, TOML text appended to / replacing GOOD, words the message must contain)
BAD_FILES = [
    ("unknown key, with suggestion", GOOD.replace("stroke_rate_spm = 50", "stroke_rate = 50"),
     ["problem.stroke_rate", "stroke_rate_spm"]),
    ("unknown table", GOOD + "[solvers]\njit = true\n", ["solvers", "solver"]),
    ("wrong type", GOOD.replace("ram_speed = -0.12", 'ram_speed = "fast"'), ["problem.ram_speed", "a number"]),
    ("clearance in mm", GOOD.replace("clearance = 1.5e-4\n[press.wrist", "clearance = 0.15\n[press.wrist"),
     ["crank_pin.clearance", "0.15", "0.00015 m"]),
    ("crank radius in mm", GOOD.replace("crank_radius = 0.08", "crank_radius = 80"), ["crank_radius", "80", "mm"]),
    ("mass in grams", GOOD.replace("slider_mass = 600.0", "slider_mass = 600000.0"), ["slider_mass", "600000"]),
    ("rod shorter than crank", GOOD.replace("rod_length = 0.40", "rod_length = 0.06"), ["rod_length", "crank"]),
    ("window reversed", GOOD.replace("window = [0.6, 0.25]", "window = [0.25, 0.6]"), ["window", "0.25"]),
    ("window of one number", GOOD.replace("window = [0.6, 0.25]", "window = 0.6"), ["problem.window", "two numbers"]),
    ("ram speed upward", GOOD.replace("ram_speed = -0.12", "ram_speed = 0.12"), ["ram_speed", "0.12"]),
    ("ram speed the crank cannot deliver", GOOD.replace("ram_speed = -0.12", "ram_speed = -5.0"),
     ["ram_speed", "-5"]),
    ("both cycle keys", GOOD.replace("stroke_rate_spm = 50", "stroke_rate_spm = 50\nperiod_s = 1.2"),
     ["stroke_rate_spm", "period_s"]),
    ("stroke rate negative", GOOD.replace("stroke_rate_spm = 50", "stroke_rate_spm = -50"),
     ["stroke_rate_spm", "-50"]),
    ("unknown objective", GOOD + 'objective = "peak_torq"\n', ["objective", "peak_torq", "peak_torque"]),
    ("unknown rod", GOOD + '[model]\nrod = "flex"\n', ["rod", "flex"]),
    ("unknown joint", GOOD + '[model]\nclearance = ["crank"]\n', ["clearance", "crank"]),
    ("unknown transcription", GOOD + '[solver]\ntranscription = "ipopt"\n', ["solver.transcription", "ipopt"]),
    ("solver tolerance NaN", GOOD + '[solver]\nverify_rtol = nan\n', ["verify_rtol", "nan"]),
    ("solver tolerance zero", GOOD + '[solver]\nverify_rtol = 0.0\n', ["verify_rtol", "[1e-14, 1e-05]"]),
    ("negative elements", GOOD + '[solver]\nelements = -5\n', ["elements", "-5"]),
    ("jit as a word", GOOD + '[solver]\njit = "yes"\n', ["jit", "'yes'"]),
    ("flexible backoff over 1", GOOD + '[solver]\nflexible_backoffs = [0.9, 1.2]\n', ["flexible_backoffs", "[0.001, 1]", "1.2"]),
    ("flexible backoffs as a number", GOOD + '[solver]\nflexible_backoffs = 0.9\n', ["flexible_backoffs", "list"]),
    ("malformed TOML", GOOD.replace("slider_mass = 600.0", "slider_mass = 600.0 kg"), ["TOML", "line"]),
    ("a table given a value", GOOD.replace("[press.wrist_pin]\nclearance = 1.5e-4", "").replace(
        "[problem]", "[problem]") + "", None),  # placeholder replaced below
]
BAD_FILES[-1] = ("a bearing given as a number", GOOD.replace("[press.crank_pin]\nclearance = 1.5e-4\n", "").replace(
    "slider_mass = 600.0", "slider_mass = 600.0\ncrank_pin = 0.04"), ["press.crank_pin", "table"])


@pytest.mark.parametrize("what, text, words", BAD_FILES, ids=[b[0] for b in BAD_FILES])
def test_bad_scenario_file_exits_2(tmp_path, capsys, what, text, words):
    path = tmp_path / "my.toml"
    path.write_text(text)
    assert main(["optimize", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pressocp: error:") and err.count("\n") == 1 and "Traceback" not in err
    for w in words:
        assert w in err, (what, err)
    assert not (tmp_path / "out").exists()  # failed before anything ran


BAD_ARGS = [
    ("missing file", ["optimize", "{tmp}/nothing.toml"], ["nothing.toml", "no such scenario file"]),
    ("unknown bundled name", ["optimize", "press7"], ["press7"]),
    ("--set unknown key", ["design", "--set", "problem.stroke=60"], ["problem.stroke", "stroke_rate_spm"]),
    ("--set wrong type", ["design", "--set", "problem.stroke_rate_spm=fast"], ["problem.stroke_rate_spm", "a number"]),
    ("--set without =", ["design", "--set", "problem.stroke_rate_spm"], ["--set", "KEY=VALUE"]),
    ("--set mm clearance", ["design", "--set", "press.wrist_pin.clearance=0.1"], ["wrist_pin.clearance", "0.1"]),
    ("--speed missing", ["simulate", "--speed", "{tmp}/speed.json"], ["--speed", "speed.json"]),
    ("--speed not JSON", ["simulate", "--speed", "{tmp}/notjson.json"], ["--speed", "not JSON"]),
    ("--speed wrong period", ["simulate", "--speed", "{tmp}/speed1s.json"], ["period", "1", "0.8"]),
    ("--out is a file", ["design", "--out", "{tmp}/afile"], ["--out", "afile"]),
    ("scenario new over a file", ["scenario", "new", "{tmp}/afile"], ["exists", "--force"]),
    ("--vary without =", ["sweep", "--vary", "slider_mass"], ["--vary", "KEY=START:STOP:N"]),
    ("--vary count not a number", ["sweep", "--vary", "slider_mass=100:200:x"], ["--vary", "START:STOP:N"]),
    ("--vary unknown key", ["sweep", "--vary", "slider_mas=100,200"], ["slider_mas", "slider_mass"]),
    ("--vary implausible value", ["sweep", "--vary", "wrist_pin.clearance=1e-4,0.1"],
     ["wrist_pin.clearance", "0.1"]),
    ("--path of unequal lists", ["sweep", "--path", "--vary", "slider_mass=100,200", "--vary",
                                 "problem.stroke_rate_spm=60,70,80"], ["--path", "same length"]),
    ("--speed with an optimize sweep", ["sweep", "--vary", "slider_mass=100,200", "--speed", "{tmp}/speed1s.json"],
     ["--speed", "simulate"]),
    ("--along not a --vary key", ["sweep", "--vary", "slider_mass=100,200", "--along", "rod_mass"],
     ["--along", "'rod_mass'", "slider_mass"]),
    ("--along on a path", ["sweep", "--path", "--vary", "slider_mass=100,200", "--along", "slider_mass"],
     ["--along", "--path"]),
    ("--along of a simulate sweep", ["sweep", "--task", "simulate", "--vary", "slider_mass=100,200", "--along",
                                     "slider_mass"], ["--along", "optima", "simulate"]),
    ("--segment 0", ["sweep", "--vary", "slider_mass=100,200", "--along", "slider_mass", "--segment", "0"],
     ["Continuation.segment", "0"]),
    ("--segment without --along", ["sweep", "--vary", "slider_mass=100,200", "--segment", "3"],
     ["--segment 3", "--along"]),
    ("sweep.csv of another run", ["sweep", "--vary", "slider_mass=100,200", "--out", "{tmp}/done"],
     ["sweep.csv", "--resume"]),
    ("--speed with more harmonics than the problem", ["simulate", "--speed", "{tmp}/speed20.json"],
     ["--speed", "20 harmonics", "problem.n_harmonics=20"]),
    ("--speed that turns the crank back", ["simulate", "--speed", "{tmp}/backwards.json"],
     ["--speed", "falls to", "turns back"]),
    ("binary scenario file", ["optimize", "{tmp}/binary.toml"], ["binary.toml", "not a text scenario file"]),
    ("--out under a file", ["optimize", "--out", "{tmp}/afile/out"], ["--out", "afile", "is a file"]),
    ("scenario new under a file", ["scenario", "new", "{tmp}/afile/my.toml"], ["scenario new", "is a file"]),
    ("scenario new onto a pipe", ["scenario", "new", "{tmp}/fifo", "--force"], ["scenario new", "fifo",
                                                                              "not a regular file"]),
    ("scenario new through a link to a folder", ["scenario", "new", "{tmp}/dirlink", "--force"],
     ["dirlink", "a folder", "not a regular file"]),
    ("the cycle set twice", ["design", "--set", "problem.stroke_rate_spm=40", "--set", "problem.period_s=2"],
     ["problem.stroke_rate_spm and problem.period_s", "one of them"]),
    ("a key set twice", ["design", "--set", "slider_mass=100", "--set", "slider_mass=200"],
     ["--set slider_mass", "twice"]),
    ("a mass in grams, --strict", ["design", "--strict", "--set", "rod_mass=3140"], ["rod_mass", "a value in g?"]),
    ("a speed limit in rpm, --strict", ["design", "--strict", "--set", "problem.omega_max=400"],
     ["omega_max", "in rpm?"]),
]


@pytest.mark.parametrize("what, argv, words", BAD_ARGS, ids=[b[0] for b in BAD_ARGS])
def test_bad_arguments_exit_2(tmp_path, capsys, what, argv, words):
    (tmp_path / "notjson.json").write_text("{period: 1")
    (tmp_path / "speed1s.json").write_text(json.dumps({"period": 1.0, "a": [0.1], "b": [0.0]}))
    (tmp_path / "backwards.json").write_text(json.dumps({"period": 0.8, "a": [10.0], "b": [0.0]}))
    (tmp_path / "binary.toml").write_bytes(bytes(range(128, 256)))
    (tmp_path / "speed20.json").write_text(json.dumps({"period": 0.8, "a": [0.01] * 20, "b": [0.0] * 20}))
    (tmp_path / "afile").write_text("x")
    (tmp_path / "done").mkdir()
    (tmp_path / "done" / "sweep.csv").write_text("slider_mass,ok\n100,True\n")
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "dirlink").symlink_to(tmp_path / "done")
    assert main([a.replace("{tmp}", str(tmp_path)) for a in argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("pressocp: error:") and "Traceback" not in err
    for w in words:
        assert w in err, (what, err)


def test_unknown_option_is_argparse_exit_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["design", "--perod", "1"])
    assert exc.value.code == 2 and "--perod" in capsys.readouterr().err


def test_set_values_are_toml():
    assert parse_set(["problem.stroke_rate_spm=60", "problem.window=[0.6, 0.25]", "model.rod=flexible",
                      'name="x y"', "solver.jit=false"]) == {
        "problem.stroke_rate_spm": 60, "problem.window": [0.6, 0.25], "model.rod": "flexible", "name": "x y",
        "solver.jit": False}


def test_template_is_a_valid_commented_scenario(tmp_path, capsys):
    path = tmp_path / "my.toml"
    assert main(["scenario", "new", str(path)]) == 0
    text = path.read_text()
    assert "# m, radial" in text and "stroke_rate_spm" in text
    assert Scenario.load(path) == Scenario.load("press75").with_overrides({"name": Scenario.load(path).name})


def test_scenario_show_applies_overrides(capsys):
    assert main(["scenario", "show", "press75", "--set", "problem.stroke_rate_spm=60"]) == 0
    shown = Scenario.from_toml(capsys.readouterr().out)
    assert shown.problem.period == pytest.approx(1.0)
    assert shown.press == Scenario.load("press75").press


def test_a_flagged_result_says_why():
    """The exit-1 message names what failed, not IPOPT's success status."""
    from pressocp.summaries import flag_reason

    base = {"converged": True, "verified": False, "periodic": True, "status": "Solve_Succeeded",
            "max_ram_speed_violation_m_s": 2e-5}
    assert flag_reason(base) == "not verified: the ram speed leaves its tolerance by 2e-05 m/s"
    assert flag_reason({**base, "periodic": "not searched: impacts", "max_ram_speed_violation_m_s": 0.0}) == \
        "not verified: the re-simulation is not periodic (not searched: impacts)"
    assert flag_reason({**base, "converged": False, "status": "Maximum_Iterations_Exceeded"}) == \
        "not converged (Maximum_Iterations_Exceeded)"
    assert "Solve_Succeeded" not in flag_reason(base)
    assert flag_reason({"job": "rate", "converged": False, "status": "no rate tried held every limit"}) == \
        "no rate tried held every limit"


def test_an_output_folder_holds_one_run(tmp_path, capsys):
    """A run replaces the previous run's files (a folder written before manifests: those its
    summary.json lists, never a path out of the folder); other files stay. While a run holds the
    folder's lock, a second run into it exits 2 before writing anything, and before it reads its
    input."""
    from filelock import FileLock

    from pressocp.io import LOCK_NAME

    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.json").write_text(json.dumps({"files": ["old.png", "../outside.txt", "summary.json"]}))
    (out / "old.png").write_text("old")
    (out / "mine.txt").write_text("the user's")
    (tmp_path / "outside.txt").write_text("outside")
    with FileLock(str(out / LOCK_NAME)):
        assert main(["design", "--out", str(out), "-q"]) == 2
        assert "being written by another pressocp run" in capsys.readouterr().err
        # refused before the input is read: a scenario that does not exist is not reached
        assert main(["design", "no_such_scenario", "--out", str(out), "-q"]) == 2
        assert "being written by another pressocp run" in capsys.readouterr().err
        assert (out / "old.png").exists()  # nothing touched
    assert main(["design", "--out", str(out), "-q"]) == 0
    assert not (out / "old.png").exists() and (out / "mine.txt").exists() and (tmp_path / "outside.txt").exists()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["job"] == "design" and all((out / f).exists() for f in summary["files"])


def test_a_scenario_written_through_a_link_replaces_its_target_and_keeps_the_link(tmp_path, capsys):
    target = tmp_path / "real.toml"
    target.write_text("old")
    link = tmp_path / "link.toml"
    link.symlink_to(target)
    assert main(["scenario", "new", str(link), "--force"]) == 0
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert Scenario.load(str(link)).name and target.read_text() != "old"


def test_a_result_of_another_press_as_speed_is_simulated_with_a_warning(tmp_path, capsys):
    """A result file designed for another press is accepted as ``--speed`` (a wear study simulates an
    optimum on a changed press) with a warning naming each differing parameter; a plain speed file
    or a result of the same press gives none."""
    from dataclasses import replace

    from pressocp import FourierSpeed
    from pressocp.jobs import press_differences

    scenario = Scenario.load("press75")
    speed = FourierSpeed(scenario.problem.period, [0.0], [0.0], 0.0).to_dict()
    other = scenario.problem.replace(press=replace(scenario.press, slider_mass=200.0))
    (tmp_path / "other.json").write_text(json.dumps({"problem": other.to_dict(), "speed": speed}))
    (tmp_path / "same.json").write_text(json.dumps({"problem": scenario.problem.to_dict(), "speed": speed}))
    (tmp_path / "plain.json").write_text(json.dumps(speed))
    diff = press_differences(tmp_path / "other.json", scenario.press)
    assert diff == ["slider_mass: 200.0 in the file, 150.0 here"]
    assert press_differences(tmp_path / "same.json", scenario.press) == []
    assert press_differences(tmp_path / "plain.json", scenario.press) == []
    from pressocp.cli import warn_other_press  # what `simulate --speed` and `sweep --speed` print first

    capsys.readouterr()
    warn_other_press(str(tmp_path / "other.json"), scenario)
    assert "was designed for another press" in capsys.readouterr().err and "slider_mass: 200.0" in diff[0]
    for quiet in ("same.json", "plain.json"):
        warn_other_press(str(tmp_path / quiet), scenario)
        assert capsys.readouterr().err == ""


def test_atomic_writes_follow_links_and_never_replace_a_device_or_folder(tmp_path):
    from pressocp.io import NotRegularFile, atomic_write

    target = tmp_path / "target.txt"
    target.write_text("old")
    link = tmp_path / "link.txt"
    link.symlink_to(target)
    atomic_write(link, "new")
    assert link.is_symlink() and target.read_text() == "new"
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "folder").mkdir()
    for path in (tmp_path / "fifo", tmp_path / "folder"):
        with pytest.raises(NotRegularFile, match="not a regular file: refusing to replace it"):
            atomic_write(path, "x")
    assert (tmp_path / "folder").is_dir() and not (tmp_path / "fifo").is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fifo", "folder", "link.txt", "target.txt"]


@pytest.mark.slow  # 9-24 s (two processes); also the concurrent case of the benchmark job transaction
def test_a_second_process_on_a_used_out_is_refused_naming_the_first(tmp_path, capsys):
    """Two real processes: one holds ``--out`` (`output_folder`), the command line run into the same
    folder exits 2 before solving, naming the holder's process; once the holder ends, the folder is
    free again."""
    import subprocess
    import sys

    out = tmp_path / "out"
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time\nfrom pressocp.io import output_folder\n"
                               "with output_folder(sys.argv[1]):\n    print('held', flush=True)\n    time.sleep(60)\n",
                               str(out)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        assert main(["design", "--out", str(out), "-q"]) == 2
        err = capsys.readouterr().err
        assert "being written by another pressocp run" in err and f"process {holder.pid} " in err
    finally:
        holder.kill()
        holder.wait()
    assert main(["design", "--out", str(out), "-q"]) == 0
