"""A job or sweep row is ``ok`` only when its responses are periodic steady states where asked, and
a sweep's figure shows its points. The impacts study is run once on press60 (its responses are
periodic); a copy whose designed-speed response is marked "no periodic state" stands for a failed
periodic search."""

from __future__ import annotations

import copy
import json

import numpy as np
import pandas as pd
import pytest

import pressocp as po
from pressocp import impacts, plots, sweeps
from pressocp.cli import main


@pytest.fixture(scope="module")
def study():
    s = po.Scenario.load("press60")
    return s, impacts.impact_study(s.problem, s.model, rtol=s.solver.verify_rtol)


def failed_search(st):
    broken = copy.deepcopy(st)
    broken.designed.stats["periodic"] = {"found": False, "reason": "no periodic state in 40 cycles (test)"}
    return broken


def test_the_impacts_job_is_ok_only_with_periodic_responses(study, tmp_path, monkeypatch):
    scenario, st = study
    assert st.not_periodic() == {}
    monkeypatch.setattr(impacts, "impact_study", lambda *a, **k: st)
    assert main(["impacts", "press60", "--out", str(tmp_path / "good"), "--quiet"]) == 0
    monkeypatch.setattr(impacts, "impact_study", lambda *a, **k: failed_search(st))
    assert main(["impacts", "press60", "--out", str(tmp_path / "bad"), "--quiet"]) == 1  # ran, not verified
    summary = json.loads((tmp_path / "bad" / "summary.json").read_text())
    assert summary["periodic"] == {"constant": True, "designed": "no periodic state in 40 cycles (test)"}
    assert "not periodic: the designed speed's response" in (tmp_path / "bad" / "report.txt").read_text()


def test_an_impacts_sweep_row_is_not_ok_after_a_failed_periodic_search(study, monkeypatch):
    scenario, st = study
    monkeypatch.setattr(impacts, "impact_study", lambda *a, **k: st)
    assert sweeps.run_point("impacts", scenario)["ok"] is True
    monkeypatch.setattr(impacts, "impact_study", lambda *a, **k: failed_search(st))
    row = sweeps.run_point("impacts", scenario)
    assert row["ok"] is False and "not periodic" in row["error"] and "designed" in row["error"]


@pytest.mark.slow  # 29 s (two impact studies)
def test_the_impacts_sweep_figure_has_its_points(tmp_path):
    """``pressocp sweep --task impacts`` on two stroke rates: both rows ok, and every panel of the
    figure drawn from sweep.csv has a line through both points."""
    out = tmp_path / "sweep"
    assert main(["sweep", "press60", "--task", "impacts", "--vary", "problem.stroke_rate_spm=55,60",
                 "--out", str(out), "--quiet"]) == 0
    table = pd.read_csv(out / "sweep.csv")
    assert table["ok"].astype(bool).all() and (out / "sweep.png").stat().st_size > 0
    fig = plots.plot_sweep(table, ["problem.stroke_rate_spm"])
    for ax in fig.axes:
        drawn = [line for line in ax.get_lines() if np.isfinite(np.asarray(line.get_ydata(), float)).sum() == 2]
        assert drawn, ax.get_ylabel()
        assert sorted(drawn[0].get_xdata()) == [55, 60]
