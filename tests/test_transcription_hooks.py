"""Transcriptions are objects with hooks: each records its settings as plain data and is rebuilt from
them, a subclass is registered by subclassing, and the optimiser refuses anything else by name."""

from __future__ import annotations

import json
from dataclasses import dataclass

import pytest

import pressocp as po
from pressocp.ocp import Transcription, transcription_from


@pytest.mark.parametrize("tr", [
    po.Rigid(), po.Rigid(samples=400, backoff=0.8, ipopt={"ipopt.max_iter": 7}, jit=False),
    po.Collocation(), po.Collocation(200, 2, jit=False, min_eccentricity=None, backoff=0.9, periodic=False),
    po.Collocation(edges=(0, 0.1, 0.15, 0.2, 0.3, 0.4, 0.45, 0.5, 0.6, 0.7, 0.8, 0.9), refinement="uniform"),
    po.MultipleShooting("cvodes", intervals=8, coefficient_step=0.5),
])
def test_settings_are_plain_data_that_rebuild_the_transcription(tr):
    data = json.loads(json.dumps(tr.settings()))  # through JSON, as a saved result holds them
    assert data["type"] == type(tr).__name__
    assert transcription_from(data) == tr


def test_hooks_say_what_each_transcription_has():
    rigid, colloc, shoot = po.Rigid(), po.Collocation(), po.MultipleShooting()
    assert (rigid.has_states, colloc.has_states, shoot.has_states) == (False, True, True)
    assert (rigid.needs_soft_start, colloc.needs_soft_start, shoot.needs_soft_start) == (False, False, True)
    assert (rigid.compiles_ahead, colloc.compiles_ahead, shoot.compiles_ahead) == (False, True, False)
    assert (rigid.gives_parametric_point, colloc.gives_parametric_point, shoot.gives_parametric_point) == \
        (True, True, False)
    assert shoot.shooting() is shoot and colloc.shooting() is None and rigid.shooting() is None
    assert shoot.refined(0.8) is None and shoot.tightened(0.1) is None
    assert colloc.refined(0.8).elements == 2 * colloc.grid(0.8).elements
    assert colloc.tightened(0.1).backoff == pytest.approx(colloc.backoff - 0.1)


def test_a_new_transcription_registers_by_subclassing():
    @dataclass(frozen=True)
    class Coarse(Transcription):
        points: int = 10

    assert transcription_from({"type": "Coarse", "points": 3}) == Coarse(3)
    with pytest.raises(ValueError, match="no known transcription: type 'Nope'"):
        transcription_from({"type": "Nope"})


def test_optimize_refuses_an_object_that_is_not_a_transcription():
    problem = po.SpeedProblem(po.PressParams(), period=1.0)
    with pytest.raises(ValueError, match="transcription must be .* got str"):
        po.optimize_speed(problem, transcription="collocation")
