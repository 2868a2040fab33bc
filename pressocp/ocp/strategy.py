"""The stage chain: the model hierarchy applied to optimisation.

1. ``rigid``: the ideal press (`Rigid`), exact Hessian, seconds. Its optimum is the floor. IPOPT
   stops at its acceptable level (`rigid_first`); an answer that other stages start from is first
   continued to the full tolerance (`rigid_tight`). It is re-simulated on the target model (rigid
   rod); when it impacts there (the joint forces reverse):
2. ``no_reversal``: the ideal press again, with the rod's axial load at both pins kept on one side
   (`SpeedProblem.without_reversal`: in tension above a margin x its static value, or, with a
   counterbalance that lifts more than ram and rod weigh, in compression), warm-started from the
   rigid optimum. Without a force reversal the journals
   stay on their bearings; it is re-simulated on the target model too. With several margins
   (``tension_margin``, default 0.05 and 0.02), stages 2-5 run once per margin, side by side in
   worker processes, and the lowest verified answer is kept (`pressocp.ocp.candidates`).
3. ``soft`` (transcriptions that need it, i.e. multiple shooting): the clearance model with a
   softer contact, when the start impacts.
4. ``target``: the clearance model (rigid rod) by the given transcription. It is re-simulated
   (`verify_stage`) and, while that does not confirm the NLP, re-solved with the ram-speed bounds
   moved from its primal-dual solution (``_tightened_k``) or on a finer grid (``_refined_k``):
   `followed`. When a polish round follows, that waits until the round was not kept. When the
   no-reversal start's journals leave their walls on this model by more than 1 % of the clearance
   (`RAISE_AHEAD`), the no-reversal stage runs again at twice the margin before the target stage
   (``no_reversal_raised_k``, at most `MARGIN_RAISES` times); when the target stage does not
   converge from a start whose journals leave their walls by less, the same raise follows it
   (`raises`); any other stage that does not converge is solved again from the same start with the
   KKT matrix scaled (`rescued`, ``{name}_rescaled``).
5. ``polish_k``: the last stage's NLP solved again from its own answer, without multipliers. IPOPT's
   barrier restarts there and can leave the local optimum the first pass stopped at. A round is kept
   only when its periodic re-simulation lowers the objective with the ram speed in tolerance and no
   limit exceeded; the first round that does not, or that gains no more than ``polish_gain``, ends
   the polishing.
6. ``flexible`` (a flexible target rod): the rigid-rod answer re-simulated on the flexible rod;
   only when it does not hold there is the problem solved on it, then polished (`on_flexible_rod`).
7. ``refine_k`` (opt-in): trust-region rounds of multiple shooting, each kept only when its
   periodic re-simulation lowers the objective with the ram speed in tolerance and no limit
   exceeded.

In "auto" mode a rigid optimum that is verified on the target model (periodic, objective within
``verified_ratio`` of its rigid-press value, ram speed in tolerance over the model's own window, no
limit of the problem exceeded: its pin-force cap, its drive's ratings) is the answer and stages 2-5
are skipped; "all" runs them from it. The no-reversal optimum is only a start: its extra constraint
is a rigid-press stand-in for "no impact", and the clearance model's own optimum (journals kept on
their walls) is lower.
"""

from __future__ import annotations

import time
from concurrent.futures import Executor
from dataclasses import dataclass, field, replace

import numpy as np

from .. import checks as chk
from ..model import ModelSpec, PressModel, build_model
from ..objectives import get as get_objective
from ..params import PressParams
from ..problem import SpeedProblem
from ..result import SimResult
from ..mechanism.ideal import ideal_inverse_dynamics
from ..simulate import SimulationError, for_repeated_use
from ..speed import FourierSpeed
from .candidates import run_candidates, run_flexible_candidates
from .rigid_stage import Rigid
from ..ipopt_options import IPOPT_RIGID_ACCEPTABLE
from .shooting import MultipleShooting
from .stage import PAUSED, Check, Resimulated, StageResult, Transcription, WarmStart, settings_repr, standing_stage
from ..verify import (IMPACT_RATIO, describe_excess, is_periodic, limits_exceeded, ram_speed_violation,
                      rigid_reference, screen, unverified_reason, verify_speed)

MODES = ("auto", "all", "continue")
#: `Strategy.polish_candidates`: after every candidate chain's first polish round only the lowest
#: verified one polishes further, or each its own rounds.
POLISH_CANDIDATES = ("best", "each")
#: Checks of a stage's answer run at this tolerance (the final verification at `Strategy.verify_rtol`).
CHECK_RTOL = 1e-7
#: Two checks' objective ratios closer than this (relative) are a tie, below what a check at
#: `CHECK_RTOL` resolves (its peak is about 5e-5 off); the no-reversal start wins a tie with the rigid
#: optimum. On the soft-contact contract scene the two starts' ratios differ by 2e-6 (1.014102 and
#: 1.014104): which one came out lower followed the checks' round-off (compiled or interpreted), and
#: multiple shooting from the rigid optimum ended infeasible where from the no-reversal start it
#: converged (2026-11-28).
RATIO_TIE = 1e-4
#: IPOPT's status when it stopped at its acceptable level.
ACCEPTABLE = "Solved_To_Acceptable_Level"
#: IPOPT iterations per refinement round, and the trust region's growth and shrink factors.
REFINE_ITERATIONS = 6
REFINE_GROW, REFINE_SHRINK = 1.5, 0.4
#: Share of the ram-speed tolerance given up, beyond the measured excess, when a stage is re-solved
#: with the held share lowered (`Strategy.solve_refined`), and how many times that is done.
TIGHTEN_MARGIN, MAX_TIGHTEN = 0.02, 3
#: A relaxed re-solve runs only when it adds at least this share of the ram-speed tolerance to what
#: the answer's NLP held (`relaxed_share`).
RELAX_MIN_GAIN = 0.01


#: The final re-simulation's relative tolerance, allowed range: looser than 1e-5 the verification
#: itself is not trustworthy (at rtol 1 a press60 answer re-simulated at 2463 N m, 32 x its peak, and
#: passed as verified), tighter than 1e-14 is below the integrators' round-off.
VERIFY_RTOL_RANGE = (1e-14, 1e-5)


def relaxed_share(held: float, share: float, past: float) -> float | None:
    """The share of the ram-speed tolerance a relaxed re-solve holds, or None when it is not worth
    one. `held` is what the answer's NLP held, `share` what the relaxed transcription would hold, and
    `past` how far the answer's re-simulated ram strays past `held` (shares of the tolerance;
    negative: inside it). A re-solve is expected to stray as far past its own bounds, so `share` is
    kept while ``share + past <= 1``; beyond that it holds ``1 - 2 past``, leaving the stray once
    more as margin, and it is not worth running when that adds less than `RELAX_MIN_GAIN` to `held`.
    The rule has no step at a stray of zero (it is continuous there for `share` = 1), so a
    re-simulation that differs by a hair from machine to machine does not decide whether the
    re-solve runs (docs/decisions/2026-11-29-relaxed-share.md)."""
    if share + past <= 1.0:
        return share
    fit = 1.0 - 2.0 * past
    return fit if fit >= held + RELAX_MIN_GAIN else None


def soft_params(params: PressParams, factor: float) -> PressParams:
    """The press with every bearing's contact stiffness divided by ``factor`` (continuation stage)."""
    chk.positive("soft_factor", factor)
    bearings = {k: replace(getattr(params, k), stiffness=getattr(params, k).contact_stiffness / factor)
                for k in ("crank_pin", "wrist_pin")}
    return params.replace(**bearings)


#: The first no-reversal margin, and the counterbalance stage's when the strategy has none.
DEFAULT_MARGIN = 0.05
#: When the target stage does not converge (rescaled too) from a no-reversal start whose journals
#: leave their walls on the target model, the no-reversal stage runs again with its margin this many
#: times larger (at most `MAX_MARGIN`), and the chain from there; at most `MARGIN_RAISES` times.
#: forming40 (60 kN over the window): from 0.05 the target stage did not converge, from 0.1 it did
#: (docs/measurements.md, 2026-11-27).
MARGIN_FACTOR, MAX_MARGIN, MARGIN_RAISES = 2.0, 0.5, 2
#: A no-reversal start whose journals leave their walls further than this (min |e|/c below it) is raised
#: before the target stage is solved from it, not after that stage failed: from such starts no target
#: stage gave an answer the chain kept (forming40 0.79, 0.92, 0.965: 200 iterations each, 1.5-9 minutes;
#: press75 with a gas spring 0.988: converged on a grid too coarse, its regrid did not), while from
#: press75's grazing 0.9987 it converged to the seed's optimum (docs/decisions/2026-12-02-raise-ahead.md).
RAISE_AHEAD = 0.99


@dataclass(frozen=True)
class Strategy:
    """How `optimize_speed` chains its stages.

    Attributes
    ----------
    mode : {"auto", "all", "continue"}
        "auto": use no more model than the scene needs (a verified rigid-press answer ends the
        chain); "all": run every stage; "continue": as "auto", but when the initial speed (a
        neighbouring optimum, in a continuation) does not impact on the model, the stages on models
        with states start from it, with no no-reversal or soft stage. When that chain fails, the
        cold chain runs after it; the failed stage stays in the record, marked ``superseded``.
    rigid : Rigid
        Transcription of the rigid and no-reversal stages.
    tension_margin : float, tuple of float, or None
        Rod load kept at both pins by the no-reversal stage, as a fraction of its static value
        (`SpeedProblem.without_reversal`), each in [0, 1); None skips that stage. It runs only when
        the rigid optimum is not verified on the target model and the load can keep one sign
        (`SpeedProblem.reversal_side`). Several margins: each starts
        a candidate chain (no-reversal, target and polish stages, named ``stage@margin``), run side by
        side in `workers` processes, and the lowest verified answer is kept (`pressocp.ocp.candidates`).
    flexible_backoffs : tuple of float
        On a flexible rod between ideal joints: further starts of the flexible stage, the rigid
        optimum re-solved holding each of these shares of the ram-speed tolerance (`Rigid.backoff`,
        in (0, 1]; warm, from the rigid stage's solution). Each start runs a candidate chain (the
        flexible stage and its polish rounds) side by side with the rigid optimum's in `workers`
        processes, and the lowest verified answer is kept (`pressocp.ocp.candidates`). The flexible
        stage's local optimum depends on its start: on the slender-rod scene the rigid optima at 0.9
        and 0.95 led to 74.55 and 70.33 N m verified, at 0.8 to 77.10 (2026-11-27). Empty: one chain.
    workers : int
        Processes for the candidate chains, 1..64 (1: one after the other in this process).
    verified_ratio : float
        A rigid-press answer is verified on a model when its objective there is within this factor
        of its rigid-press value (and it is periodic with the ram speed in tolerance and no limit
        exceeded).
    soft_factor : float or None
        Contact-stiffness divisor of the soft stage, for transcriptions that need one (multiple
        shooting), in (1, 1e8); None skips it.
    polish_rounds : int
        Most re-solves of the last stage from its own answer, 0..10 (each about as long as that
        stage). They run only when a stage on a model with states gave the answer, and stop at the
        first round that does not lower the verified objective by more than `polish_gain`. Then one
        re-solve holding more of the ram-speed tolerance (`relax`), also after a rigid answer that
        stands; 0 runs none of them.
    polish_gain : float
        Share by which a polish round must lower the verified objective for another round to run,
        in [0, 1). Each round restarts IPOPT's barrier from the last answer, which can escape a
        local optimum: on the slender-rod scene the rounds gained 4 % and 2 % (to 71.78 and 70.33
        N m) and a third nothing; on the 75 spm seed a second round gained nothing.
    polish_candidates : str
        With several candidate chains: "best" runs every chain to its first polish round, then
        polishes further only the lowest verified of them (`pressocp.ocp.candidates`); "each" lets
        every chain run all its rounds. On the 75 spm seed the losing chain's second round was the
        call's longest path (7-9 s of 50); in 223 recorded calls a chain behind after its first round
        ended ahead in 3, by 2.4e-6 (145.14376 against 145.14411 N m;
        docs/decisions/2026-12-02-polish-the-best-candidate.md).
    refine_rounds : int
        Trust-region rounds of multiple shooting after the other stages, 0..100 (minutes each).
    refine_step : float
        Initial trust region of the refinement, rad/s on every Fourier coefficient.
    verify_rtol : float
        Tolerance of the final periodic re-simulation, in [1e-14, 1e-5] (`VERIFY_RTOL_RANGE`).
    grid_tol : float
        A stage on a model with states is re-simulated (at `verify_rtol`) and, while its objective
        there differs from the NLP's by more than this share or the ram speed leaves its tolerance,
        solved again from its answer on a finer grid (`refined`), in (0, 1).
    regrid_gap : float or None
        When the target stage's NLP objective differs from its re-simulation's by more than this
        share, its grid is too coarse for the scene: its optimum lives on the grid's error, and a
        refinement from it rarely converges. The target stage is then solved again on the finer grid
        from its own start (``target_regrid_k``, `regridded`), in (`grid_tol`, 1); None: never.
        On press75 with a gas-spring counterbalance the 400-element optima re-simulated 7-8 % above
        their NLPs and every refinement from them stopped at its iteration limit (688 s, 144.99 N m
        verified); from the start on 800 elements the call took 323 s to 135.86 N m (2026-11-30).
    """

    mode: str = "auto"
    rigid: Rigid = field(default_factory=Rigid)
    tension_margin: float | tuple[float, ...] | None = (DEFAULT_MARGIN, 0.02)
    flexible_backoffs: tuple[float, ...] = (0.95,)
    workers: int = 2
    verified_ratio: float = 1.02
    soft_factor: float | None = 100.0
    polish_rounds: int = 3
    polish_gain: float = 0.025
    polish_candidates: str = "best"
    refine_rounds: int = 0
    refine_step: float = 0.2
    verify_rtol: float = 1e-9
    grid_tol: float = 0.02
    regrid_gap: float | None = 0.05

    def __post_init__(self) -> None:
        chk.choice("mode", self.mode, MODES)
        if not isinstance(self.rigid, Rigid):
            raise ValueError(f"rigid must be a Rigid transcription, got {type(self.rigid).__name__}")
        for m in self.margins:
            chk.in_half_open_interval("tension_margin", m, 0.0, 1.0)
        if isinstance(self.tension_margin, tuple) and len(set(self.margins)) != len(self.margins):
            raise ValueError(f"tension_margin lists a margin twice: {self.tension_margin}")
        for b in self.flexible_backoffs:
            chk.in_closed_interval("flexible_backoffs", b, 1e-3, 1.0)
        if len(set(self.flexible_backoffs)) != len(self.flexible_backoffs):
            raise ValueError(f"flexible_backoffs lists a backoff twice: {self.flexible_backoffs}")
        chk.integer("workers", self.workers, 1, 64)
        chk.in_open_interval("verified_ratio", self.verified_ratio, 1.0, 10.0)
        if self.soft_factor is not None:
            chk.in_open_interval("soft_factor", self.soft_factor, 1.0, 1e8)
        chk.integer("polish_rounds", self.polish_rounds, 0, 10)
        chk.in_half_open_interval("polish_gain", self.polish_gain, 0.0, 1.0)
        chk.choice("polish_candidates", self.polish_candidates, POLISH_CANDIDATES)
        chk.integer("refine_rounds", self.refine_rounds, 0, 100)
        chk.positive("refine_step", self.refine_step, "rad/s")
        chk.in_closed_interval("verify_rtol", self.verify_rtol, *VERIFY_RTOL_RANGE)
        chk.in_open_interval("grid_tol", self.grid_tol, 0.0, 1.0)
        if self.regrid_gap is not None:
            chk.in_open_interval("regrid_gap", self.regrid_gap, self.grid_tol, 1.0)

    def __repr__(self) -> str:
        return settings_repr(self)

    @property
    def margins(self) -> tuple[float, ...]:
        """The no-reversal stages' tension margins (empty when that stage is skipped)."""
        m = self.tension_margin
        return () if m is None else tuple(m) if isinstance(m, (tuple, list)) else (m,)

    @classmethod
    def of(cls, strategy: "Strategy | str") -> "Strategy":
        """A `Strategy` from itself or a mode name."""
        if isinstance(strategy, Strategy):
            return strategy
        chk.choice("strategy", strategy, MODES)
        return cls(mode=strategy)

    # The chain ---------------------------------------------------------------------------------
    def settle_counterbalance(self, problem: SpeedProblem, model: PressModel, initial: FourierSpeed,
                              progress: bool) -> tuple[StageResult, SpeedProblem, PressModel]:
        """The ``counterbalance`` stage of a problem with a `SpeedProblem.counterbalance_range`: the
        ideal press with the counterbalance's force free in that range, and the rod's load held on the
        side it can keep at the top of the range (`SpeedProblem.without_reversal` at the first
        margin; in compression, when the counterbalance can lift more than ram and rod weigh, at
        that margin of their weight, as in tension), so that the force is chosen for joints loaded
        one way. Returns the stage, and the problem and
        model with the force it chose (the chain then designs the speed for that press)."""
        lo, hi = problem.counterbalance_range
        top = problem.lifted()
        margin = self.margins[0] if self.margins else DEFAULT_MARGIN
        held = top.without_reversal(margin) or top
        if held.max_tension is not None and -margin * problem.hanging_weight > top.static_tension[1]:
            held = held.replace(max_tension=-margin * problem.hanging_weight)  # the tension side's margin
        stage = self.rigid.solve(held.replace(counterbalance_range=(lo, hi)), None, WarmStart(initial),
                                 "counterbalance", progress)
        force = stage.details["free"]["counterbalance.force"]
        stage.details["reversal_side"] = top.reversal_side()
        press = problem.press.with_value("counterbalance.force", force)
        fixed = problem.replace(press=press, counterbalance_range=None)
        return stage, fixed, model.spec.build(press, model.n_harmonics)

    def run(self, problem: SpeedProblem, model: PressModel, transcription: Transcription, initial: FourierSpeed,
            progress: bool, pool: Executor | None = None) -> list[StageResult]:
        """Every stage in order; the last one's speed is the answer. `pool`: worker processes for the
        candidate chains (default: started when needed, `workers` of them)."""
        rigid = self.rigid_first.solve(problem, model, WarmStart(initial), "rigid", progress)
        if model.is_rigid or (problem.drive is not None and not rigid.success):
            # a drive the ideal press cannot meet: no clearance model does better
            return [self.rigid_tight(problem, model, rigid, progress)]
        if not model.clearance:  # a flexible rod between ideal joints: no clearance stages
            rigid = self.rigid_tight(problem, model, rigid, progress)
            return [rigid, *self.flexible_only(problem, model, rigid, transcription, progress, pool)]
        base = model if model.rod == "rigid" else self.clearance_spec(model.spec).build(model.params,
                                                                                     model.n_harmonics)
        rigid.check = self.check(base, rigid, problem)
        if not (self.mode in ("auto", "continue") and rigid.check.verified):  # other stages start from it
            rigid = self.rigid_tight(problem, model, rigid, progress)
        stages = [rigid, *self.rigid_rod_stages(problem, base, rigid, transcription, initial, progress, pool)]
        if model.rod != "flexible" or not all(st.success or st.superseded for st in stages):
            return stages
        return stages + self.on_flexible_rod(problem, model, base, stages[-1], transcription, progress)

    @property
    def rigid_first(self) -> Rigid:
        """`rigid` stopping at IPOPT's acceptable level (`IPOPT_RIGID_ACCEPTABLE`): the rigid stage's
        first solve, and the relaxed re-solve of a rigid answer that stands (a final answer, verified
        by its re-simulation; press60: 6 iterations instead of 75, 76.1239 against 76.1244 N m)."""
        return replace(self.rigid, ipopt={**IPOPT_RIGID_ACCEPTABLE, **self.rigid.ipopt})

    def rigid_tight(self, problem: SpeedProblem, model: PressModel, rigid: StageResult,
                    progress: bool) -> StageResult:
        """The rigid stage's answer at `Rigid`'s own tolerance: `rigid` itself when IPOPT converged
        there, else (stopped at its acceptable level, `IPOPT_RIGID_ACCEPTABLE`) the same NLP continued
        from its primal-dual point, one record with both solves' iterations and times. Its ``check``
        (the screen on the clearance model) stays the acceptable iterate's: the two speeds differ by
        about 1e-6 of the objective. When the continuation fails, `rigid` stands, its status saying so."""
        if rigid.status != ACCEPTABLE or rigid.nlp is None:
            return rigid
        tight = self.rigid.solve(problem, model, WarmStart(rigid.speed, point=rigid.nlp), "rigid", progress)
        if not tight.success:
            rigid.status = f"{ACCEPTABLE} (its continuation to the full tolerance failed: {tight.status})"
            return rigid
        timing = {k: rigid.timing.get(k, 0.0) + tight.timing.get(k, 0.0) for k in {*rigid.timing, *tight.timing}}
        log, more = rigid.iteration_log or {}, tight.iteration_log or {}
        offset = log["time_s"][-1] if log.get("time_s") else 0.0
        joined = {k: [*log.get(k, []), *((t + offset for t in more[k]) if k == "time_s" else more[k])] for k in more}
        return replace(tight, iterations=rigid.iterations + tight.iterations, wall_time=rigid.wall_time + tight.wall_time,
                       timing=timing, check=rigid.check, history=[*rigid.history, *tight.history],
                       barrier=[*rigid.barrier, *tight.barrier], iteration_log=joined,
                       details={**tight.details, "warm": False, "acceptable_iterations": rigid.iterations,
                                "acceptable_objective": rigid.objective})

    @staticmethod
    def clearance_spec(spec: ModelSpec) -> ModelSpec:
        """The model level of the clearance stages for a target model level: its clearances on a rigid
        rod (a flexible rod follows them, `on_flexible_rod`)."""
        return spec if spec.rod == "rigid" else ModelSpec("rigid", spec.clearance, 4, mechanism=spec.mechanism)

    def rigid_rod_stages(self, problem: SpeedProblem, base: PressModel, rigid: StageResult,
                         transcription: Transcription, initial: FourierSpeed, progress: bool,
                         pool: Executor | None) -> list[StageResult]:
        """The clearance stages on the rigid-rod model `base` after the `rigid` stage (checked on
        `base`): in "continue" mode the chain from the initial speed when it fits; the candidate
        chains when there are several no-reversal margins and the rigid optimum is not verified;
        else one chain."""
        stages: list[StageResult] = []
        if self.mode == "continue" and not rigid.check.verified and self.fits(base, initial, problem):
            tried = self.clearance_chain(problem, base, rigid, transcription, initial, progress)
            if all(st.success for st in tried):
                return tried
            for st in tried:
                if not st.success:
                    st.superseded = "the chain from the neighbour's optimum failed here; it restarted as a cold chain"
            stages += tried
        margins = self.margins
        if len(margins) > 1 and not rigid.check.verified and problem.reversal_side() is not None:
            return stages + run_candidates(self, problem, base.spec, rigid, transcription, margins, progress, pool)
        return stages + self.clearance_chain(problem, base, rigid, transcription, None, progress,
                                             margins[0] if margins else None)

    def on_flexible_rod(self, problem: SpeedProblem, model: PressModel, base: PressModel, last: StageResult,
                        transcription: Transcription, progress: bool) -> list[StageResult]:
        """The flexible rod after the rigid-rod answer `last` (solved on `base`): that answer
        re-simulated on `model` (periodic at `verify_rtol`, its search started from the rigid-rod
        journal states with the rod undeformed). In "auto" and "continue" mode, when it is periodic
        with the ram speed in tolerance, no limit exceeded, and its objective within `verified_ratio`
        of the rigid rod's, the flexible stage is skipped (its record holds that re-simulation, which
        the final verification reuses); otherwise the flexible stage starts from it, then the polish
        rounds."""
        value = problem.objective_value
        t0 = time.perf_counter()
        on_base = self.verify_stage(base, last)
        x0 = rod_undeformed(model, base, on_base.states[:, 0]) if is_periodic(on_base) is True else None
        sim = verify_speed(model, last.speed, self.verify_rtol, x0=x0)
        ratio = value(sim) / value(on_base)
        viol = max(ram_speed_violation(sim, problem), 0.0)
        limits = limits_exceeded(problem, last.speed, sim)
        check = Check(model=model.spec.describe(), objective=value(sim), ratio=float(ratio), periodic=is_periodic(sim),
                      ram_speed_violation=viol, peak_torque=sim.peak("torque"), limits=limits,
                      verified=bool(is_periodic(sim) is True and ratio <= self.verified_ratio and viol <= 0.0
                                    and not limits))
        seconds = time.perf_counter() - t0
        if self.mode in ("auto", "continue") and check.verified:
            reason = (f"the rigid-rod answer meets the constraints on the flexible rod and its objective there is "
                      f"within {self.verified_ratio:g} x the rigid rod's ({check.ratio:.4g} x)")
            stage = StageResult.skipped("flexible", reason, model.spec.describe(), last)
            stage.check, stage.simulation = check, sim
            add_time(stage, "checks", seconds)
            return [stage]
        x_flex = sim.states[:, 0] / model.x_scale if is_periodic(sim) is True else None
        solved, transcription = self.solve_refined(problem, model, transcription, WarmStart(last.speed, x_flex),
                                                   "flexible", progress)
        solved[0].check = check
        add_time(solved[0], "checks", seconds)
        if not solved[-1].success:
            return solved
        return [*solved, *self.rounds(problem, model, model, solved, transcription, progress)]

    def clearance_chain(self, problem: SpeedProblem, base: PressModel, rigid: StageResult,
                        transcription: Transcription, neighbour: FourierSpeed | None,
                        progress: bool, margin: float | None = None, candidate: bool = False) -> list[StageResult]:
        """The stages after the rigid one on the rigid-rod model with clearance `base`, to the polish
        and refinement rounds; it stops at a failed stage. ``neighbour``: a non-impacting start (a
        neighbouring optimum in a continuation) that the stages on models with states take as it is,
        with no no-reversal or soft stage; None: the cold chain from the rigid optimum, through the
        no-reversal stage at tension `margin` (None: none). A `candidate` chain (one of several side by
        side) ends where its no-reversal stage does not converge: its start would be the rigid optimum,
        the start of no candidate (`pressocp.ocp.candidates` runs that chain once when every candidate
        ended so)."""
        stages: list[StageResult] = []
        start = rigid
        held = None if margin is None else problem.without_reversal(margin)
        if neighbour is None and not rigid.check.verified and held is not None:
            nr = self.rigid.solve(held, base, WarmStart(rigid.speed), "no_reversal", progress)
            stages.append(nr)
            if candidate and not nr.success:
                return stages
            if nr.success:
                nr.check = self.check(base, nr, problem)
                if nr.check.verified or nr.check.ratio < rigid.check.ratio * (1.0 + RATIO_TIE):
                    start = nr
        chain: list[tuple[str, PressModel]] = []
        if self.mode in ("auto", "continue") and rigid.check.verified:
            # the rigid answer stands; with the polish on, it holds more of the ram-speed tolerance if
            # that re-simulates lower
            relaxed, sim = self.relax(problem, base, start, self.rigid_first, progress) \
                if self.polish_rounds else ([], None)
            target = StageResult.skipped("target", self.verified_reason, base.spec.describe(),
                                         standing_stage([start, *relaxed]))
            target.simulation = sim  # the final verification's (same model, same tolerance)
            stages += [*relaxed, target]
        else:
            if transcription.needs_soft_start and self.soft_factor is not None \
                    and neighbour is None and start.check.ratio > IMPACT_RATIO:
                chain.append(("soft", build_model(soft_params(base.params, self.soft_factor), "rigid", base.clearance,
                                                  n_harmonics=base.n_harmonics, mechanism=base.mechanism)))
            chain.append(("target", base))
        if not chain:
            return stages + self.rounds(problem, None, base, [rigid, *stages], transcription, progress)
        start, margin, done = self.raised_ahead(problem, base, rigid, start, transcription, margin, stages, progress)
        first = len(stages)
        raise_next = raises(problem, rigid, start, transcription, margin, done)
        solved, transcription = self.state_chain(problem, chain, transcription,
                                                 start.speed if neighbour is None else neighbour, progress,
                                                 rescue=not raise_next)
        stages += solved
        while raise_next and not solved[-1].success:
            # the no-reversal start's journals leave their walls on the target model, which holds them there:
            # the rod's load kept further from zero gives a start the target stage can reach
            raised = self.raised_start(problem, base, start, margin, done, progress)
            note = (f"{solved[-1].name} did not converge ({solved[-1].status}) from {start.name}, whose journals leave "
                    f"their walls on this model (|e|/c down to {start.check.min_eccentricity:.4g}); the chain ran again "
                    f"from the no-reversal stage at tension margin {raised.details['tension_margin']:g}")
            for st in stages[first - 1 :]:
                st.superseded = st.superseded or note
            stages.append(raised)
            if not raised.success:
                break
            start, margin, first, done = raised, raised.details["tension_margin"], len(stages), done + 1
            raise_next = raises(problem, rigid, start, transcription, margin, done)
            solved, transcription = self.state_chain(problem, chain, transcription, start.speed, progress,
                                                     rescue=not raise_next)
            stages += solved
        if not stages[-1].success:
            return stages
        return stages + self.rounds(problem, chain[-1][1], base, [rigid, *stages], transcription, progress,
                                    floor=rigid.objective, candidate=candidate)

    def raised_ahead(self, problem: SpeedProblem, base: PressModel, rigid: StageResult, start: StageResult,
                     transcription: Transcription, margin: float | None, stages: list[StageResult],
                     progress: bool) -> tuple[StageResult, float | None, int]:
        """The no-reversal stage raised (`raised_start`, appended to `stages`) while its start's journals
        leave their walls by more than `RAISE_AHEAD` allows, before any target stage is solved from it:
        the start the target stage is solved from, its margin and the raises done (`MARGIN_RAISES`
        when a raise did not converge: the target stage then runs from the start there was, and no
        raise follows it)."""
        done = 0
        while raises(problem, rigid, start, transcription, margin, done, RAISE_AHEAD):
            raised = self.raised_start(problem, base, start, margin, done, progress)
            stages.append(raised)
            if not raised.success:
                raised.superseded = f"it did not converge ({raised.status}); the target stage ran from {start.name}"
                return start, margin, MARGIN_RAISES
            start.superseded = start.superseded or (
                f"its journals leave their walls on this model (|e|/c down to {start.check.min_eccentricity:.4g}, "
                f"below {RAISE_AHEAD:g}: from such starts no target stage gave an answer the chain kept), so the "
                f"no-reversal stage ran again at tension margin {raised.details['tension_margin']:g} before the "
                "target stage")
            start, margin, done = raised, raised.details["tension_margin"], done + 1
        return start, margin, done

    def raised_start(self, problem: SpeedProblem, base: PressModel, start: StageResult, margin: float, done: int,
                     progress: bool) -> StageResult:
        """The no-reversal stage again from `start` (solved at tension `margin` after `done` raises) at
        `MARGIN_FACTOR` times the margin (at most `MAX_MARGIN`): ``no_reversal_raised_{done + 1}``, its
        margin in ``details["tension_margin"]``, checked on `base` when it converged."""
        raised_margin = min(MARGIN_FACTOR * margin, MAX_MARGIN)
        held = problem.without_reversal(raised_margin)
        raised = self.rigid.solve(held, base, WarmStart(start.speed), f"no_reversal_raised_{done + 1}", progress)
        raised.details["tension_margin"] = raised_margin
        if raised.success:
            raised.check = self.check(base, raised, problem)
        return raised

    def state_chain(self, problem: SpeedProblem, chain: list[tuple[str, PressModel]], transcription: Transcription,
                    speed: FourierSpeed, progress: bool, rescue: bool = True) -> tuple[list[StageResult], Transcription]:
        """The stages on models with states (`chain`: names and models, the last the target) from
        `speed`, each from the last one's answer, rescued when it does not converge (`rescued`; the
        last only with `rescue`), the last solved again on finer grids while its grid is too coarse
        (`regridded`), and followed up (`followed`), except the last when polish rounds follow (a
        polish round that is kept makes its follow-ups moot); it stops at a stage that does not
        converge. Returns the stages and the transcription of the last one."""
        stages: list[StageResult] = []
        for k, (name, m) in enumerate(chain):
            start = WarmStart(speed)
            last = k == len(chain) - 1
            solved, used = self.rescued(problem, m, transcription, start, name, progress, rescue or not last)
            if last:
                solved, used = self.regridded(problem, m, transcription, used, solved, start, progress, rescue)
            transcription = used
            if k < len(chain) - 1 or not self.polish_rounds:
                more, transcription = self.followed(problem, m, transcription, solved[-1], progress)
                solved = solved[:-1] + more
            stages += solved
            speed = solved[-1].speed
            if not solved[-1].success:
                break
        return stages, transcription

    def regridded(self, problem: SpeedProblem, model: PressModel, transcription: Transcription, used: Transcription,
                  solved: list[StageResult], start: WarmStart, progress: bool,
                  rescue: bool = True) -> tuple[list[StageResult], Transcription]:
        """`solved` (the target stage by `used`, `transcription` or its rescued form, from `start`) and,
        while the last one converged but its NLP objective is more than `regrid_gap` from its
        periodic re-simulation's (`verify_stage`), the same stage from `start` on the next finer grid
        of `transcription` (stage ``{name}_regrid_k``, with `rescue` rescued when it does not
        converge); the coarser ones stay in the record, superseded. Returns the stages and the last
        one's transcription."""
        name, k = solved[0].name, 0
        while self.regrid_gap is not None and solved[-1].success:
            last = solved[-1]
            finer = transcription.refined(problem.period, model.rod)
            if finer is None:
                break
            sim = self.verify_stage(model, last)
            if is_periodic(sim) is not True:
                break
            value = problem.objective_value(sim)
            gap = abs(value - last.objective) / abs(value)
            if gap <= self.regrid_gap:
                break
            k += 1
            why = (f"its NLP's objective {last.objective:.6g} is {100 * gap:.1f} % from its re-simulation's "
                   f"{value:.6g} (more than {100 * self.regrid_gap:g} %): the grid is too coarse for this scene; "
                   f"{name}_regrid_{k} solved it again from the same start on the finer grid")
            for st in solved:
                st.superseded = st.superseded or why
            transcription = finer
            again, used = self.rescued(problem, model, transcription, start, f"{name}_regrid_{k}", progress, rescue)
            again[-1].details["regridded"] = why
            solved = [*solved, *again]
        return solved, used

    def flexible_only(self, problem: SpeedProblem, model: PressModel, rigid: StageResult,
                      transcription: Transcription, progress: bool, pool: Executor | None = None) -> list[StageResult]:
        """The stages after ``rigid`` on a flexible rod between ideal joints: the rigid optimum is checked
        on the flexible model itself, and when it is not verified there ("auto") or always ("all"), the
        flexible stage starts from it, then the polish rounds; with `flexible_backoffs`, so do
        candidate chains from the rigid optimum re-solved at those backoffs (`flexible_starts`), and
        the lowest verified answer is kept (`pool`: their worker processes, as `run`'s)."""
        rigid.check = self.check(model, rigid, problem)
        if self.mode in ("auto", "continue") and rigid.check.verified:
            reason = self.verified_reason
            return [StageResult.skipped("flexible", reason, model.spec.describe(), rigid)]
        starts = self.flexible_starts(problem, model, rigid, progress)
        usable = [rigid, *(st for st in starts if st.success)]
        if len(usable) == 1:
            return starts + self.flexible_chain(problem, model, rigid, transcription, progress)
        return starts + run_flexible_candidates(self, problem, model.spec, usable, transcription, progress, pool)

    def flexible_starts(self, problem: SpeedProblem, model: PressModel, rigid: StageResult,
                        progress: bool) -> list[StageResult]:
        """`rigid`'s NLP re-solved at each of `flexible_backoffs` other than its own (stages ``rigid@b``,
        warm from its solution). One that does not converge is marked superseded: it starts nothing."""
        starts = []
        for b in self.flexible_backoffs:
            if b == self.rigid.backoff or rigid.nlp is None:
                continue
            st = replace(self.rigid, backoff=b).solve(problem, model, WarmStart(rigid.speed, point=rigid.nlp),
                                                      "rigid", progress)
            st.name = f"rigid@{b:g}"  # after the solve: IPOPT's function names take no "@"
            if not st.success:
                st.superseded = "not a start: this re-solve of the rigid optimum did not converge"
            starts.append(st)
        return starts

    def flexible_chain(self, problem: SpeedProblem, model: PressModel, start: StageResult,
                       transcription: Transcription, progress: bool, candidate: bool = False) -> list[StageResult]:
        """The flexible stage on `model` from `start`'s speed, then the polish rounds (a `candidate`
        chain's paused as `rounds` says)."""
        solved, transcription = self.solve_refined(problem, model, transcription, WarmStart(start.speed), "flexible",
                                                   progress)
        if not solved[-1].success:
            return solved
        return [*solved, *self.rounds(problem, model, model, solved, transcription, progress, candidate=candidate)]

    def rounds(self, problem: SpeedProblem, polish_model: PressModel | None, refine_model: PressModel,
               stages: list[StageResult], transcription: Transcription, progress: bool,
               floor: float = -np.inf, candidate: bool = False) -> list[StageResult]:
        """After the chain: the polish rounds on `polish_model` (None when no stage on a model with states
        ran), then the refinement rounds on `refine_model`, from ``stages[-1]``. `floor`: the rigid
        press's optimum of the same problem (`polish`). A `candidate` chain with `polish_candidates`
        "best" pauses after its first polish round when another would run (`polish`): the stages
        so far, the last one marked `PAUSED`; `pressocp.ocp.candidates` resumes the best one
        (`resume_polish`)."""
        out: list[StageResult] = []
        if polish_model is not None and self.polish_rounds:
            out += self.polish(problem, polish_model, stages[-1], transcription, progress, floor,
                               pause=candidate and self.polish_candidates == "best")
            if PAUSED in out[-1].details:
                return out
        return out + self.after_polish(problem, polish_model, refine_model, [*stages, *out], transcription, progress)

    def after_polish(self, problem: SpeedProblem, polish_model: PressModel | None, refine_model: PressModel,
                     stages: list[StageResult], transcription: Transcription, progress: bool) -> list[StageResult]:
        """What follows the polish rounds of `stages` (`rounds`, `resume_polish`): the relaxed re-solve of
        the standing answer on `polish_model` (when there is one and the polish is on), then the
        refinement rounds on `refine_model`."""
        out: list[StageResult] = []
        if polish_model is not None and self.polish_rounds:
            out += self.relax(problem, polish_model, standing_stage(stages), transcription, progress)[0]
        if self.refine_rounds:
            out += self.refine(problem, refine_model, (stages + out)[-1], transcription, progress)
        return out

    def resume_polish(self, problem: SpeedProblem, model: PressModel, stages: list[StageResult],
                      progress: bool) -> list[StageResult]:
        """The rest of a candidate chain paused after its first polish round (`rounds`; its last stage
        in `stages` marked `PAUSED`, which `pressocp.ocp.candidates` removes): the polish rounds from the
        second on, from that round's answer and its re-simulation, then `after_polish`. `model`: the
        chain's model, rebuilt from its spec (a candidate chain polishes and refines on the same model)."""
        last = stages[-1]
        paused = last.details[PAUSED]
        transcription, value = paused["transcription"], last.details["verified_value"]
        out = self.polish_from(problem, model, last, transcription, progress, paused["simulation"], value, value,
                               start=1)
        return out + self.after_polish(problem, model, model, [*stages, *out], transcription, progress)

    @property
    def verified_reason(self) -> str:
        """Why a stage is skipped when the rigid optimum is verified on its model."""
        return (f"the rigid optimum meets the constraints on this model and its objective is within "
                f"{self.verified_ratio:g} x its rigid-press value")

    def fits(self, model: PressModel, speed: FourierSpeed, problem: SpeedProblem) -> bool:
        """Whether `speed` does not impact on `model` (its objective there within `IMPACT_RATIO` of its
        rigid-press value): a start the clearance stage can take as it is."""
        return self.screened(model, speed, problem)[1] <= IMPACT_RATIO

    @staticmethod
    def screened(model: PressModel, speed: FourierSpeed, problem: SpeedProblem, rtol: float = CHECK_RTOL):
        """`screen` of `speed` on `model` against its rigid-press objective: (sim, ratio, dense rigid
        response). The chain's checks and re-simulations run compiled (`for_repeated_use`); the stages'
        own simulations (a collocation stage's warm start) keep the model as built, so that IPOPT's
        start and path do not move with the checks' round-off
        (docs/decisions/2026-11-28-compiled-checks.md)."""
        dense = rigid_reference(problem, speed)
        sim, ratio = screen(for_repeated_use(model), speed, problem.objective_value(dense), problem.objective,
                            rtol, drive=problem.drive)
        return sim, float(ratio), dense

    def verify_stage(self, model: PressModel, stage: StageResult) -> SimResult:
        """``stage.simulation``: the stage's answer re-simulated on `model` (`verify_speed` at
        `verify_rtol`), its periodic search started from the stage's own state at t = 0 when the
        transcription has one (a collocation grid's first column: one or two cycles settle it). Run
        once per stage on its own model; its time goes to the stage's ``timing["checks"]``. On another
        model than the stage's, the re-simulation is returned and not kept."""
        own = stage.model == model.spec.describe()
        if stage.simulation is None or not own:
            t0 = time.perf_counter()
            states = stage.states
            x0 = states[:, 0] if own and states is not None and states.ndim == 2 and states.shape[0] == model.nx \
                else None
            sim = verify_speed(for_repeated_use(model), stage.speed, self.verify_rtol, x0=x0)
            if not own:
                return sim
            stage.simulation = sim
            add_time(stage, "checks", time.perf_counter() - t0)
        return stage.simulation

    def grid_error(self, stage: StageResult, problem: SpeedProblem) -> tuple[str, float]:
        """Why `stage`'s re-simulation (`verify_stage`, run before) does not confirm its NLP ("" when it
        does), and by how much the re-simulated ram speed leaves its tolerance (m/s, 0 when it does
        not). Not confirmed: not periodic, the ram speed out of tolerance, the objective more than
        `grid_tol` from the NLP's, or a limit the NLP holds at its samples exceeded between them
        (`limits_exceeded`: a finer grid follows)."""
        sim = stage.simulation
        periodic = is_periodic(sim)
        if periodic is not True:
            return f"its re-simulation is not periodic ({periodic})", 0.0
        value = problem.objective_value(sim)
        if abs(value - stage.objective) > self.grid_tol * abs(value):
            return f"re-simulated {value:.6g} against the NLP's {stage.objective:.6g}", 0.0
        viol = ram_speed_violation(sim, problem)
        if viol > 0.0:
            return f"the re-simulated ram speed leaves its tolerance by {viol:.2g} m/s", viol
        return describe_excess(limits_exceeded(problem, stage.speed, sim)), 0.0

    def solve_refined(self, problem: SpeedProblem, model: PressModel, transcription: Transcription, start: WarmStart,
                      name: str, progress: bool, rescue: bool = True) -> tuple[list[StageResult], Transcription]:
        """`transcription` on `model` from `start` (with `rescue`, solved again rescaled when it does not
        converge: `rescued`), then its follow-ups while the answer's re-simulation does not confirm it
        (`followed`). Returns the stages and the transcription of the last one."""
        if rescue:
            solved, transcription = self.rescued(problem, model, transcription, start, name, progress)
        else:
            solved = [transcription.solve(problem, model, start, name, progress)]
        more, transcription = self.followed(problem, model, transcription, solved[-1], progress)
        return solved[:-1] + more, transcription

    @staticmethod
    def rescued(problem: SpeedProblem, model: PressModel, transcription: Transcription, start: WarmStart,
                name: str, progress: bool, rescue: bool = True) -> tuple[list[StageResult], Transcription]:
        """`transcription` on `model` from `start`; when IPOPT does not converge, `rescue` is set and the
        transcription has a rescaled form (`Transcription.rescaled`: the linear solver scaling the KKT
        matrix), the same NLP again from the same start in that form (stage ``{name}_rescaled``; the
        first is kept in the record, marked ``superseded``). Returns the stages and the transcription of
        the last one (the rescaled one then serves the stages that follow)."""
        first = transcription.solve(problem, model, start, name, progress)
        again = None if first.success or not rescue else transcription.rescaled()
        if again is None:
            return [first], transcription
        first.superseded = (f"it did not converge ({first.status}); {name}_rescaled solved it again from the same "
                            f"start with the KKT matrix scaled")
        return [first, again.solve(problem, model, start, f"{name}_rescaled", progress)], again

    def followed(self, problem: SpeedProblem, model: PressModel, transcription: Transcription, first: StageResult,
                 progress: bool) -> tuple[list[StageResult], Transcription]:
        """`first` (solved by `transcription` on `model`) and, while the last answer's re-simulation
        does not confirm it (`grid_error`):

        * when only the ram speed strays (by v m/s over its tolerance tol), the same NLP again with
          the held share of the tolerance lowered by v/tol + `TIGHTEN_MARGIN` (``tightened``), started
          from the answer with its multipliers, so IPOPT moves only as far as the bounds did (stage
          ``{name}_tightened_k``; at most `MAX_TIGHTEN` times);
        * otherwise, on a finer grid (``refined``, given the answer's re-simulation: collocation with
          ``refinement="local"`` cuts only the elements where that response needs it) from the answer
          (stage ``{name}_refined_k``), while the transcription has one: collocation from the answer's
          states and multipliers carried
          to the finer grid (`pressocp.ocp.prolong`), another transcription from the answer's
          periodic state. When the carried start does not converge, the stage is solved again from
          the answer's periodic state (``{name}_refined_k_resimulated``; the first is kept in the
          record, marked ``superseded``): on the seed's hard scenes (pin caps, counterbalances) 7 of
          20 refined stages stopped at their iteration limit from either start, not always the same
          ones (docs/decisions/2026-11-29-refined-multipliers.md).

        Returns the stages (`first` included) and the transcription of the last one."""
        name, stages, tightened = first.name, [first], 0
        while stages[-1].success:
            last = stages[-1]
            finer = transcription.refined(problem.period, model.rod)
            can_tighten = last.nlp is not None and tightened < MAX_TIGHTEN and transcription.tightened(0.0) is not None
            if finer is None and not can_tighten:
                break
            sim = self.verify_stage(model, last)
            why, viol = self.grid_error(last, problem)
            if not why:
                break
            tight = transcription.tightened(viol / problem.tol + TIGHTEN_MARGIN) if viol > 0.0 and can_tighten else None
            if tight is not None:
                tightened += 1
                transcription = tight
                label, warm = f"{name}_tightened_{tightened}", WarmStart(last.speed, point=last.nlp)
            else:
                x_start = sim.states[:, 0] / model.x_scale
                where = Resimulated(model, last.speed, x_start, near_peak(problem, sim, self.grid_tol))
                finer = None if finer is None else transcription.refined(problem.period, model.rod, where)
                if finer is None:
                    break
                transcription = finer
                x0 = x_start if is_periodic(sim) is True else None
                k = sum(not s.superseded for s in stages)
                label, warm = f"{name}_refined_{k}", WarmStart(last.speed, x0, point=last.nlp)
            last.details["followed_by"] = f"{label}: {why}"
            st = transcription.solve(problem, model, warm, label, progress)
            if not st.success and "carried_from_elements" in st.details:
                st.superseded = (f"it did not converge from {last.name}'s solution carried to the finer grid "
                                 f"({st.status}); {label}_resimulated solved it again from the answer's "
                                 f"periodic response")
                stages.append(st)
                st = transcription.solve(problem, model, WarmStart(last.speed, warm.x0), f"{label}_resimulated",
                                         progress)
            stages.append(st)
        return stages, transcription

    def check(self, model: PressModel, stage: StageResult, problem: SpeedProblem) -> Check:
        """Re-simulate a rigid-press stage's answer on `model` (`screen`, `CHECK_RTOL`); its time goes
        to the stage's ``timing["checks"]``."""
        t0 = time.perf_counter()
        sim, ratio, dense = self.screened(model, stage.speed, problem)
        viol = max(ram_speed_violation(sim, problem), 0.0)
        periodic = is_periodic(sim)
        ne = ideal_inverse_dynamics(problem.press, problem.mechanism, *stage.speed.evaluate(dense.t))
        limits = limits_exceeded(problem, stage.speed, sim)
        add_time(stage, "checks", time.perf_counter() - t0)
        return Check(model=model.spec.describe(), objective=problem.objective_value(sim), ratio=ratio,
                     periodic=periodic, ram_speed_violation=viol, peak_torque=sim.peak("torque"), limits=limits,
                     verified=bool(periodic is True and ratio <= self.verified_ratio and viol <= 0.0 and not limits),
                     min_rod_tension=float(min(ne["crank_pin_tension"].min(), ne["wrist_pin_tension"].min())),
                     min_eccentricity=min(sim.min_eccentricities(model.clearance).values(), default=None))

    def polish(self, problem: SpeedProblem, model: PressModel, last: StageResult, transcription: Transcription,
               progress: bool, floor: float = -np.inf, pause: bool = False) -> list[StageResult]:
        """Up to `polish_rounds` re-solves of `last`'s NLP (`transcription` on `model`) from its answer,
        each followed by its own tightened or refined re-solves (`solve_refined`). A round that does
        not lower the periodic re-simulation's objective (at `verify_rtol`), or fails, or leaves the
        ram speed out of tolerance, is recorded as not kept, its answer being `last`'s, and ends the
        polishing; so does a kept round that gained no more than `polish_gain`. When the first round
        is not kept, `last`'s own follow-ups (`followed`, deferred by `clearance_chain`) run then.

        No round runs when `last`'s verified objective is at or below `floor` (the rigid press's
        optimum): a barrier restart escapes a local optimum above the floor, and the clearances move
        an answer below it by little (large_press, 2026-11-28: both candidates' rounds, 17-27 s each,
        re-simulated 487.609 against 487.608 and 487.582 against 487.581 N m, floor 487.631, and were
        not kept). Its follow-ups run instead, and a record ``polish_1`` says why.

        With `pause`, a kept first round after which another would run ends the rounds here, its stage
        marked `PAUSED` (`polish_from`), from where `resume_polish` goes on."""
        value = problem.objective_value
        # both re-simulated alike, at the final verification's tolerance: an optimum holds the ram
        # speed to within a few 1e-5 m/s of its tolerance, about the error of a check at rtol 1e-7
        first = self.verify_stage(model, last)
        # an answer whose re-simulation does not verify it sets no bar to beat, but a periodic one
        # still measures a round's gain
        reference = value(first) if is_periodic(first) is True else np.inf
        best = reference if not unverified_reason(problem, last.speed, first) else np.inf
        if best <= floor:
            follow, _ = self.followed(problem, model, transcription, last, progress)
            reason = (f"{last.name}'s answer re-simulates at {best:.6g}, at or below the rigid press's optimum "
                      f"{floor:.6g}")
            skipped = StageResult.skipped("polish_1", reason, model.spec.describe(), last)
            skipped.simulation = first
            return [skipped, *follow[1:]]  # the last stage's answer is the chain's
        return self.polish_from(problem, model, last, transcription, progress, first, best, reference,
                                stop=1 if pause else None)

    def polish_from(self, problem: SpeedProblem, model: PressModel, last: StageResult, transcription: Transcription,
                    progress: bool, first: SimResult, best: float, reference: float, start: int = 0,
                    stop: int | None = None) -> list[StageResult]:
        """The polish rounds ``polish_{start + 1}`` to ``polish_{polish_rounds}`` (`polish`) from the
        standing answer `last`, its re-simulation `first` and verified objective `best` (inf: none),
        `reference` the periodic objective a round's gain is measured from. With `stop`, a kept round
        ``polish_{stop}`` after which another would run ends the rounds, marked `PAUSED` (its
        ``details[PAUSED]``: the transcription to resume with and the round's re-simulation)."""
        rounds = []
        for k in range(start, self.polish_rounds):
            name = f"polish_{k + 1}"
            # `last`'s periodic response on `model`: its state starts the warm start's search
            x0 = first.states[:, 0] / model.x_scale if is_periodic(first) is True else None
            solved, _ = self.solve_refined(problem, model, transcription, WarmStart(last.speed, x0), name, progress,
                                           rescue=False)
            st = solved[-1]
            cand, new, why = self.judged(problem, model, st, best)
            if not why:
                st.details.update(verified_value=new, previous_verified_value=best if np.isfinite(best) else None)
                rounds += solved
                gain = (reference - new) / abs(reference) if np.isfinite(reference) else np.inf
                last, best, reference, first = st, new, new, cand
                if gain <= self.polish_gain:
                    break
                if k + 1 == stop and k + 1 < self.polish_rounds:
                    st.details[PAUSED] = {"transcription": transcription, "simulation": cand}
                    break
                continue
            rounds += [replace(s, superseded=f"the polish round ending in {st.name} was not kept") for s in solved[:-1]]
            if k == 0:  # the polished stage's own follow-ups, deferred by `clearance_chain`
                follow, transcription = self.followed(problem, model, transcription, last, progress)
                if len(follow) > 1:
                    rounds += [replace(solved[-1], superseded=f"not kept ({why}); {last.name} was followed up instead")]
                    rounds += follow[1:]
                    return rounds
            kept = replace(StageResult.skipped(st.name, "", model.spec.describe(), last),
                           status=f"not kept ({st.iterations} iterations: {why}); the previous answer stands",
                           iterations=st.iterations, wall_time=st.wall_time, timing=st.timing,
                           details={"verified_value": new,
                                    "previous_verified_value": best if np.isfinite(best) else None},
                           simulation=first)
            rounds.append(kept)
            break
        return rounds

    def judged(self, problem: SpeedProblem, model: PressModel, st: StageResult,
               best: float) -> tuple[SimResult | None, float | None, str]:
        """A re-solve `st` of the standing answer (a polish round, the relaxed re-solve), re-simulated on
        `model` (`verify_stage`) and judged against `best`, the standing answer's verified objective
        (inf: none to beat): its re-simulation, its objective there, and why it is not kept ("" when it
        is: periodic, the ram speed in tolerance, no limit exceeded (`unverified_reason`), lower than
        `best`). One that did not converge cannot be kept and is not re-simulated: (None, None,
        IPOPT's status)."""
        if not st.success:
            return None, None, st.status
        cand = self.verify_stage(model, st)
        new = problem.objective_value(cand)
        why = unverified_reason(problem, st.speed, cand)
        if why:
            return cand, new, why
        return cand, new, "" if new < best else f"re-simulated {new:.6g} against {best:.6g}"

    def relax(self, problem: SpeedProblem, model: PressModel, last: StageResult, transcription: Transcription,
              progress: bool) -> tuple[list[StageResult], SimResult | None]:
        """One re-solve of the answer's NLP with more of the ram-speed tolerance held (``relaxed``: the
        collocation stages hold 95 % of it and the rigid stage 90 %, because a re-simulated ram strays
        past the held value), from the answer with its multipliers, so IPOPT moves only as far as the
        bounds. Kept when its periodic re-simulation on `model` lowers the objective with the ram speed
        still in tolerance (large_press: 487.585 to 487.509 N m; press60's rigid optimum: 76.153 to
        76.125 N m); otherwise recorded as not kept. Nothing runs when the transcription has no such
        re-solve or the answer has no NLP point. When the answer's re-simulated ram already strays so
        far past the share its NLP holds that the same stray past the relaxed share would leave the
        tolerance, the re-solve holds less (`relaxed_share`, through the transcription's
        ``tightened``), or is skipped (a ``relaxed`` record says why) when that gains too little: the
        75 spm seed's answers re-simulate at 0.98 of it holding 0.95, and their relaxed re-solves
        stopped at their 8-iteration limit (about 4.5 s each), with 52 iterations not kept. Returns
        the stages (none, the kept one, or one not kept) and the standing answer's re-simulation on
        `model` (None when no re-solve was possible)."""
        tr = None if last is None or not last.success else transcription.relaxed(last)
        if tr is None:
            return [], None
        value = problem.objective_value
        t0 = time.perf_counter()
        before = self.verify_stage(model, last)
        viol = ram_speed_violation(before, problem)
        if unverified_reason(problem, last.speed, before):
            return [], before
        # the shares of the tolerance held (a transcription's ``backoff``): the answer's NLP's, the re-solve's
        held, share = last.details.get("backoff"), getattr(tr, "backoff", None)
        if held is not None and share is not None:
            past = viol / problem.tol + 1.0 - held
            fit = relaxed_share(held, share, past)
            fitted = None if fit is None else tr if fit == share else tr.tightened(share - fit)
            if fitted is None:
                why = (f"leaving the stray once more as margin adds less than {RELAX_MIN_GAIN:g}" if fit is None
                       else f"holding {fit:.3g} (the stray left once more as margin) cannot be set")
                reason = (f"the answer's re-simulated ram strays {past:.3g} of the tolerance past the {held:g} its "
                          f"NLP holds; holding {share:g} would take it out of tolerance, and {why}")
                skipped = StageResult.skipped("relaxed", reason, model.spec.describe(), last)
                skipped.simulation = before
                add_time(skipped, "checks", time.perf_counter() - t0)
                return [skipped], before
            tr = fitted
        best, checks = value(before), time.perf_counter() - t0
        st = tr.solve(problem, model, WarmStart(last.speed, point=last.nlp), "relaxed", progress)
        t0 = time.perf_counter()
        cand, new, why = self.judged(problem, model, st, best)
        if st.success and st.model != model.spec.describe():  # verify_stage timed its own model's re-simulation only
            add_time(st, "checks", checks + time.perf_counter() - t0)
        if not why:
            st.details.update(verified_value=new, previous_verified_value=best)
            return [st], cand
        return [replace(StageResult.skipped("relaxed", "", model.spec.describe(), last),
                        status=f"not kept ({st.iterations} iterations: {why}); the previous answer stands",
                        iterations=st.iterations, wall_time=st.wall_time, timing=st.timing,
                        details={"verified_value": new, "previous_verified_value": best}, simulation=before)], before

    def refine(self, problem: SpeedProblem, model: PressModel, last: StageResult, transcription: Transcription,
               progress: bool) -> list[StageResult]:
        """Trust-region rounds of multiple shooting on `model` from `last`'s answer. A round's final
        iterate is accepted (and the region grows) only when its periodic re-simulation lowers the
        objective with the ram speed in tolerance and no limit exceeded; otherwise the region shrinks.
        Each round's node states come from the verifying re-simulation of the current speed."""
        shooting = transcription.shooting() or MultipleShooting("cvodes")
        speed, step, rounds = last.speed, self.refine_step, []
        sim = verify_speed(for_repeated_use(model), speed, CHECK_RTOL)
        best = problem.objective_value(sim)
        for k in range(self.refine_rounds):
            t0 = time.perf_counter()
            settings = replace(shooting, coefficient_step=step,
                               ipopt={"ipopt.max_iter": REFINE_ITERATIONS, **shooting.ipopt})
            name = f"refine_{k + 1}"
            try:
                st = settings.solve(problem, model, WarmStart(speed, sim.states[:, 0] / model.x_scale), name, progress)
            except SimulationError as err:  # the verified answer so far stands
                rounds.append(StageResult.skipped(name, f"stopped: {str(err).splitlines()[0]}",
                                                  model.spec.describe(), last))
                break
            cand, ratio = screen(for_repeated_use(model), st.last_speed, best, problem.objective, CHECK_RTOL,
                                 drive=problem.drive)
            viol = max(ram_speed_violation(cand, problem), 0.0)
            accepted = bool(ratio < 1.0 and not unverified_reason(problem, st.last_speed, cand))
            value = ratio * best
            st.details.update(coefficient_step=step, accepted=accepted, verified_value=value, ram_speed_violation=viol)
            st.wall_time = time.perf_counter() - t0
            if accepted:
                speed, sim, best, step = st.last_speed, cand, value, step * REFINE_GROW
                st.speed, st.objective = st.last_speed, value
                last = st
            else:
                st.speed, st.objective = speed, best
                step *= REFINE_SHRINK
            rounds.append(st)
        return rounds


def near_peak(problem: SpeedProblem, sim: SimResult, share: float) -> np.ndarray:
    """Times within the period (s, from the response's start) where the problem's objective on the
    re-simulated response `sim` is within `share` of its largest value, for a peak objective (an
    empty array for the others): where the NLP's epigraph decides its objective."""
    objective = get_objective(problem.objective)
    if objective.kind != "peak":
        return np.zeros(0)
    magnitude = np.max(np.abs(np.vstack(objective.sample_terms(sim, problem.drive))), axis=0)
    t = np.asarray(sim.t, float) - float(sim.t[0])
    return t[magnitude >= (1.0 - share) * magnitude.max()] % problem.period


def raises(problem: SpeedProblem, rigid: StageResult, start: StageResult, transcription: Transcription,
           margin: float | None, done: int, below: float | None = None) -> bool:
    """Whether a target stage from `start` that does not converge is followed by the no-reversal
    stage at a raised margin (after `done` raises of `margin`, the margin `start` was solved at): when
    `start` is a no-reversal answer (not `rigid`) whose journals leave their walls on the clearance
    model (`loses_contact`), fewer than `MARGIN_RAISES` raises ran and the raised margin can be held.
    Such a target stage is not rescued: a start the transcription cannot reach is the cause, not the
    KKT matrix's scaling. From 6 such starts (drawing75 and its two 1 kN variants, press75 with a
    gas spring at margin 0.02, forming40 at both margins) the rescaled re-solve stopped at its
    iteration limit each time; from the one start that kept its journals on their walls (the gas
    spring at 0.05) it converged (docs/decisions/2026-12-01-raise-before-rescue.md). With `below`, only
    when the start's min |e|/c is below it too (`RAISE_AHEAD`: the raise before the target stage)."""
    if start is rigid or margin is None or done >= MARGIN_RAISES or not loses_contact(start, transcription):
        return False
    if below is not None and not start.check.min_eccentricity < below:
        return False
    return problem.without_reversal(min(MARGIN_FACTOR * margin, MAX_MARGIN)) is not None


def loses_contact(stage: StageResult, transcription: Transcription) -> bool:
    """Whether `stage`'s answer, re-simulated on the clearance model (``stage.check``), has a journal
    leave its bearing wall where `transcription` keeps every journal on it (its ``min_eccentricity``)."""
    keep = getattr(transcription, "min_eccentricity", None)
    check = stage.check
    return bool(keep is not None and check is not None and check.min_eccentricity is not None
                and check.min_eccentricity < keep)


def rod_undeformed(model: PressModel, base: PressModel, x: np.ndarray) -> np.ndarray:
    """A scaled state of the flexible-rod `model` from the (unscaled) state `x` of its rigid-rod `base`:
    the states both name (the journals') copied, the rod's coordinates and rates zero."""
    out = np.zeros(model.nx)
    for i, name in enumerate(base.state_names):
        if name in model.state_names:
            k = model.state_names.index(name)
            out[k] = x[i] / model.x_scale[k]
    return out


def add_time(stage: StageResult, key: str, seconds: float) -> None:
    """Add `seconds` to ``stage.timing[key]`` and to the stage's wall time."""
    stage.timing[key] = stage.timing.get(key, 0.0) + seconds
    stage.timing["total"] = stage.timing.get("total", stage.wall_time) + seconds
    stage.wall_time += seconds


def max_relative_change(speed: FourierSpeed, other: FourierSpeed, samples: int = 4001) -> float:
    """max |omega - omega_other| over the period, divided by the mean speed."""
    t = np.linspace(0.0, speed.period, samples)
    return float(np.max(np.abs(speed.omega(t) - other.omega(t))) / speed.mean_speed)
