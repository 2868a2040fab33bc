"""`Strategy.regridded`: a target stage whose NLP objective is far from its re-simulation's is solved
again from its own start on the finer grid, not refined from its answer."""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import pytest

import pressocp.ocp.strategy as strategy_module
from pressocp import WarmStart
from pressocp.ocp import Transcription
from pressocp.ocp.stage import StageResult
from pressocp.ocp.strategy import Strategy
from pressocp.speed import FourierSpeed

SPEED = FourierSpeed(1.0, np.array([2 * np.pi]), np.zeros(1))
#: The stand-in NLP's objective per grid; every answer re-simulates at 1.2 (10 elements: 16.7 % off,
#: 20: 4.2 %, 40: 0.8 %).
NLP_OBJECTIVE = {10: 1.0, 20: 1.15, 40: 1.19}
RESIMULATED = 1.2


@dataclass(frozen=True)
class Doubling(Transcription):
    """A stand-in transcription: its grid doubles up to 40 elements; it records every solve."""

    elements: int = 10
    calls: tuple = ()

    def refined(self, period, rod="rigid", where=None):
        return Doubling(2 * self.elements, self.calls) if self.elements < 40 else None

    def solve(self, problem, model, start, name="target", progress=False):
        self.calls[0].append((name, self.elements, start))
        return StageResult(name=name, transcription="Doubling", model="m", success=True, status="Solve_Succeeded",
                           iterations=1, wall_time=0.0, objective=NLP_OBJECTIVE[self.elements], speed=SPEED,
                           last_speed=SPEED, t1=0.0)


@pytest.fixture
def stand_ins(monkeypatch):
    monkeypatch.setattr(Strategy, "verify_stage", lambda self, model, stage: SimpleNamespace())
    monkeypatch.setattr(strategy_module, "is_periodic", lambda sim: True)
    problem = SimpleNamespace(period=1.0, objective_value=lambda sim: RESIMULATED)
    return problem, SimpleNamespace(rod="rigid")


def run(strategy: Strategy, stand_ins) -> tuple[list[StageResult], Transcription, list]:
    problem, model = stand_ins
    calls: list = []
    coarse = Doubling(10, (calls,))
    start = WarmStart(SPEED)
    first = coarse.solve(problem, model, start, "target")
    stages, last = strategy.regridded(problem, model, coarse, coarse, [first], start, False)
    return stages, last, [(name, elements, s is start) for name, elements, s in calls]


def test_a_target_far_from_its_resimulation_is_solved_again_from_its_start_on_finer_grids(stand_ins):
    stages, last, calls = run(Strategy(), stand_ins)
    # 16.7 % off on 10 elements, 4.2 % on 20: within the default 5 %, so it stops there
    assert calls == [("target", 10, True), ("target_regrid_1", 20, True)]
    assert [(s.name, bool(s.superseded)) for s in stages] == [("target", True), ("target_regrid_1", False)]
    assert "16.7 % from its re-simulation's 1.2" in stages[0].superseded
    assert stages[-1].details["regridded"] == stages[0].superseded
    assert last.elements == 20


def test_a_tighter_gap_goes_on_to_the_finest_grid_and_none_never_regrids(stand_ins):
    stages, last, calls = run(Strategy(grid_tol=0.005, regrid_gap=0.01), stand_ins)
    assert [c[:2] for c in calls] == [("target", 10), ("target_regrid_1", 20), ("target_regrid_2", 40)]
    assert all(c[2] for c in calls)  # every one from the stage's own start, not the last answer
    assert [bool(s.superseded) for s in stages] == [True, True, False] and last.elements == 40
    stages, last, calls = run(Strategy(regrid_gap=None), stand_ins)
    assert [c[:2] for c in calls] == [("target", 10)] and not stages[0].superseded and last.elements == 10


def test_a_regrid_gap_not_above_the_grid_tolerance_is_refused_by_name():
    with pytest.raises(ValueError, match="regrid_gap"):
        Strategy(grid_tol=0.02, regrid_gap=0.02)
