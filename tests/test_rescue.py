"""What the stage chain does when a stage on the clearance model does not converge: from a
no-reversal start whose journals leave their walls, it raises the no-reversal margin and runs the
chain again from there; otherwise (or when no raise is left) it solves the same NLP again with the
KKT matrix scaled (`Transcription.rescaled`). The chain logic is checked here with stand-in
transcriptions (no IPOPT); the forming press on which the raise was needed runs in
`benchmarks/bench_forming.py`."""

from __future__ import annotations

from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np
import pytest

import pressocp as po
from pressocp.ocp import Transcription
from pressocp.ocp.stage import Check, StageResult
from pressocp.ocp.strategy import MARGIN_FACTOR, RAISE_AHEAD, Strategy, loses_contact


def stage(name: str, success: bool, speed: po.FourierSpeed) -> StageResult:
    return StageResult(name=name, transcription="stand-in", model="stand-in", success=success,
                       status="Solve_Succeeded" if success else "Maximum_Iterations_Exceeded", iterations=1,
                       wall_time=0.0, objective=1.0, speed=speed, last_speed=speed, t1=0.0)


def speed_of(value: float) -> po.FourierSpeed:
    return po.FourierSpeed.from_coefficients(1.0, [value, 0.0])


@dataclass(frozen=True)
class Stubborn(Transcription):
    """Converges only rescaled, or only from the speeds in `converges_from` (when given)."""

    scaled: bool = False
    converges_from: tuple[float, ...] = ()
    min_eccentricity: float = 1.0

    def solve(self, problem, model, start, name="target", progress=False):
        ok = float(start.speed.a[0]) in self.converges_from if self.converges_from else self.scaled
        return stage(name, ok, start.speed)

    def rescaled(self):
        return None if self.scaled else replace(self, scaled=True)


def test_collocation_rescaled_turns_mumps_scaling_on_once():
    tr = po.Collocation()
    assert tr.rescaled().ipopt["ipopt.mumps_scaling"] == 77
    assert tr.rescaled().rescaled() is None
    assert po.Collocation(ipopt={"ipopt.mumps_scaling": 0}).rescaled() is None  # the user chose
    assert po.Rigid().rescaled() is None and po.MultipleShooting().rescaled() is None


def test_a_stage_that_does_not_converge_is_solved_again_rescaled_from_the_same_start():
    start = po.ocp.WarmStart(speed_of(3.0))
    stages, tr = Strategy.rescued(None, None, Stubborn(), start, "target", False)
    assert [s.name for s in stages] == ["target", "target_rescaled"]
    assert not stages[0].success and "target_rescaled solved it again" in stages[0].superseded
    assert stages[1].success and not stages[1].superseded and tr.scaled
    assert stages[1].speed is start.speed  # the same start
    converged, tr = Strategy.rescued(None, None, Stubborn(scaled=True), start, "target", False)
    assert [s.name for s in converged] == ["target"] and tr == Stubborn(scaled=True)


class MarginRigid(po.Rigid):
    """A rigid transcription stand-in: the no-reversal answer's speed is its margin (from the held
    problem's min_tension), so a check and a target stage can tell which margin they got."""

    def solve(self, problem, model, start, name="rigid", progress=False):
        low = problem.replace(min_tension=None).static_tension[0]
        margin = 0.0 if problem.min_tension is None else problem.min_tension / low
        return stage(name, True, speed_of(round(margin, 6)))


#: The stand-ins' journals below a margin of 0.1: grazing their walls (raised after a failed target
#: stage), unless a test sets ``OFF_WALL["min"]`` below `RAISE_AHEAD` (raised before it).
OFF_WALL = {"min": 0.995}


@pytest.fixture
def margin_chain(monkeypatch):
    """(problem, strategy, rigid stage, clearance model) for `Strategy.clearance_chain` with stand-ins:
    each stage's check says its journals leave their walls below a margin of 0.1 (|e|/c down to
    ``OFF_WALL["min"]``)."""
    problem = po.SpeedProblem(po.PressParams(), period=1.0)
    assert problem.reversal_side() == "tension"
    monkeypatch.setitem(OFF_WALL, "min", 0.995)

    def check(self, model, st, problem):
        margin = float(st.speed.a[0])
        return Check(model="stand-in", objective=1.0, ratio=1.0 - margin, periodic=True, ram_speed_violation=0.0,
                     peak_torque=1.0, verified=False, min_eccentricity=OFF_WALL["min"] if margin < 0.1 else 1.01)

    monkeypatch.setattr(Strategy, "check", check)
    strategy = Strategy(rigid=MarginRigid(), polish_rounds=0, workers=1)
    rigid = stage("rigid", True, speed_of(-1.0))
    rigid.check = Check(model="stand-in", objective=1.0, ratio=2.0, periodic=True, ram_speed_violation=0.0,
                        peak_torque=1.0, verified=False, min_eccentricity=0.5)
    base = SimpleNamespace(rod="rigid")  # the clearance model: only the stand-ins see it
    return problem, strategy, rigid, base


def test_the_margin_is_raised_when_the_target_fails_from_a_start_that_leaves_the_walls(margin_chain):
    problem, strategy, rigid, base = margin_chain
    target = Stubborn(scaled=True, converges_from=(0.1,))
    stages = strategy.clearance_chain(problem, base, rigid, target, None, False, 0.05)
    assert [s.name for s in stages] == ["no_reversal", "target", "no_reversal_raised_1", "target"]
    assert stages[2].details["tension_margin"] == pytest.approx(0.05 * MARGIN_FACTOR)
    assert all("the chain ran again from the no-reversal stage at tension margin 0.1" in s.superseded
               for s in stages[:2])
    assert stages[-1].success and not stages[-1].superseded and not stages[2].superseded
    # a start that keeps its journals on the walls is not raised: the failure stands
    never = Stubborn(scaled=True, converges_from=(7.0,))
    stages = strategy.clearance_chain(problem, base, rigid, never, None, False, 0.1)
    assert [s.name for s in stages] == ["no_reversal", "target"] and not stages[-1].success
    # at most MARGIN_RAISES raises, then the last failure is the answer's status
    stages = strategy.clearance_chain(problem, base, rigid, never, None, False, 0.02)
    assert [s.name for s in stages] == ["no_reversal", "target", "no_reversal_raised_1", "target",
                                        "no_reversal_raised_2", "target"]
    assert not stages[-1].success and not stages[-1].superseded


class FailingRaise(MarginRigid):
    """`MarginRigid` whose raised no-reversal stages do not converge."""

    def solve(self, problem, model, start, name="rigid", progress=False):
        st = super().solve(problem, model, start, name, progress)
        return stage(name, False, st.speed) if name.startswith("no_reversal_raised") else st


@dataclass(frozen=True)
class Rescuable(Stubborn):
    """Converges rescaled, and from the speeds in `converges_from`."""

    def solve(self, problem, model, start, name="target", progress=False):
        return stage(name, self.scaled or float(start.speed.a[0]) in self.converges_from, start.speed)


def test_a_start_that_leaves_the_walls_is_raised_not_rescaled_until_no_raise_is_left(margin_chain):
    problem, strategy, rigid, base = margin_chain
    # off the walls at 0.05: raised to 0.1, where the target converges; no rescaled re-solve ran
    stages = strategy.clearance_chain(problem, base, rigid, Rescuable(converges_from=(0.1,)), None, False, 0.05)
    assert [s.name for s in stages] == ["no_reversal", "target", "no_reversal_raised_1", "target"]
    assert stages[-1].success
    # off the walls at 0.02, 0.04 and 0.08: after the last raise the target is rescued
    stages = strategy.clearance_chain(problem, base, rigid, Rescuable(converges_from=(7.0,)), None, False, 0.02)
    assert [s.name for s in stages] == ["no_reversal", "target", "no_reversal_raised_1", "target",
                                        "no_reversal_raised_2", "target", "target_rescaled"]
    assert stages[-1].success and "target_rescaled solved it again" in stages[-2].superseded
    # on the walls at 0.1: rescued, not raised
    stages = strategy.clearance_chain(problem, base, rigid, Rescuable(converges_from=(7.0,)), None, False, 0.1)
    assert [s.name for s in stages] == ["no_reversal", "target", "target_rescaled"] and stages[-1].success


def test_a_start_far_off_the_walls_is_raised_before_the_target_stage(margin_chain):
    problem, strategy, rigid, base = margin_chain
    OFF_WALL["min"] = RAISE_AHEAD - 0.04
    stages = strategy.clearance_chain(problem, base, rigid, Stubborn(scaled=True, converges_from=(0.1,)), None,
                                      False, 0.05)
    assert [s.name for s in stages] == ["no_reversal", "no_reversal_raised_1", "target"]
    assert "ran again at tension margin 0.1 before the target stage" in stages[0].superseded
    assert stages[-1].success and not stages[-1].superseded and not stages[1].superseded
    # at most MARGIN_RAISES raises ahead, then the target stage from the last start, rescued when it can be
    stages = strategy.clearance_chain(problem, base, rigid, Rescuable(converges_from=(7.0,)), None, False, 0.02)
    assert [s.name for s in stages] == ["no_reversal", "no_reversal_raised_1", "no_reversal_raised_2", "target",
                                        "target_rescaled"]
    assert stages[-1].success and stages[2].details["tension_margin"] == pytest.approx(0.08)
    # a raise that does not converge: the target stage runs from the start there was, and no raise follows it
    failing = replace(strategy, rigid=FailingRaise())
    stages = failing.clearance_chain(problem, base, rigid, Rescuable(converges_from=(0.05,)), None, False, 0.05)
    assert [s.name for s in stages] == ["no_reversal", "no_reversal_raised_1", "target"]
    assert "did not converge" in stages[1].superseded and stages[-1].success
    assert stages[-1].speed.a[0] == pytest.approx(0.05)


def test_loses_contact_reads_the_check_against_the_transcriptions_wall_setting():
    st = stage("no_reversal", True, speed_of(0.0))
    st.check = Check(model="m", objective=1.0, ratio=1.0, periodic=True, ram_speed_violation=0.0, peak_torque=1.0,
                     verified=False, min_eccentricity=0.99)
    assert loses_contact(st, po.Collocation())
    assert not loses_contact(st, po.Collocation(min_eccentricity=None))  # free flight allowed
    assert not loses_contact(st, po.Collocation(min_eccentricity=0.9))
    assert not loses_contact(st, po.Rigid())
    st.check = replace(st.check, min_eccentricity=None)  # no clearance joint
    assert not loses_contact(st, po.Collocation())
    assert np.isfinite(MARGIN_FACTOR)
