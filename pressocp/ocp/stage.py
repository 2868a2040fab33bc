"""The transcription contract: a warm start goes in, a `StageResult` comes out.

Every transcription (`Rigid`, `MultipleShooting`, `Collocation`) is a settings dataclass derived
from `Transcription`, with

    solve(problem, model, start: WarmStart, name="...", progress=False) -> StageResult

and the hooks the strategy calls (`Transcription.refined`, ``tightened``, ``relaxed``, ...).

`Check` records how a stage's answer did when re-simulated on another model.
"""

from __future__ import annotations

from dataclasses import MISSING, asdict, dataclass, field, fields
from typing import Any, ClassVar

import numpy as np

from ..model import PressModel
from ..problem import SpeedProblem
from ..result import SimResult
from ..speed import FourierSpeed
from .nlp import ParametricPoint


@dataclass
class NlpPoint:
    """A state transcription's NLP solution, to start the same NLP (same grid, same window samples;
    other bounds allowed) from it with its multipliers.

    Attributes
    ----------
    w, lam_x, lam_g : ndarray
        The NLP's variables and IPOPT's multipliers.
    band : ndarray of int
        The samples the ram speed was held at (`pressocp.ocp.states.window_band`).
    scale : float
        The objective's scale in that NLP.
    grid : tuple
        The transcription's grid it belongs to (e.g. elements and degree).
    groups : list of (name, first index, size)
        The constraint groups (`pressocp.ocp.nlp.Constraints.groups`): where each group's
        multipliers lie in ``lam_g``.
    """

    w: np.ndarray
    lam_x: np.ndarray
    lam_g: np.ndarray
    band: np.ndarray
    scale: float
    grid: tuple
    groups: list = field(default_factory=list)


@dataclass
class WarmStart:
    """Where a stage starts.

    Attributes
    ----------
    speed : FourierSpeed
        Start speed (period = the problem's).
    x0 : ndarray, optional
        Its periodic scaled state on the stage's model, if known (saves a search).
    point : NlpPoint, optional
        A solution of the same NLP with its multipliers: a transcription on the same grid starts
        there, primal and dual (no simulation, and IPOPT stays at that optimum when nothing moved).
        Collocation on a finer grid (an even split of the point's) starts there too, its states and
        multipliers carried to the finer grid (`pressocp.ocp.prolong`).
    """

    speed: FourierSpeed
    x0: np.ndarray | None = None
    point: NlpPoint | None = None


@dataclass
class Check:
    """A stage's answer re-simulated on a model with states.

    Attributes
    ----------
    model : str
        The model (`ModelSpec.describe`).
    objective : float
        The objective on that model's response, in its unit.
    ratio : float
        ``objective`` over the stage's own value.
    periodic : bool or str
        True: periodic steady state found; otherwise why not (an impacting response is not searched).
    ram_speed_violation : float
        max(|v - ram_speed| - tol, 0) over the model's own height window, m/s.
    peak_torque : float
        N m on that model.
    verified : bool
        Periodic, ratio within the strategy's limit, the ram speed in tolerance and no limit exceeded.
    min_rod_tension : float or None
        Smaller axial rod tension of the two pins on the rigid press, N (negative: the joint forces
        reverse); rigid stages only.
    min_eccentricity : float or None
        Smallest journal eccentricity ratio |e|/c of the clearance joints over the re-simulated cycle
        (< 1: a journal left its bearing wall); None without clearance joints.
    limits : dict
        The problem's limits (pin-force cap, drive) the re-simulation exceeds, with the excess as a
        share of each (`pressocp.verify.limits_exceeded`).
    """

    model: str
    objective: float
    ratio: float
    periodic: bool | str
    ram_speed_violation: float
    peak_torque: float
    verified: bool
    min_rod_tension: float | None = None
    min_eccentricity: float | None = None
    limits: dict = field(default_factory=dict)


@dataclass
class StageResult:
    """One stage of an optimisation.

    Attributes
    ----------
    name : str
        "rigid", "no_reversal", "soft", "target", "flexible", "polish_k", "refine_k".
    transcription : str
        The transcription and its settings (its repr), or "skipped".
    model : str
        The model the stage solved (`ModelSpec.describe`).
    success : bool
        IPOPT's success flag; when False ``speed`` is the least-infeasible iterate.
    status : str
        IPOPT's return status, or why the stage was skipped.
    iterations : int
    wall_time : float
        s.
    objective : float
        The objective at ``speed`` as the stage sees it (its samples, its model), in its unit.
    speed : FourierSpeed
        The stage's answer.
    last_speed : FourierSpeed
        IPOPT's final iterate (equals ``speed`` on success).
    t1 : float
        Start of the time interval on which the stage held the ram speed, s.
    history : list of float
        Objective per iteration, in its unit.
    barrier : list of float
        IPOPT's barrier parameter per iteration.
    iteration_log : dict
        Per iteration: ``time_s`` since the stage started, IPOPT's scaled ``inf_pr`` and ``inf_du``.
    violations_start, violations : dict
        Largest violation per constraint group at the start and at ``speed``.
    details : dict
        Transcription-specific plain data (grid, warm-start facts, collocation defect, ...).
    timing : dict
        Where the stage's wall time went, s: IPOPT's split (`pressocp.ocp.nlp.timing_split`) and the
        stage's own work around it (``start``: warm start; ``checks``: re-simulations of its answer).
    check : Check or None
        The answer re-simulated on the target model (rigid stages of a chain).
    states : ndarray or None
        Scaled states of the solution (node or collocation states); not saved.
    point : ParametricPoint or None
        The NLP at its solution, when the stage's model carried press parameters
        (`pressocp.optimum_sensitivities`); not saved.
    superseded : str
        Why a failed stage does not fail the result (the chain went on another way), else empty.
    simulation : SimResult or None
        The answer's periodic re-simulation on the stage's model at the strategy's ``verify_rtol``,
        when the strategy ran one (`Strategy.verify_stage`); not saved.
    nlp : NlpPoint or None
        The NLP's solution with its multipliers, for a primal-dual warm start on the same grid
        (transcriptions that give one); not saved.
    settings : dict
        The transcription's `Transcription.settings` (empty for a skipped stage): `transcription_from`
        rebuilds it.
    """

    name: str
    transcription: str
    model: str
    success: bool
    status: str
    iterations: int
    wall_time: float
    objective: float
    speed: FourierSpeed
    last_speed: FourierSpeed
    t1: float
    history: list = field(default_factory=list)
    barrier: list = field(default_factory=list)
    iteration_log: dict = field(default_factory=dict)
    violations_start: dict = field(default_factory=dict)
    violations: dict = field(default_factory=dict)
    details: dict = field(default_factory=dict)
    timing: dict = field(default_factory=dict)
    check: Check | None = None
    states: np.ndarray | None = field(default=None, repr=False)
    point: ParametricPoint | None = field(default=None, repr=False)
    superseded: str = ""
    simulation: SimResult | None = field(default=None, repr=False)
    nlp: NlpPoint | None = field(default=None, repr=False)
    settings: dict = field(default_factory=dict)

    @classmethod
    def skipped(cls, name: str, reason: str, model: str, start: "StageResult") -> "StageResult":
        """A stage not run: its answer is `start`'s."""
        return cls(name=name, transcription="skipped", model=model, success=True, status=f"skipped: {reason}",
                   iterations=0, wall_time=0.0, objective=start.objective, speed=start.speed,
                   last_speed=start.speed, t1=start.t1)

    @property
    def was_skipped(self) -> bool:
        return self.transcription == "skipped"

    def to_dict(self) -> dict:
        """Plain data (JSON-safe); ``states`` and ``point`` are left out."""
        d = {f.name: getattr(self, f.name) for f in fields(self)
             if f.name not in ("states", "point", "speed", "last_speed", "check", "simulation", "nlp")}
        d.update(speed=self.speed.to_dict(), last_speed=self.last_speed.to_dict(),
                 check=None if self.check is None else asdict(self.check))
        return d

    @classmethod
    def from_dict(cls, data: dict) -> "StageResult":
        d = dict(data)
        d["speed"], d["last_speed"] = FourierSpeed.from_dict(d["speed"]), FourierSpeed.from_dict(d["last_speed"])
        d["check"] = None if d.get("check") is None else Check(**d["check"])
        return cls(**d)


@dataclass(frozen=True)
class Resimulated:
    """A stage's answer re-simulated, as a transcription's local refinement reads it.

    Attributes
    ----------
    model : PressModel
        The model the stage solved on.
    speed : FourierSpeed
        The stage's answer.
    x0 : ndarray
        The re-simulation's scaled state at t = 0 (the periodic one when it is periodic).
    near_peak : ndarray
        Times within the period (s) where the re-simulated objective is near its largest value (a
        peak objective; empty otherwise): the NLP's objective is decided there.
    """

    model: PressModel
    speed: FourierSpeed
    x0: np.ndarray
    near_peak: np.ndarray = field(default_factory=lambda: np.zeros(0))


class Transcription:
    """The base of every transcription: a frozen settings dataclass with ``solve`` and the hooks the
    strategy calls. A hook's default here is "this transcription has none"; a transcription overrides
    the hooks it has. A new transcription is one module with its subclass (registered by subclassing:
    `transcription_from` rebuilds it from its `settings`)."""

    #: Whether the transcription solves models with states (else only the rigid press).
    has_states: ClassVar[bool] = True
    #: Whether a clearance stage of the strategy starts on a softened contact first.
    needs_soft_start: ClassVar[bool] = False
    #: Whether `prepare` compiles something (`optimize_speed` then runs it in a worker while the
    #: rigid stage runs).
    compiles_ahead: ClassVar[bool] = False
    #: Whether a solve on a model that carries press parameters returns the NLP at its solution as a
    #: `ParametricPoint` (``StageResult.point``), which `optimum_sensitivities` differentiates.
    gives_parametric_point: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        TRANSCRIPTIONS[cls.__name__] = cls

    def solve(self, problem: SpeedProblem, model: PressModel, start: WarmStart, name: str = "target",
              progress: bool = False) -> StageResult:
        """One stage: the NLP on `model` from `start`."""
        raise NotImplementedError(f"{type(self).__name__} has no solve")

    def refined(self, period: float, rod: str = "rigid", where: Resimulated | None = None) -> "Transcription | None":
        """The same transcription on a finer grid for a period and a model's rod ("rigid" or
        "flexible"), or None when it has none (the strategy refines while a stage's re-simulation
        disagrees with the NLP). `where`, the disagreeing answer re-simulated, lets it refine where
        that response needs it; without it, the grid it would refine at most."""
        return None

    def tightened(self, share: float) -> "Transcription | None":
        """The same transcription holding `share` less of the ram-speed tolerance, or None."""
        return None

    def relaxed(self, stage: StageResult) -> "Transcription | None":
        """`stage`'s NLP holding more of the ram-speed tolerance (started from its `NlpPoint`), or None
        when there is no such re-solve."""
        return None

    def rescaled(self) -> "Transcription | None":
        """The same transcription with its linear solver scaling the KKT system, for a second solve
        from the same start after a stage that did not converge, or None when it has no such setting
        or uses it already."""
        return None

    def shooting(self) -> "Transcription | None":
        """The multiple-shooting transcription that the strategy's trust-region refinement runs: this
        one when it is multiple shooting, else None (the strategy then uses its default)."""
        return None

    def prepare(self, problem: SpeedProblem, model: PressModel, speed: FourierSpeed) -> float:
        """Compile into the compile cache what a solve on `model` compiles, without solving; return the
        compile seconds (none here: see `compiles_ahead`)."""
        return 0.0

    def settings(self) -> dict:
        """The settings as plain data, ``type`` naming the class (`transcription_from` rebuilds it)."""
        return {"type": type(self).__name__, **{f.name: getattr(self, f.name) for f in fields(self)}}


#: ``StageResult.details`` key of a candidate chain's polish round after which the chain paused
#: (`Strategy.rounds`); its value holds the transcription the rounds resume with and the round's
#: re-simulation (`Strategy.resume_polish`). `pressocp.ocp.candidates` removes it from every chain.
PAUSED = "polish_paused"

#: Transcription classes by name (every subclass of `Transcription`).
TRANSCRIPTIONS: dict[str, type[Transcription]] = {}


def transcription_from(settings: dict) -> Transcription:
    """The transcription whose `Transcription.settings` are `settings`."""
    data = dict(settings)
    kind = data.pop("type", None)
    if kind not in TRANSCRIPTIONS:
        raise ValueError(f"settings name no known transcription: type {kind!r}, known {sorted(TRANSCRIPTIONS)}")
    return TRANSCRIPTIONS[kind](**data)


def settings_repr(obj: Any) -> str:
    """``Name(field=value, ...)`` of a settings dataclass, the fields at their default left out."""
    parts = []
    for f in fields(obj):
        default = f.default if f.default is not MISSING else (
            f.default_factory() if f.default_factory is not MISSING else MISSING)
        value = getattr(obj, f.name)
        if default is MISSING or value != default:
            parts.append(f"{f.name}={value!r}")
    return f"{type(obj).__name__}({', '.join(parts)})"


def standing_stage(stages: list[StageResult]) -> StageResult | None:
    """The stage whose answer stands: the last one that ran (not skipped) and was not superseded (a
    losing candidate, a polish round not kept); None when there is none."""
    return next((s for s in reversed(stages) if not s.was_skipped and not s.superseded), None)
