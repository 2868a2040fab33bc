"""`OcpResult`: an optimal crank speed, how it was found and how it was verified; saved and reloaded
as JSON."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..io import check_run_file, versions, write_json
from ..series import PEAK_SERIES
from ..model import ModelSpec
from ..problem import SpeedProblem
from ..result import SimResult
from ..speed import FourierSpeed
from .nlp import EVALUATIONS
from .stage import StageResult
from ..simulate import for_repeated_use
from ..verify import cap_excess, verify_speed

#: Version of the JSON layout written by `OcpResult.to_json`.
FORMAT = 1


def peaks_of(sim: SimResult) -> dict[str, float]:
    """Peak magnitudes of `PEAK_SERIES`, keyed by series name (N m or N)."""
    return {k: sim.peak(k) for k in PEAK_SERIES}


@dataclass
class OcpResult:
    """An optimal (or best-iterate) crank speed, its stages and its verification.

    Attributes
    ----------
    problem : SpeedProblem
        What was asked.
    model : ModelSpec
        The target model level (the press is ``problem.press``).
    transcription, strategy : str
        The clearance-stage transcription and the strategy, with their settings.
    speed : FourierSpeed
        The answer; ``speed.amplitude`` and ``speed.phase`` give r_k, phi_k.
    initial_speed : FourierSpeed
        Where the chain started (the kinematic design unless given).
    objective_value : float
        The objective as the last stage that ran reported it (its samples, its model), in its unit.
    verified_objective : float
        The objective on the verification re-simulation, in its unit.
    peaks, initial_peaks : dict
        Peak |torque| (N m) and peak slider normal, crank-pin and wrist-pin forces (N) of the answer and
        of the initial speed on the target model (periodic re-simulation).
    rigid_peak_torque : float
        Peak torque of the rigid-press optimum on the rigid press, N m: the floor (the rigid stage's
        answer, or its relaxed re-solve where that holds more of the ram-speed tolerance and was kept).
    t1, t2 : float
        When the re-simulated ram enters and leaves the height window, s.
    success : bool
        Every stage that ran converged; when False ``speed`` is the failing stage's least-infeasible
        iterate and ``status`` names the stage.
    status : str
    periodic : bool or str
        True: the verification found a periodic steady state; otherwise why not.
    max_ram_speed_violation : float
        max(|v - ram_speed| - tol, 0) over the re-simulated ram's height window, m/s.
    limits : dict
        The problem's limits the re-simulation exceeds (the pin-force cap, the drive's ratings), each
        with its excess as a share of the limit (`pressocp.verify.limits_exceeded`); empty when every
        limit holds. The NLP holds them at its samples only.
    min_omega : float
        Smallest crank speed over the period, rad/s.
    iterations : int
        IPOPT iterations over all stages.
    wall_time : float
        s.
    stages : list of StageResult
    verify_rtol : float
        Tolerance of the verification.
    versions : dict
        Package versions that produced it.
    simulation, initial_simulation : SimResult or None
        The verification responses (not saved in JSON; `resimulate` recomputes).
    timing : dict
        Wall time outside the stages, s: ``verification`` (the answer's and the initial speed's
        re-simulations; ``verification_compile`` of it compiling their output functions), ``other``
        (set-up, the initial design) and, when the clearance stages' functions were compiled ahead in a
        worker alongside the rigid stage, ``prepare`` (``prepare_compile`` of it compiling); `time_table`
        adds the stages.
    """

    problem: SpeedProblem
    model: ModelSpec
    transcription: str
    strategy: str
    speed: FourierSpeed
    initial_speed: FourierSpeed
    objective_value: float
    verified_objective: float
    peaks: dict
    initial_peaks: dict
    rigid_peak_torque: float
    t1: float
    t2: float
    success: bool
    status: str
    periodic: bool | str
    max_ram_speed_violation: float
    min_omega: float
    iterations: int
    wall_time: float
    stages: list = field(default_factory=list)
    verify_rtol: float = 1e-9
    versions: dict = field(default_factory=versions)
    simulation: SimResult | None = field(default=None, repr=False)
    initial_simulation: SimResult | None = field(default=None, repr=False)
    timing: dict = field(default_factory=dict)
    limits: dict = field(default_factory=dict)

    # Views -------------------------------------------------------------------------------------
    @property
    def objective(self) -> str:
        """Name of the objective."""
        return self.problem.objective

    @property
    def peak_torque(self) -> float:
        """Peak |motor torque| of the answer on the target model, N m."""
        return float(self.peaks["torque"])

    @property
    def initial_peak_torque(self) -> float:
        """Peak |motor torque| of the initial speed on the target model, N m."""
        return float(self.initial_peaks["torque"])

    @property
    def verified(self) -> bool:
        """Periodic re-simulation found, ram speed in tolerance over the model's window, no limit of the
        problem exceeded on it (`limits`)."""
        return self.periodic is True and self.max_ram_speed_violation <= 0.0 and not self.limits

    @property
    def rigid(self) -> StageResult:
        """The rigid-press stage (after the ``counterbalance`` stage, when it ran)."""
        return next(s for s in self.stages if s.name == "rigid")

    @property
    def history(self) -> list[float]:
        """Objective per IPOPT iteration, every stage in order, in its unit."""
        return [h for s in self.stages for h in s.history]

    @property
    def amplitude(self) -> np.ndarray:
        """r_k, rad/s."""
        return self.speed.amplitude

    @property
    def phase(self) -> np.ndarray:
        """phi_k, rad."""
        return self.speed.phase

    def stage(self, name: str) -> StageResult:
        """The stage called `name`."""
        for s in self.stages:
            if s.name == name:
                return s
        raise KeyError(f"no stage {name!r}; stages: {[s.name for s in self.stages]}")

    def time_table(self) -> list[dict]:
        """Where the wall time went, a row per stage and one for the verification, each with
        ``wall`` and its parts (s): ``build`` (the NLP and its functions generated, linked and set up),
        ``compile`` (the C compiler's time: none when the object files came from the cache), ``functions``
        (objective, constraints and their derivatives), ``linear_solver`` (IPOPT's own time, MUMPS
        above all), ``start`` (the warm start's simulations), ``checks`` (re-simulations of the
        stage's answer), and ``iterations``."""
        rows = []
        for s in self.stages:
            t = s.timing
            rows.append({"stage": s.name, "iterations": s.iterations, "wall": s.wall_time,
                         "build": t.get("build", 0.0), "compile": t.get("compile", 0.0),
                         "functions": sum(t.get(k, 0.0) for k in EVALUATIONS),
                         "linear_solver": t.get("solver", 0.0), "start": t.get("start", 0.0),
                         "checks": t.get("checks", 0.0)})
        for key in ("prepare", "verification", "other"):
            if key in self.timing:
                rows.append({"stage": key, "iterations": 0, "wall": self.timing[key], "build": 0.0,
                             "compile": self.timing.get(f"{key}_compile", 0.0), "functions": 0.0,
                             "linear_solver": 0.0, "start": 0.0, "checks": self.timing[key] if key == "verification"
                             else 0.0})
        return rows

    def resimulate(self, rtol: float | None = None) -> SimResult:
        """The answer re-simulated (periodic, CVODES) on the target model, at `verify_rtol` by default, as
        the optimiser verified it (compiled where it was: `pressocp.simulate.for_repeated_use`). At rtol
        1e-8 a compiled and an interpreted run can differ by 1e-4 in the peak (round-off, amplified where
        a journal leaves its wall), so the other path would not reproduce the saved peak."""
        model = for_repeated_use(self.model.build(self.problem.press, self.problem.n_harmonics))
        return verify_speed(model, self.speed, self.verify_rtol if rtol is None else rtol)

    # Saving ------------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Plain data (JSON-safe), without the time series."""
        return {
            "format": FORMAT, "versions": self.versions, "problem": self.problem.to_dict(),
            "model": self.model.to_dict(), "transcription": self.transcription, "strategy": self.strategy,
            "speed": self.speed.to_dict(), "initial_speed": self.initial_speed.to_dict(),
            "objective_value": self.objective_value, "verified_objective": self.verified_objective,
            "peaks": self.peaks, "initial_peaks": self.initial_peaks, "rigid_peak_torque": self.rigid_peak_torque,
            "t1": self.t1, "t2": self.t2, "success": self.success, "status": self.status,
            "verification": {"periodic": self.periodic, "max_ram_speed_violation": self.max_ram_speed_violation,
                             "rtol": self.verify_rtol, "limits": self.limits},
            "min_omega": self.min_omega, "iterations": self.iterations, "wall_time": self.wall_time,
            "timing": self.timing, "stages": [s.to_dict() for s in self.stages],
        }

    def to_json(self, path: str | Path) -> Path:
        """Write `to_dict` as JSON (atomically). Returns the path."""
        return write_json(path, self.to_dict())

    @classmethod
    def from_dict(cls, data: dict) -> "OcpResult":
        """Inverse of `to_dict` (no time series: `resimulate` recomputes them). A file without the
        verification's ``limits`` (written before they were checked) gets the pin-force cap's from its
        saved peaks; a drive's need the re-simulation (`resimulate`, `pressocp.verify.limits_exceeded`)."""
        if data.get("format") != FORMAT:
            raise ValueError(f"unknown result format {data.get('format')!r} (this pressocp reads {FORMAT})")
        d = dict(data)
        ver = d.pop("verification")
        d.pop("format")
        problem = SpeedProblem.from_dict(d.pop("problem"))
        return cls(problem=problem, model=ModelSpec.from_dict(d.pop("model")),
                   speed=FourierSpeed.from_dict(d.pop("speed")),
                   initial_speed=FourierSpeed.from_dict(d.pop("initial_speed")),
                   stages=[StageResult.from_dict(s) for s in d.pop("stages")], periodic=ver["periodic"],
                   max_ram_speed_violation=ver["max_ram_speed_violation"], verify_rtol=ver["rtol"],
                   limits=ver["limits"] if "limits" in ver else cap_excess(problem, d["peaks"]), **d)

    @classmethod
    def from_json(cls, path: str | Path) -> "OcpResult":
        """Read a file written by `to_json`. In an output folder with a manifest, the folder is checked
        first (`pressocp.io.check_run_file`): a file of a mixed or changed run raises `RunMismatch`."""
        path = Path(path)
        try:
            check_run_file(path)
            data = json.loads(path.read_text())
        except FileNotFoundError:
            raise FileNotFoundError(f"no result file at {path}") from None
        except json.JSONDecodeError as err:
            raise ValueError(f"{path}: not JSON ({err})") from None
        return cls.from_dict(data)
