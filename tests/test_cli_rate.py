"""`pressocp rate`: bad requests exit 2 before any solve; on the ideal press (slow: a few minutes)
the files and the verdict."""

import json

import pytest

from pressocp.cli import main

DRIVE = ["--set", "drive.gear_ratio=10", "--set", "drive.peak_torque=11", "--set", "drive.continuous_torque=7.7",
         "--set", "drive.max_speed=400", "--set", "drive.gear_efficiency=0.95", "--set", "drive.motor_inertia=8e-4"]


def test_rate_without_a_drive_exits_2(tmp_path, capsys):
    assert main(["rate", "press75", "-q", "--out", str(tmp_path / "o")]) == 2
    assert "has no [drive] table" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_rate_with_a_bad_tolerance_exits_2(tmp_path, capsys):
    assert main(["rate", "press75", *DRIVE, "--tolerance-spm", "0", "-q", "--out", str(tmp_path / "o")]) == 2
    assert "tolerance_spm must be" in capsys.readouterr().err


@pytest.mark.slow  # six optimisations on the ideal press: about 2 minutes
def test_rate_on_the_ideal_press_writes_the_search(tmp_path):
    out = tmp_path / "o"
    argv = ["rate", "press75", "--set", "model.clearance=[]", "--set", "problem.n_harmonics=8", "--set",
            "problem.stroke_rate_spm=66", *DRIVE, "--tolerance-spm", "2", "-q", "--out", str(out)]
    assert main(argv) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["job"] == "rate" and summary["best"]["feasible"] and not summary["above"]["feasible"]
    assert {"speed.json", "result.json", "motor.png", "report.txt"} <= {p.name for p in out.iterdir()}


def test_a_long_unverified_reason_is_a_note_not_a_table_cell():
    """The rate table keeps its verdict cells short: an optimum not verified is 'not verified [k]' there,
    its reason (an IPOPT status with the drive's shortfall runs to hundreds of characters) numbered
    under the table; without a note number the reason is inline."""
    from pressocp.jobs import rate_verdict
    from pressocp.stroke_rate import RateTrial

    reason = "not converged (stage 'rigid': Infeasible_Problem_Detected; " + "x" * 300 + ")"
    trial = RateTrial(57.2, False, {"rms_margin": -0.01, "verified": reason}, held=True,
                      unconstrained_failed={"rms_margin": -0.09})
    assert rate_verdict(trial, 2) == ("failed: rms_margin, not verified [2] (limits in the NLP; unconstrained: "
                                      "rms_margin)")
    assert reason in rate_verdict(trial)
    assert rate_verdict(RateTrial(50.0, True, {})) == "held"
