"""The command line's jobs, end to end on fast scenarios (the full 75 spm main job is a benchmark:
``benchmarks/bench_main_job.py``)."""

import json

import numpy as np
import pandas as pd
import pytest

from pressocp.io import LOCK_NAME, MANIFEST_NAME

from pressocp.cli import main
from pressocp.speed import FourierSpeed

#: Every file the optimise job writes.
OPTIMIZE_FILES = {"summary.json", "results.csv", "speed.json", "result.json", "report.txt", "speed.png",
                  "loads.png"}
SUMMARY_KEYS = {"period_s", "peak_torque_N_m", "initial_peak_torque_N_m", "rigid_peak_torque_N_m", "converged",
                "max_ram_speed_error", "peak_slider_normal_force_N", "initial_peak_slider_normal_force_N",
                "peak_crank_pin_force_N", "initial_peak_crank_pin_force_N", "peak_wrist_pin_force_N",
                "initial_peak_wrist_pin_force_N"}


def no_temporary_files(folder):
    """No hidden file but the folder's lock file (kept: deleting a lock file races with its next user)."""
    return not [p for p in folder.iterdir() if p.name.startswith(".") and p.name != LOCK_NAME]


@pytest.fixture(scope="module")
def rigid_optimum(tmp_path_factory):
    """`pressocp optimize` on the ideal press at 60 spm, 6 harmonics (the rigid stage only, seconds)."""
    out = tmp_path_factory.mktemp("optimum")
    code = main(["optimize", "press75", "--out", str(out), "--quiet", "--set", "model.clearance=[]",
                 "--set", "problem.stroke_rate_spm=60", "--set", "problem.n_harmonics=6"])
    return code, out


def test_optimize_writes_every_file(rigid_optimum):
    code, out = rigid_optimum
    assert code == 0
    assert OPTIMIZE_FILES <= {p.name for p in out.iterdir()} and no_temporary_files(out)
    summary = json.loads((out / "summary.json").read_text())
    assert SUMMARY_KEYS <= set(summary) and summary["converged"] and summary["verified"]
    assert summary["period_s"] == pytest.approx(1.0)
    assert summary["max_ram_speed_error"] <= 0.01
    # on the ideal press the answer is the rigid optimum: the floor itself, below the design's peak
    assert summary["peak_torque_N_m"] == pytest.approx(summary["rigid_peak_torque_N_m"], rel=1e-9)
    assert summary["peak_torque_N_m"] < summary["initial_peak_torque_N_m"]
    assert set(summary["files"]) == {p.name for p in out.iterdir()} - {LOCK_NAME, MANIFEST_NAME}
    assert set(json.loads((out / MANIFEST_NAME).read_text())["files"]) == set(summary["files"])
    for png in ("speed.png", "loads.png"):
        assert (out / png).stat().st_size > 20_000


def test_results_csv_holds_both_speeds_with_units(rigid_optimum):
    _, out = rigid_optimum
    table = pd.read_csv(out / "results.csv")
    assert table.columns[0] == "t [s]" and "initial torque [N m]" in table and "optimum omega [rad/s]" in table
    summary = json.loads((out / "summary.json").read_text())
    assert np.abs(table["optimum torque [N m]"]).max() == pytest.approx(summary["peak_torque_N_m"], rel=1e-6)
    assert np.abs(table["initial torque [N m]"]).max() == pytest.approx(summary["initial_peak_torque_N_m"], rel=1e-6)


def test_simulate_reproduces_the_saved_speed(rigid_optimum, tmp_path, capsys):
    _, out = rigid_optimum
    speed = FourierSpeed.from_dict(json.loads((out / "speed.json").read_text()))
    assert speed.period == pytest.approx(1.0)
    for source in ("speed.json", "result.json"):
        sim_out = tmp_path / source
        code = main(["simulate", "--speed", str(out / source), "--out", str(sim_out), "--set", "model.clearance=[]",
                     "--set", "problem.stroke_rate_spm=60", "--set", "problem.n_harmonics=6"])
        assert code == 0
        a = json.loads((out / "summary.json").read_text())
        b = json.loads((sim_out / "summary.json").read_text())
        for key in ("peak_torque_N_m", "peak_slider_normal_force_N", "peak_wrist_pin_force_N"):
            assert b[key] == pytest.approx(a[key], rel=1e-6)
    assert "peak motor torque" in capsys.readouterr().out


def test_design_job_quietly(tmp_path, capsys):
    assert main(["design", "--quiet", "--out", str(tmp_path)]) == 0
    assert capsys.readouterr().out == ""
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["converged"] and summary["max_ram_speed_error"] < 0.01
    assert (tmp_path / "design.png").stat().st_size > 10_000 and no_temporary_files(tmp_path)
    assert "ram speed error" in (tmp_path / "report.txt").read_text()


def test_flagged_result_is_exit_1(tmp_path, capsys, monkeypatch):
    """A job whose result is written but not converged or not verified exits with 1 and says so."""
    from pressocp import jobs

    def flagged(scenario, out, progress=True):
        return jobs.JobReport("optimize", {"status": "stage 'collocation': Maximum_Iterations_Exceeded"},
                              "report", [], ok=False)

    monkeypatch.setattr(jobs, "optimize_job", flagged)
    assert main(["optimize", "--out", str(tmp_path)]) == 1
    assert "Maximum_Iterations_Exceeded" in capsys.readouterr().err


@pytest.mark.slow
def test_main_job_on_the_75_spm_scenario(tmp_path, capsys, monkeypatch):
    """`pressocp` with no arguments (2.5 min): every file, the table, the 75 spm optimum verified."""
    monkeypatch.chdir(tmp_path)
    assert main([]) == 0
    out = tmp_path / "out"
    assert OPTIMIZE_FILES | {"journals.png"} <= {p.name for p in out.iterdir()} and no_temporary_files(out)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["converged"] and summary["verified"] and summary["max_ram_speed_error"] <= 0.01
    assert summary["peak_torque_N_m"] <= 148.0 and summary["initial_peak_torque_N_m"] > 800.0
    assert "peak motor torque" in capsys.readouterr().out


@pytest.mark.slow  # 20 s; sweeps by default: tests/test_sweep.py
def test_sweep_command_writes_table_and_figure(tmp_path, capsys):
    """``pressocp sweep`` on the ideal press: a 2 x 2 grid of simulations, the table and the figure."""
    out = tmp_path / "sweep"
    code = main(["sweep", "--task", "simulate", "--vary", "slider_mass=100:200:2", "--vary",
                 "wrist_pin.clearance=1e-4,2e-4", "--set", "model.clearance=[]", "--set", "problem.n_harmonics=6",
                 "--workers", "1", "--out", str(out)])
    assert code == 0
    table = pd.read_csv(out / "sweep.csv")
    assert table["slider_mass"].tolist() == [100.0, 100.0, 200.0, 200.0] and table["ok"].all()
    assert (out / "sweep.png").stat().st_size > 20_000 and "peak_torque_N_m" in capsys.readouterr().out
    assert main(["sweep", "--task", "simulate", "--vary", "slider_mass=100:200:2", "--vary",
                 "wrist_pin.clearance=1e-4,2e-4", "--set", "model.clearance=[]", "--set", "problem.n_harmonics=6",
                 "--workers", "1", "--out", str(out), "--resume", "--quiet"]) == 0


def test_long_stage_statuses_go_to_notes_below_the_table():
    """A status longer than the column's width is cut at its first colon or parenthesis and numbered;
    the whole text is a note below the table, once for identical texts."""
    from pressocp.jobs import footnoted

    long = "skipped: the answer's re-simulated ram strays 0.0391 of the tolerance past the 0.95 its NLP holds"
    kept = "Solve_Succeeded (candidate not kept: its answer re-simulates at 145.809 against 145.144)"
    column, notes = footnoted(["Solve_Succeeded", kept, long, kept], width=40)
    assert column == ["Solve_Succeeded", "Solve_Succeeded [1]", "skipped [2]", "Solve_Succeeded [1]"]
    assert notes == [f"[1] {kept}", f"[2] {long}"]
