"""Scenario files: a press, a speed problem, a model level and solver choices in one TOML file.

    name = "default press, 75 spm, 0.1 mm clearances"
    [press]              # any PressParams field, SI
    slider_mass = 150.0
    [press.wrist_pin]    # any Bearing field
    clearance = 1.0e-4
    [problem]            # SpeedProblem fields; the cycle as stroke_rate_spm or period_s
    stroke_rate_spm = 75
    ram_speed = -0.1
    window = [0.7, 0.3]
    objective = "peak_torque"
    [model]
    rod = "rigid"
    clearance = ["crank_pin", "wrist_pin"]
    [solver]
    transcription = "auto"

A [drive] table (`pressocp.drive.Drive`: gear_ratio, peak_torque, continuous_torque, max_speed,
...) adds the servo motor's figures to every result.

A press other than the slider-crank names its linkage in a [mechanism] table (`MECHANISMS`), whose
drive geometry gives the press's crank_radius and rod_length unless [press] sets them:

    [mechanism]
    name = "knuckle_joint"    # or "six_bar"; any field of the mechanism
    input_inertia = 0.05
    [mechanism.drive]         # any field of its geometry (KnucklePress, SixBarPress)
    input_crank = 0.04

Every key is checked before anything is solved: an unknown key names the nearest valid one, a wrong
type names the expected type, and a value out of range names the key, the value and the range.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import tomllib
import typing
from dataclasses import dataclass, field, fields
from importlib import resources
from pathlib import Path
from typing import Any

from . import checks as chk
from .compile_cache import check_jit
from .drive import Drive
from .mechanism import MECHANISMS, SLIDER_CRANK, Mechanism, mechanism_to_dict
from .model import ModelSpec, PressModel
from .ocp import VERIFY_RTOL_RANGE, Collocation, MultipleShooting, OcpResult, Strategy, optimize_speed
from .params import NESTED, PressParams
from .problem import SpeedProblem
from .speed import FourierSpeed

#: Transcriptions a scenario can name ("auto": the default chain's, collocation).
TRANSCRIPTIONS = ("auto", "collocation", "shooting-idas", "shooting-cvodes")
#: Keys of the [problem] table other than the cycle (`stroke_rate_spm` or `period_s`).
PROBLEM_KEYS = tuple(f.name for f in fields(SpeedProblem) if f.name not in ("press", "period", "mechanism", "drive"))
#: Tables a scenario may leave out, which `--set` may still name.
OPTIONAL_TABLES = ("mechanism", "drive")
#: Keys of the [solver] table.
SOLVER_KEYS = ("transcription", "elements", "jit", "verify_rtol", "polish_rounds", "flexible_backoffs")


class ScenarioError(ValueError):
    """A scenario that cannot be used: the message names the file (if any) and the key."""


@dataclass(frozen=True)
class SolverChoice:
    """The [solver] table.

    Attributes
    ----------
    transcription : str
        One of `TRANSCRIPTIONS`.
    elements : int or None
        Collocation elements per period (None: the default, 2000 per second).
    jit : bool or "auto"
        Compile collocation's model functions.
    verify_rtol : float
        Tolerance of the final re-simulation.
    polish_rounds : int
        Most re-solves of the last stage from its own answer (`Strategy.polish_rounds`), 0..10.
    flexible_backoffs : tuple of float
        Ram-speed backoffs of the extra starts of a flexible rod between ideal joints
        (`Strategy.flexible_backoffs`; empty: the rigid optimum only).
    """

    transcription: str = "auto"
    elements: int | None = None
    jit: bool | str = "auto"
    verify_rtol: float = 1e-9
    polish_rounds: int = 3
    flexible_backoffs: tuple[float, ...] = Strategy.flexible_backoffs

    def __post_init__(self) -> None:
        # every key is checked here, when the scenario loads, not when a solve starts (the
        # transcription's name in `Scenario.from_dict`, with a suggestion)
        if self.elements is not None:
            chk.integer("elements", self.elements, 10, 100_000)
        check_jit(self.jit)
        r = chk.finite("verify_rtol", self.verify_rtol)
        lo, hi = VERIFY_RTOL_RANGE
        if not lo <= r <= hi:
            raise ValueError(f"verify_rtol must be in [{lo:g}, {hi:g}], got {self.verify_rtol!r} (the final "
                             "re-simulation's relative tolerance; 1e-9 by default)")
        object.__setattr__(self, "verify_rtol", r)
        chk.integer("polish_rounds", self.polish_rounds, 0, 10)
        object.__setattr__(self, "flexible_backoffs", tuple(self.flexible_backoffs))
        self.make_strategy()  # checks the backoffs, as the strategy does

    def make_transcription(self) -> Collocation | MultipleShooting:
        """The transcription object this choice names (`optimize_speed`'s ``transcription``)."""
        if self.transcription.startswith("shooting-"):
            return MultipleShooting(integrator=self.transcription.removeprefix("shooting-"))
        return Collocation(elements=self.elements, jit=self.jit)

    def make_strategy(self) -> Strategy:
        """The default stage chain with this choice's verification tolerance, polish rounds and flexible
        starts."""
        return Strategy(verify_rtol=self.verify_rtol, polish_rounds=self.polish_rounds,
                        flexible_backoffs=self.flexible_backoffs)


@dataclass(frozen=True)
class Scenario:
    """A named scenario: the speed `problem` (which holds the press), the `model` level and the `solver`
    choice, read from and written to TOML."""

    name: str
    problem: SpeedProblem
    model: ModelSpec = field(default_factory=ModelSpec)
    solver: SolverChoice = field(default_factory=SolverChoice)

    @property
    def press(self) -> PressParams:
        return self.problem.press

    def check_speed(self, speed: FourierSpeed | None, name: str = "speed") -> None:
        """Raise ScenarioError unless `speed` (if given) has the problem's period, at most its
        harmonics, and a crank speed above 0 throughout."""
        if speed is not None and not math.isclose(speed.period, self.problem.period, rel_tol=1e-9, abs_tol=0.0):
            raise ScenarioError(f"{name}: the speed's period is {speed.period:g} s but the scenario's is "
                                f"{self.problem.period:g} s; set the scenario's cycle to match, e.g. "
                                f"--set problem.period_s={speed.period!r}")
        if speed is not None and speed.min_speed() <= 0.0:
            raise ScenarioError(f"{name}: the crank speed falls to {speed.min_speed():.4g} rad/s, so the crank "
                                "stops or turns back within the cycle; a press speed stays above 0 (check the "
                                "file's coefficients)")
        if speed is not None and speed.n_harmonics > self.problem.n_harmonics:
            raise ScenarioError(f"{name}: the speed has {speed.n_harmonics} harmonics but the scenario's problem "
                                f"{self.problem.n_harmonics}; set the problem's to match, e.g. "
                                f"--set problem.n_harmonics={speed.n_harmonics}")

    def build_model(self) -> PressModel:
        """The scenario's model level for its press (`ModelSpec.build`)."""
        return self.model.build(self.press, self.problem.n_harmonics)

    def optimize(self, progress: bool = True, *, initial: FourierSpeed | None = None,
                 strategy: Strategy | None = None) -> OcpResult:
        """`optimize_speed` of the problem on the scenario's model with its solver choice (`strategy`
        replaces the solver's stage chain, `initial` the start)."""
        return optimize_speed(self.problem, self.build_model(), self.solver.make_transcription(),
                              self.solver.make_strategy() if strategy is None else strategy, progress,
                              initial=initial)

    # Reading -----------------------------------------------------------------------------------
    @classmethod
    def load(cls, path: str | Path) -> "Scenario":
        """Read a scenario file (TOML). A bundled one by its name: ``Scenario.load("press75")``."""
        p = Path(path)
        if not p.exists() and p.suffix == "" and str(path) in bundled():
            return cls.bundled(str(path))
        try:
            text = p.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise ScenarioError(f"{p}: no such scenario file (bundled scenarios: {', '.join(bundled())})") from None
        except IsADirectoryError:
            raise ScenarioError(f"{p}: is a folder, not a scenario file") from None
        except UnicodeDecodeError as err:
            raise ScenarioError(f"{p}: not a text scenario file (not UTF-8: {err.reason} at byte {err.start})") from None
        return cls.from_toml(text, source=str(p))

    @classmethod
    def bundled(cls, name: str) -> "Scenario":
        """A scenario shipped with pressocp (`bundled`)."""
        names = bundled()
        if name not in names:
            raise ScenarioError(f"no bundled scenario {name!r}{_suggest(name, names)}; bundled: {', '.join(names)}")
        text = resources.files("pressocp").joinpath("scenarios", f"{name}.toml").read_text(encoding="utf-8")
        return cls.from_toml(text, source=f"bundled scenario {name!r}")

    @classmethod
    def from_toml(cls, text: str, source: str = "scenario") -> "Scenario":
        """Parse TOML text (errors say where)."""
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as err:
            raise ScenarioError(f"{source}: not valid TOML: {err}") from None
        return cls.from_dict(data, source)

    @classmethod
    def from_dict(cls, data: dict, source: str = "scenario") -> "Scenario":
        """Build and check a scenario from nested dicts (the TOML tables)."""
        where = f"{source}: " if source else ""
        _known(data, ("name", "press", "mechanism", "drive", "problem", "model", "solver"), "", where)
        name = data.get("name", Path(source).stem if source else "scenario")
        if not isinstance(name, str):
            raise ScenarioError(f"{where}name must be a string, got {type(name).__name__}")
        try:
            mechanism = _mechanism(data.get("mechanism", {"name": "slider_crank"}), where)
            press = _press(_drive_lengths(data.get("press", {}), mechanism), where)
            drive = _typed(Drive, data["drive"], "drive", where, lists={"curve_speeds": 1, "curve_torques": 1}) \
                if "drive" in data else None
            problem = _problem(data.get("problem", {}), press, mechanism, drive, where)
            model = _typed(ModelSpec, data.get("model", {}), "model", where, {"clearance": (list, tuple)},
                           exclude=("mechanism",))
            model = dataclasses.replace(model, mechanism=mechanism)
            solver = _typed(SolverChoice, data.get("solver", {}), "solver", where, lists={"flexible_backoffs": 1})
            if solver.transcription not in TRANSCRIPTIONS:
                raise ScenarioError(f"{where}solver.transcription must be one of {', '.join(TRANSCRIPTIONS)}; got "
                                    f"{solver.transcription!r}{_suggest(solver.transcription, TRANSCRIPTIONS)}")
        except ScenarioError:
            raise
        except ValueError as err:  # a range check of the dataclasses: name the table
            raise ScenarioError(f"{where}{err}") from None
        return cls(name, problem, model, solver)

    # Writing -----------------------------------------------------------------------------------
    def to_dict(self) -> dict:
        """Nested plain data, the inverse of `from_dict` (None values left out)."""
        problem = {k: v for k, v in self.problem.to_dict().items()
                   if k not in ("press", "mechanism", "drive") and v is not None}
        period = problem.pop("period")
        model = {k: v for k, v in self.model.to_dict().items() if k != "mechanism"}
        mechanism = self.problem.mechanism
        return {"name": self.name, "press": _drop_none(self.press.to_dict()),
                **({} if mechanism == SLIDER_CRANK else {"mechanism": _drop_none(mechanism_to_dict(mechanism))}),
                **({} if self.problem.drive is None else {"drive": self.problem.drive.to_dict()}),
                "problem": {"period_s": period, **problem}, "model": model,
                "solver": _drop_none({f.name: getattr(self.solver, f.name) for f in fields(SolverChoice)})}

    def to_toml(self) -> str:
        """The scenario as TOML text (`load` reads it back to an equal scenario)."""
        return _toml(self.to_dict())

    def with_overrides(self, overrides: dict[str, Any]) -> "Scenario":
        """A copy with dotted keys set, e.g. ``{"problem.stroke_rate_spm": 60, "wrist_pin.clearance":
        5e-5}`` (press fields may leave out ``press.``). Checked like a file. Unless ``name`` is set,
        the copy's name lists the keys set (it titles figures and reports)."""
        cycle = [k for k in overrides if k in ("problem.stroke_rate_spm", "problem.period_s")]
        if len(cycle) > 1:
            raise ScenarioError(f"{' and '.join(cycle)} both set: the cycle is one of them, as in a scenario file")
        data = self.to_dict()
        if overrides and "name" not in overrides:
            data["name"] = f"{self.name}; " + ", ".join(f"{k} = {v}" for k, v in overrides.items())
        for key, value in overrides.items():
            parts = key.split(".")
            table = parts[0] in OPTIONAL_TABLES or isinstance(data.get(parts[0]), dict)
            if not (table or (parts[0] in data and len(parts) == 1)):  # a press field without "press."
                owners = _owning_tables(parts[0]) if len(parts) == 1 else ()
                if owners:
                    meant = " or ".join(f"'{t}.{key}'" for t in owners)
                    raise ScenarioError(f"{self.name} with {key}: unknown key press.{key}: {key} is not a press "
                                        f"field (did you mean {meant}?)")
                parts = ["press", *parts]
            node = data
            for p in parts[:-1]:
                node = node.setdefault(p, {})
                if not isinstance(node, dict):
                    raise ScenarioError(f"{key}: {p} is not a table")
            if parts[0] == "problem" and parts[-1] in ("stroke_rate_spm", "period_s"):
                node.pop("period_s", None)
                node.pop("stroke_rate_spm", None)
            node[parts[-1]] = value
        return Scenario.from_dict(data, source=f"{self.name} with {', '.join(overrides)}")


def _owning_tables(key: str) -> tuple[str, ...]:
    """Where `key`, set without its table's name, belongs if not to the press: the tables nested in
    the press that have it (``("crank_pin", "wrist_pin")`` for a bearing's field), else the one of
    ``problem``, ``solver``, ``model`` or ``drive``; empty when it is a press field or no table's."""
    if key in {f.name for f in fields(PressParams)}:
        return ()
    nested = tuple(t for t, cls in NESTED.items() if key in {f.name for f in fields(cls)})
    if nested:
        return nested
    tables = {"problem": ("stroke_rate_spm", "period_s", *PROBLEM_KEYS), "solver": SOLVER_KEYS,
              "model": tuple(f.name for f in fields(ModelSpec)), "drive": tuple(f.name for f in fields(Drive))}
    return tuple(t for t, keys in tables.items() if key in keys)[:1]


def bundled() -> list[str]:
    """Names of the scenarios shipped with pressocp."""
    folder = resources.files("pressocp").joinpath("scenarios")
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


# Checking ----------------------------------------------------------------------------------------
def _suggest(key: str, valid) -> str:
    near = difflib.get_close_matches(key, list(valid), n=1)
    return f" (did you mean {near[0]!r}?)" if near else ""


def _known(table: Any, valid, prefix: str, where: str) -> None:
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}{prefix.rstrip('.') or 'the file'} must be a table")
    for key in table:
        if key not in valid:
            raise ScenarioError(f"{where}unknown key {prefix}{key}{_suggest(key, valid)}; valid keys: "
                                f"{', '.join(valid)}")


_TYPES = {float: ((int, float), "a number"), int: ((int,), "an integer"), str: ((str,), "a string"),
          bool: ((bool,), "true or false")}


def _check_type(value: Any, annotation: Any, key: str, where: str) -> None:
    """Raise unless `value` fits the field annotation (numbers, strings, booleans, their unions)."""
    options = typing.get_args(annotation) if typing.get_origin(annotation) in (typing.Union, type(int | None)) \
        else (annotation,)
    expected = []
    for opt in options:
        if opt is type(None):
            continue
        if opt in _TYPES:
            kinds, word = _TYPES[opt]
            if isinstance(value, kinds) and not (isinstance(value, bool) and opt is not bool):
                return
            expected.append(word)
        else:
            return  # nested dataclasses are checked by their own table
    raise ScenarioError(f"{where}{key} must be {' or '.join(expected)}, got {value!r} ({type(value).__name__})")


def _typed(cls, table: Any, prefix: str, where: str, lists: dict | None = None, exclude: tuple[str, ...] = ()):
    """An instance of the dataclass `cls` from a table, every key known (the fields but `exclude`) and typed."""
    valid = [f.name for f in fields(cls) if f.name not in exclude]
    _known(table, valid, f"{prefix}.", where)
    hints = typing.get_type_hints(cls)
    values = {}
    for key, value in table.items():
        if lists and key in lists:
            if not isinstance(value, (list, tuple)):  # a tuple: from `Scenario.to_dict`
                raise ScenarioError(f"{where}{prefix}.{key} must be a list, got {value!r}")
            value = tuple(value)
        else:
            _check_type(value, hints[key], f"{prefix}.{key}", where)
        values[key] = value
    try:
        return cls(**values)
    except ValueError as err:
        raise ScenarioError(f"{where}{prefix}: {err}") from None


def _press(table: Any, where: str) -> PressParams:
    nested = NESTED
    _known(table, [f.name for f in fields(PressParams)], "press.", where)
    hints = typing.get_type_hints(PressParams)
    for key, value in table.items():
        if key in nested:
            if not isinstance(value, dict):
                raise ScenarioError(f"{where}press.{key} must be a table ([press.{key}])")
            _known(value, [f.name for f in fields(nested[key])], f"press.{key}.", where)
            sub_hints = typing.get_type_hints(nested[key])
            for k, v in value.items():
                _check_type(v, sub_hints[k], f"press.{key}.{k}", where)
        else:
            _check_type(value, hints[key], f"press.{key}", where)
    try:
        return PressParams.from_dict(table)
    except ValueError as err:
        raise ScenarioError(f"{where}press: {err}") from None


def _mechanism(table: Any, where: str) -> Mechanism:
    """The [mechanism] table: its name (`MECHANISMS`), its fields and its [mechanism.drive]."""
    if not isinstance(table, dict):
        raise ScenarioError(f"{where}mechanism must be a table ([mechanism])")
    name = table.get("name", "slider_crank")
    if name not in MECHANISMS:
        raise ScenarioError(f"{where}mechanism.name must be one of {', '.join(MECHANISMS)}; got {name!r}"
                            f"{_suggest(str(name), MECHANISMS)}")
    cls = MECHANISMS[name]
    _known(table, ("name", *(f.name for f in fields(cls))), "mechanism.", where)
    mechanism = _typed(cls, {k: v for k, v in table.items() if k not in ("name", "drive")}, "mechanism", where)
    if "drive" in table:
        if not isinstance(table["drive"], dict):
            raise ScenarioError(f"{where}mechanism.drive must be a table ([mechanism.drive])")
        mechanism = dataclasses.replace(mechanism, drive=_typed(cls.geometry, table["drive"], "mechanism.drive", where))
    return mechanism


def _drive_lengths(table: Any, mechanism: Mechanism) -> Any:
    """The [press] table with the crank radius and rod length of the mechanism's drive where it
    gives them and the table does not (a six-bar's or a toggle's press crank and rod are its drive's)."""
    drive = getattr(mechanism, "drive", None)
    if drive is None or not isinstance(table, dict):
        return table
    return {"crank_radius": drive.crank_radius, "rod_length": drive.rod_length, **table}


def _problem(table: Any, press: PressParams, mechanism: Mechanism, drive: Drive | None, where: str) -> SpeedProblem:
    valid = ("stroke_rate_spm", "period_s", *PROBLEM_KEYS)
    _known(table, valid, "problem.", where)
    table = dict(table)
    if "stroke_rate_spm" in table and "period_s" in table:
        raise ScenarioError(f"{where}problem: give stroke_rate_spm or period_s, not both")
    if "stroke_rate_spm" not in table and "period_s" not in table:
        raise ScenarioError(f"{where}problem.stroke_rate_spm (strokes per minute) or problem.period_s (s per "
                            "stroke) is missing: a scenario has no default cycle")
    hints = typing.get_type_hints(SpeedProblem)
    for key, value in table.items():
        if key in ("stroke_rate_spm", "period_s"):
            _check_type(value, float, f"problem.{key}", where)
        elif key in ("window", "counterbalance_range"):
            if not (isinstance(value, list) and len(value) == 2 and all(isinstance(v, (int, float))
                                                                        and not isinstance(v, bool) for v in value)):
                what = "[h1/H, h2/H]" if key == "window" else "[low, high] in N"
                raise ScenarioError(f"{where}problem.{key} must be a list of two numbers {what}, got {value!r}")
        else:
            _check_type(value, hints[key], f"problem.{key}", where)
    if "stroke_rate_spm" in table:
        spm = table.pop("stroke_rate_spm")
        if not 0 < spm < 2000:
            raise ScenarioError(f"{where}problem.stroke_rate_spm must be in (0, 2000) strokes/min, got {spm!r}")
        table["period"] = 60.0 / spm
    elif "period_s" in table:
        T = table.pop("period_s")
        if not (isinstance(T, (int, float)) and 0.0 < T < math.inf):
            raise ScenarioError(f"{where}problem.period_s must be in (0, inf) s, got {T!r}")
        table["period"] = T
    for key in ("window", "counterbalance_range"):
        if key in table:
            table[key] = tuple(table[key])
    try:
        return SpeedProblem(press, **table, mechanism=mechanism, drive=drive)
    except ValueError as err:
        raise ScenarioError(f"{where}problem: {err}") from None


# Writing TOML --------------------------------------------------------------------------------------
def _drop_none(d: dict) -> dict:
    return {k: (_drop_none(v) if isinstance(v, dict) else v) for k, v in d.items() if v is not None}


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _toml(data: dict, prefix: str = "") -> str:
    scalars = [f"{k} = {_value(v)}" for k, v in data.items() if not isinstance(v, dict)]
    tables = [(k, v) for k, v in data.items() if isinstance(v, dict)]
    out = "\n".join(scalars)
    for k, v in tables:
        name = f"{prefix}{k}"
        out += f"\n\n[{name}]\n" + _toml(v, name + ".").lstrip("\n")
    return out.strip("\n") + "\n" if not prefix else out


__all__ = ["Scenario", "ScenarioError", "SolverChoice", "bundled"]
