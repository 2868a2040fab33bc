"""`optimize_speed`: the crank speed that minimises a load with the ram at constant speed in the
window, found by a chain of stages (`Strategy`) and verified by re-simulation."""

from __future__ import annotations

import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from .. import checks as chk
from ..compile_cache import compile_seconds, prepared_record, write_prepared_record
from ..design import design_speed
from ..ipopt_options import check_nlpsol_options
from ..model import ModelSpec, PressModel, build_model
from ..problem import ReversalWarning, SpeedProblem
from ..simulate import for_repeated_use
from ..speed import FourierSpeed
from ..workers import parallel_workers, process_pool
from .collocation import Collocation
from .nlp import drive_shortfall
from .ocp_result import OcpResult, peaks_of
from .stage import StageResult, Transcription, WarmStart, standing_stage
from .strategy import Strategy
from ..mechanism.ideal import ideal_response
from ..verify import (describe_excess, is_periodic, limits_exceeded, motor_cycle_of, ram_speed_violation,
                      rigid_reference, screen, verify_speed, window_times)


#: Tolerance of the initial speed's response. It usually impacts, and its 4th cycle from rest is then
#: chaotic: on the 75 spm seed's 4-element rod the peak torque was 893, 856 and 883 N m at rtol 1e-6,
#: 1e-7 and 1e-8, which took 17, 24 and 47 s.
INITIAL_RTOL = 1e-7


def optimize_speed(problem: SpeedProblem, model: PressModel | None = None, transcription: Transcription | None = None,
                   strategy: Strategy | str = "auto", progress: bool = True, *,
                   initial: FourierSpeed | None = None) -> OcpResult:
    """Design the crank speed that minimises `problem`'s objective.

    With only a problem it returns the best verified answer on the default model (both clearances,
    rigid rod): the rigid-press optimum when it is verified on that model, otherwise the optimum of
    the clearance model by direct collocation with the journals kept on their bearing walls.

    Parameters
    ----------
    problem : SpeedProblem
        What is asked.
    model : PressModel, optional
        Target model (`build_model`); default both clearances and a rigid rod for ``problem.press``.
        A model without states (the rigid press) stops after the rigid stage. Its press must be the
        problem's.
    transcription : Rigid, MultipleShooting or Collocation, optional
        Transcription of the stages on models with states; default `Collocation()`.
    strategy : Strategy or {"auto", "all"}
        The stage chain (`Strategy`).
    progress : bool
        A tqdm bar per stage: its name, iterations, the objective in its unit.
    initial : FourierSpeed, optional
        Start speed (period = the problem's); default the kinematic design (`design_speed`).

    Returns
    -------
    OcpResult
        ``success`` False when a stage did not converge (its least-infeasible iterate is returned,
        and ``status`` names the stage).

    Raises
    ------
    ValueError
        Invalid request (checked before any solve), among them an extra IPOPT or nlpsol option of the
        transcription or ``strategy.rigid`` that IPOPT or CasADi refuses (`check_nlpsol_options`).
    KeyboardInterrupt
        Ctrl-C; ``err.best`` holds the interrupted stage's least-infeasible iterate when there is one.
    """
    t_start = time.perf_counter()
    strat, tr, model, initial = checked_request(problem, model, transcription, strategy, initial)
    t_chain = time.perf_counter()
    settled: list[StageResult] = []
    if problem.counterbalance_range is not None:
        stage, problem, model = strat.settle_counterbalance(problem, model, initial, progress)
        settled = [stage]
    chain, init_sim, timing, (t_verify, c_verify) = run_chain(problem, model, tr, strat, initial, progress)
    stages = [*settled, *chain]
    answer = stages[-1]
    # judged by the stage whose answer stands; an earlier stage that stopped short (its answer a start
    # that a later stage improved on) is recorded, not inherited
    found = standing_stage(stages) or stages[0]
    earlier = [s for s in stages if not s.success and not s.superseded and s is not found]
    # the last stage's own verification (same model, same tolerance) when the strategy ran one
    reuse = answer.simulation is not None and answer.model == model.spec.describe()
    sim = answer.simulation if reuse else verify_speed(for_repeated_use(model), answer.speed, strat.verify_rtol)
    t1, t2 = window_times(sim, problem)
    limits = limits_exceeded(problem, answer.speed, sim)
    wall = time.perf_counter() - t_start
    timing.update(verification=time.perf_counter() - t_verify, other=t_chain - t_start,
                  verification_compile=compile_seconds() - c_verify)
    return OcpResult(
        problem=problem, model=model.spec, transcription=repr(tr), strategy=repr(strat), speed=answer.speed,
        initial_speed=initial, objective_value=found.objective, verified_objective=problem.objective_value(sim),
        peaks=peaks_of(sim), initial_peaks=peaks_of(init_sim), rigid_peak_torque=rigid_floor(chain, problem),
        t1=t1, t2=t2, success=found.success,
        status=outcome_status(answer, found, earlier) + (drive_floor(problem, strat, initial, found)
                                                         or ("" if found.success else drive_shortfall(found.violations)))
        + (f"; not verified: {describe_excess(limits)}" if limits else ""),
        periodic=is_periodic(sim), max_ram_speed_violation=max(ram_speed_violation(sim, problem), 0.0),
        min_omega=answer.speed.min_speed(), iterations=sum(s.iterations for s in stages),
        wall_time=wall, stages=stages, verify_rtol=strat.verify_rtol, simulation=sim,
        initial_simulation=init_sim, timing=timing, limits=limits)


def checked_request(problem: SpeedProblem, model: PressModel | None, transcription: Transcription | None,
                    strategy: Strategy | str, initial: FourierSpeed | None) -> tuple:
    """`optimize_speed`'s arguments checked before any solve, with their defaults filled in:
    (strategy, transcription, model with the problem's harmonics, initial speed)."""
    chk.instance("problem", problem, SpeedProblem)
    strat = Strategy.of(strategy)
    tr = Collocation() if transcription is None else transcription
    if not isinstance(tr, Transcription):
        raise ValueError(f"transcription must be Rigid, MultipleShooting or Collocation (a Transcription), "
                         f"got {type(tr).__name__}")
    check_nlpsol_options(f"{type(tr).__name__}.ipopt", getattr(tr, "ipopt", {}))
    check_nlpsol_options("Strategy.rigid.ipopt", strat.rigid.ipopt)
    if model is None:
        model = build_model(problem.press, n_harmonics=problem.n_harmonics, mechanism=problem.mechanism)
    chk.instance("model", model, PressModel)
    if model.params != problem.press:
        raise ValueError("model.params must be the problem's press (build the model from problem.press)")
    if model.mechanism != problem.mechanism:
        raise ValueError(f"model.mechanism must be the problem's ({problem.mechanism!r}), got {model.mechanism!r}: "
                         "build the model with mechanism=problem.mechanism")
    if not model.is_rigid and not tr.has_states:
        raise ValueError(f"{type(tr).__name__} solves the rigid press only; the model has states: pass "
                         "MultipleShooting or Collocation (or a model built with clearance=())")
    if model.n_harmonics != problem.n_harmonics:
        model = model.spec.build(model.params, problem.n_harmonics)
    if model.clearance and problem.lifted().reversal_side() is None:
        warnings.warn(ReversalWarning(f"{problem.reversal_cause()}. The optimiser cannot design the impacts away: it "
                                      "runs without its no-reversal stage, and the answer impacts"), stacklevel=3)
    if initial is None:
        initial = design_speed(problem).speed
    elif not isinstance(initial, FourierSpeed) or not np.isclose(initial.period, problem.period):
        raise ValueError(f"initial must be a FourierSpeed with the problem's period ({problem.period:g} s)")
    elif initial.n_harmonics > problem.n_harmonics:
        raise ValueError(f"initial has {initial.n_harmonics} harmonics, more than the problem's "
                         f"{problem.n_harmonics}")
    return strat, tr, model, initial


def run_chain(problem: SpeedProblem, model: PressModel, tr: Transcription, strat: Strategy, initial: FourierSpeed,
              progress: bool) -> tuple[list[StageResult], Any, dict, tuple[float, float]]:
    """The strategy's stages, and the initial speed's response (`initial_response`) on `model`:
    (stages, response, timing of the compile-ahead when it ran, (clock, compile seconds) when the
    stages ended: the verification's time starts there).

    Candidate chains run in worker processes, started now so that they import while the rigid stage
    runs here; the initial speed's response is simulated there meanwhile, in a worker of its own
    (spawned on demand: only when that response still runs as the candidates start, as on a flexible
    rod, where it takes longer than the rigid stage, and no candidate waits for it). The clearance
    stages' compiled functions are compiled ahead into the compile cache, in the worker that then
    simulates the initial speed, while the rigid stage runs: the candidates find them there (75 spm
    seed, empty cache: both chains compiled the same 7.5 s side by side after their no-reversal
    stage), or wait for a compile still running (`pressocp.jitcc`'s entry lock). A record in the
    cache (`prepared_record`) skips that when it was done before; with the cache off there is
    nowhere to compile ahead into."""
    workers = min(parallel_workers(strat.workers), len(strat.margins))
    parallel = workers > 1 and bool(model.clearance)
    spec = strat.clearance_spec(model.spec)
    preparable = parallel and tr.has_states and tr.compiles_ahead
    record = prepared_record(repr(tr), repr(problem), repr(spec)) if preparable else None
    ahead = record is not None and not record.exists()
    pool = process_pool(workers + 1, start=workers) if parallel else None
    timing: dict = {}
    try:
        init_job = None if pool is None else pool.submit(
            initial_response, model.spec, problem, initial, strat.verify_rtol,
            (tr, spec, record) if ahead else None)
        stages = strat.run(problem, model, tr, initial, progress, pool)
        ended = time.perf_counter(), compile_seconds()
        init_sim = initial_response(model, problem, initial, strat.verify_rtol) if init_job is None \
            else init_job.result()
        if ahead:
            init_sim, (timing["prepare"], timing["prepare_compile"]) = init_sim
    finally:
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)
    return stages, init_sim, timing, ended


def drive_floor(problem: SpeedProblem, strat: Strategy, initial: FourierSpeed, found: StageResult) -> str:
    """When the rigid stage found no speed within the drive's limits: what the ideal press's best
    speed without them (its floor, `Rigid`) asks of the motor, against the drive's ratings; else "".
    IPOPT's least-infeasible point spreads the excess over every constraint, so its own shortfall
    understates how much the motor lacks."""
    if problem.drive is None or found.success or found.name != "rigid":
        return ""
    floor = strat.rigid.solve(problem.replace(drive=None), None, WarmStart(initial), "drive_floor")
    if not floor.success:
        return ""
    d = problem.drive
    motor = motor_cycle_of(problem, floor.speed, ideal_response(problem.press, problem.mechanism, floor.speed))
    return (f"; the drive is too weak for this problem: without its limits the ideal press's best speed (peak crank "
            f"torque {floor.objective:.4g} N m) "
            f"needs {motor.peak_torque:.4g} N m peak at the motor and {motor.max_speed * 60 / (2 * np.pi):.0f} rpm, "
            f"{motor.rms_torque:.3g} N m RMS; the drive gives drive.peak_torque = {d.peak_torque:g} N m, "
            f"drive.max_speed = {d.max_speed * 60 / (2 * np.pi):.0f} rpm, drive.continuous_torque = "
            f"{d.continuous_torque:g} N m (gear ratio {d.gear_ratio:g})")


def outcome_status(answer: StageResult, found: StageResult, earlier: list[StageResult]) -> str:
    """The result's status: the answer's stage's (`found`, the last that ran and was not superseded;
    `answer` is the last stage, which may be a skipped one holding its answer), prefixed with that
    stage's name when it did not converge, and followed by the earlier stages that stopped short."""
    status = answer.status if found.success else f"stage {found.name!r}: {found.status}"
    if earlier and found.success:
        status += "; before it, " + ", ".join(f"stage {s.name!r} stopped ({s.status})" for s in earlier) + \
            ", its answer a start that a later stage improved on"
    return status


def rigid_floor(chain: list[StageResult], problem: SpeedProblem) -> float:
    """The floor: the peak torque on the rigid press (dense), N m, of the lowest rigid-press answer of
    `chain` (its first stage the rigid one): the rigid stage's, or its ``relaxed`` re-solve holding
    more of the ram-speed tolerance where that was kept (press60: 76.125 against 76.153 N m, the
    answer then below the rigid stage's peak)."""
    rigid = chain[0]
    relaxed = [s for s in chain if s.name == "relaxed" and s.model == rigid.model and s.success and not s.superseded
               and not s.was_skipped]
    return min(rigid_reference(problem, s.speed).peak("torque") for s in [rigid, *relaxed])


def prepare_stage(transcription: Transcription, problem: SpeedProblem, spec: ModelSpec, speed: FourierSpeed,
                  record: Path | None) -> tuple[float, float]:
    """`transcription.prepare` on the model level `spec` (built here, as in a worker process), then
    `record` written: (wall, compile) seconds."""
    t0 = time.perf_counter()
    compiled = transcription.prepare(problem, spec.build(problem.press, problem.n_harmonics), speed)
    write_prepared_record(record)
    return time.perf_counter() - t0, compiled


def initial_response(model: PressModel | ModelSpec, problem: SpeedProblem, initial: FourierSpeed, rtol: float,
                     ahead: tuple[Transcription, ModelSpec, Path | None] | None = None):
    """The initial speed's response on the target model (built from its spec when given one, as in a
    worker process): periodic when it does not impact, else its 4th cycle from rest (`screen`), at
    rtol max(`INITIAL_RTOL`, 10 `rtol`). With `ahead`, ``(transcription, model level, record)``,
    `prepare_stage` runs first, and the result is ``(response, (wall, compile))`` (one after the other
    in one worker, so that the rigid stage shares the two cores with one process only)."""
    if ahead is not None:
        prepared = prepare_stage(ahead[0], problem, ahead[1], initial, ahead[2])
        return initial_response(model, problem, initial, rtol), prepared
    if isinstance(model, ModelSpec):
        model = model.build(problem.press, problem.n_harmonics)
    if model.is_rigid:
        return verify_speed(model, initial, rtol)
    reference = problem.objective_value(rigid_reference(problem, initial))
    return screen(for_repeated_use(model), initial, reference, problem.objective, max(INITIAL_RTOL, 10 * rtol),
                  drive=problem.drive)[0]
