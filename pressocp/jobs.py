"""The command line's jobs on a scenario: optimise the speed, simulate a speed, the rigid design, the
impact study. Each writes its files into a folder (atomically) and returns a `JobReport`."""

from __future__ import annotations

import json
import math
import sys
import textwrap
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import impacts
from .design import design_speed
from .journals import contact_losses, describe_contacts
from .io import SUMMARY_NAME, RunMismatch, atomic_write, check_run_file, versions, write_json
from .objectives import get as get_objective
from .params import PressParams
from .verify import (SETTLE_SCREEN_CYCLES, SETTLE_SCREEN_RTOL, is_periodic, motor_cycle_of, rigid_reference,
                     window_times)
from .plots import plot_impact_study, plot_journal_orbits, plot_responses, plot_torque_speed, rigid_torque_level, save
from .problem import SpeedProblem
from .report import describe_problem, format_table, load_table, peak_summary, stamp, write_cycle_table
from .result import SimResult
from .series import PEAK_SERIES
from .scenario import Scenario
from .speed import FourierSpeed
from .stroke_rate import RateSearch, RateTrial, max_stroke_rate
from .units import format_force
from .summaries import (drive_summary, drive_text, optimum_summary, problem_summary, simulate_speed,
                        simulation_summary, time_table_text)

#: Figures of a response pair: file name -> series stacked in it.
FIGURES = {
    "speed.png": ("omega", "ram_height", "ram_velocity"),
    "loads.png": PEAK_SERIES,
}
#: The journal orbits of a response pair on a model with clearance (`plot_journal_orbits`).
JOURNALS = "journals.png"
#: Characters of a stage's status in the report's stage table; a longer one goes to a note below it.
STATUS_WIDTH = 40
#: Every file a job may write into its folder (checked to be placeable before a job runs).
OUTPUT_NAMES = ("results.csv", "speed.json", "result.json", *FIGURES, JOURNALS, "motor.png", "design.png",
                "impacts.png", "report.txt", SUMMARY_NAME)


@dataclass
class JobReport:
    """What a job did.

    Attributes
    ----------
    job : str
        "optimize", "simulate", "design" or "impacts".
    summary : dict
        The content of ``summary.json``.
    text : str
        The short report printed on the terminal (the head of ``report.txt``).
    files : list of Path
        Files written.
    ok : bool
        Converged and verified (exit code 0); False: results written but flagged (exit code 1).
    """

    job: str
    summary: dict
    text: str
    files: list[Path] = field(default_factory=list)
    ok: bool = True

    @property
    def exit_code(self) -> int:
        return 0 if self.ok else 1


def read_speed(path: str | Path) -> FourierSpeed:
    """A crank speed from ``speed.json`` (`FourierSpeed.to_dict`) or from a result file
    (`OcpResult.to_json`, its ``speed``). Raises ValueError naming the file."""
    path = Path(path)
    try:
        check_run_file(path)
        data = json.loads(path.read_text(encoding="utf-8"))
    except RunMismatch as err:
        raise ValueError(f"--speed: {err}") from None
    except FileNotFoundError:
        raise ValueError(f"--speed: no such file {path}") from None
    except IsADirectoryError:
        raise ValueError(f"--speed: {path} is a folder, not a speed file") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise ValueError(f"--speed: {path} is not JSON ({err})") from None
    if isinstance(data, dict) and isinstance(data.get("speed"), dict):
        data = data["speed"]
    if not isinstance(data, dict):
        raise ValueError(f"--speed: {path} holds no speed (expected keys period, a, b)")
    try:
        return FourierSpeed.from_dict(data)
    except (ValueError, TypeError) as err:
        raise ValueError(f"--speed: {path}: {err}") from None


def press_differences(path: str | Path, press: PressParams) -> list[str]:
    """How the press a result file was designed for (`OcpResult.to_json`, its ``problem.press``)
    differs from `press`, one entry per parameter ("slider_mass: 150 in the file, 200 here"); empty
    for a plain speed file or the same press."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    theirs = data.get("problem", {}).get("press") if isinstance(data, dict) else None
    if not isinstance(theirs, dict):
        return []
    a, b = _flat(theirs), _flat(press.to_dict())
    same = lambda x, y: (math.isclose(x, y, rel_tol=1e-12, abs_tol=0.0)  # noqa: E731
                         if isinstance(x, (int, float)) and isinstance(y, (int, float)) else x == y)
    return [f"{k}: {a.get(k)!r} in the file, {b.get(k)!r} here" for k in sorted(a.keys() | b.keys())
            if not same(a.get(k), b.get(k))]


def _flat(d: dict, prefix: str = "") -> dict:
    """A nested dict's leaves by dotted key."""
    out = {}
    for k, v in d.items():
        out.update(_flat(v, f"{prefix}{k}.") if isinstance(v, dict) else {f"{prefix}{k}": v})
    return out


def _state_names(scenario: Scenario) -> list[str]:
    """The names of the states of the scenario's model (`PressModel.state_names`)."""
    return scenario.build_model().state_names


def _figures(out: Path, responses: list[tuple[str, SimResult]], scenario: Scenario,
             window: tuple[float, float], title: str, state_names: list[str], floor: float | None = None) -> list[Path]:
    """The `FIGURES`, with the ram speed tolerance, the pin-force cap (when the problem has one) and
    the rigid-press optimum's peak torque (`floor`, N·m, for an optimum) drawn; and `JOURNALS`, the
    journal orbits, when the scenario's model has clearances (its states named by `state_names`)."""
    problem = scenario.problem
    levels: dict[str, list[tuple[float, str]]] = {}
    if floor is not None:
        levels["torque"] = [rigid_torque_level(problem.objective, floor)]
    if problem.max_pin_force is not None:
        for pin in ("crank_pin_force", "wrist_pin_force"):
            levels[pin] = [(problem.max_pin_force, f"cap {format_force(problem.max_pin_force)}")]
    files = []
    for name, series in FIGURES.items():
        fig = plot_responses(responses, window=window, series=series, title=title,
                             ram_speed=(problem.ram_speed, problem.tol), levels=levels)
        files.append(save(fig, out / name))
    if scenario.model.clearance:
        clearances = {j: getattr(scenario.press, j).clearance for j in scenario.model.clearance}
        fig = plot_journal_orbits(responses, state_names, clearances, window=window, title=title)
        files.append(save(fig, out / JOURNALS))
    return files


def _motors(problem: SpeedProblem, responses: dict) -> dict:
    """The drive's cycle of each (speed, response) by label; empty without a drive."""
    if problem.drive is None:
        return {}
    return {label: motor_cycle_of(problem, speed, sim) for label, (speed, sim) in responses.items()}


def _motor_figure(out: Path, problem: SpeedProblem, motors: dict, summary: dict, title: str) -> list[Path]:
    """motor.png and the summary's ``drive`` key, when the problem has a drive."""
    if not motors:
        return []
    summary.update(drive_summary(problem, motors))
    return [save(plot_torque_speed(problem.drive, motors, title), out / "motor.png")]


def _contacts_line(sim: SimResult, press: PressParams, scenario: Scenario) -> list[str]:
    """The report's line on the journals' separations from their walls (`describe_contacts`); none
    without clearance joints."""
    joints = scenario.model.clearance
    return [f"  {describe_contacts(contact_losses(sim, press, joints))}"] if joints else []


def _finish(job: str, out: Path, summary: dict, text: str, details: str, files: list[Path], ok: bool) -> JobReport:
    """Write report.txt and summary.json (last, so a complete summary means a complete run)."""
    files.append(atomic_write(out / "report.txt", text + "\n\n" + details + "\n"))
    summary["files"] = sorted(p.name for p in [*files, out / SUMMARY_NAME])
    files.append(write_json(out / SUMMARY_NAME, summary))
    return JobReport(job, summary, text, files, ok)


def optimize_job(scenario: Scenario, out: Path, progress: bool = True) -> JobReport:
    """The scenario's optimum: the rigid design, its response on the scenario's model, the optimum and
    its verification. Writes summary.json, results.csv, speed.json, result.json, report.txt and
    figures."""
    result = scenario.optimize(progress)
    problem = result.problem  # with a counterbalance chosen with the speed, the chosen one
    sim, init = result.simulation, result.initial_simulation
    ideal = rigid_reference(problem, result.initial_speed)
    where = scenario.model.describe()
    unit = get_objective(problem.objective).unit
    summary = {**optimum_summary(scenario, result, ideal), "versions": versions(), "run": stamp()}
    error = summary["max_ram_speed_error"]
    motors = _motors(problem, {"initial": (result.initial_speed, init), "optimum": (result.speed, sim)})
    names = _state_names(scenario)
    files = [write_cycle_table(out / "results.csv", {"initial": init, "optimum": sim}, motors, names),
             write_json(out / "speed.json", result.speed.to_dict()), result.to_json(out / "result.json")]
    label = "optimum" if result.success else "best iterate (not converged)"
    files += _figures(out, [("initial: rigid design", init), (label, sim)], scenario, (result.t1, result.t2),
                      f"{scenario.name}: {where}", names, result.rigid_peak_torque)
    files += _motor_figure(out, problem, motors, summary, f"{scenario.name}: {where}")
    verdict = ("converged and verified" if result.success and result.verified else
               f"NOT {'verified' if result.success else 'converged'}: {result.status}"
               + ("" if result.periodic is True else f"; {result.periodic}"))
    text = "\n".join([
        f"{scenario.name}: minimum {problem.objective} on the {where}",
        f"  {describe_problem(problem)}",
        "",
        format_table(load_table([("design, ideal joints", ideal), ("design, model", init), ("optimum, model", sim)],
                                problem.drive is not None)),
        "",
        f"  {verdict}; ram speed within {100 * error:.2f} % over the window "
        f"(allowed {100 * problem.tol / abs(problem.ram_speed):.2g} %)",
        f"  peak torque {summary['peak_torque_N_m']:.1f} N·m, "
        f"{100 * (summary['peak_torque_N_m'] / summary['initial_peak_torque_N_m'] - 1):+.1f} % against the design; "
        f"floor (rigid press optimum) {result.rigid_peak_torque:.1f} N·m; {result.wall_time:.0f} s",
        *_contacts_line(sim, problem.press, scenario),
        *([f"  counterbalance {format_force(problem.press.counterbalance.force)} at bottom dead centre, chosen with "
           f"the speed in [{', '.join(format_force(f) for f in scenario.problem.counterbalance_range)}]"]
          if scenario.problem.counterbalance_range else []),
        *(["", drive_text(problem, motors)] if motors else []),
    ])
    statuses, notes = footnoted([s.status + (f" ({s.superseded})" if s.superseded else "") for s in result.stages])
    stages = format_table([["stage", "model", "status", "iterations", "time, s", f"objective, {unit}"],
                           *([s.name, s.model, status, str(s.iterations), f"{s.wall_time:.1f}", f"{s.objective:.4g}"]
                             for s, status in zip(result.stages, statuses))])
    details = "\n".join([f"transcription: {result.transcription}", f"strategy: {result.strategy}",
                         f"verification: periodic CVODES re-simulation, rtol {result.verify_rtol:g}", "", stages,
                         *notes,
                         "", "where the time went, s (stages named stage@margin are candidate chains that ran side by "
                         f"side; the call took {result.wall_time:.0f} s):", time_table_text(result)])
    return _finish("optimize", out, summary, text, details, files, result.success and result.verified)


def footnoted(texts: list[str], width: int = STATUS_WIDTH) -> tuple[list[str], list[str]]:
    """Each of `texts` for a table column: as it is when it has at most `width` characters, else its
    first part (up to its first colon or parenthesis) and a note number; and the notes' lines, one per
    distinct long text, in order ("[1] the whole text")."""
    numbers: dict[str, int] = {}
    column = []
    for text in texts:
        if len(text) <= width:
            column.append(text)
            continue
        n = numbers.setdefault(text, len(numbers) + 1)
        head = text.split(":")[0].split(" (")[0].strip()
        column.append(f"{head[:width]} [{n}]")
    return column, [f"[{n}] {text}" for text, n in numbers.items()]


def simulate_job(scenario: Scenario, out: Path, speed: FourierSpeed | None = None,
                 source: str = "rigid design", progress: bool = False) -> JobReport:
    """A speed (default: the scenario's rigid design) on the scenario's model: periodic response
    (CVODES at the solver's ``verify_rtol``), with the ideal-joint response for comparison. With
    `progress`, a line on stderr says what runs (on the flexible rod it can take a minute)."""
    problem = scenario.problem
    scenario.check_speed(speed, "--speed")
    if speed is None:
        speed = design_speed(problem).speed
    if progress:
        print(f"pressocp simulate: {source} on the {scenario.model.describe()}: the periodic response at rtol "
              f"{scenario.solver.verify_rtol:g}, after a screen of {SETTLE_SCREEN_CYCLES} cycles from rest at rtol "
              f"{SETTLE_SCREEN_RTOL:g} where the model has states ...", file=sys.stderr, flush=True)
    t0 = time.perf_counter()
    sim, ideal = simulate_speed(scenario, speed)
    summary = {**simulation_summary(scenario, sim, ideal, source), "wall_time_s": time.perf_counter() - t0,
               "versions": versions(), "run": stamp()}
    periodic, error, where = summary["periodic"], summary["max_ram_speed_error"], summary["model"]
    motors = _motors(problem, {"speed": (speed, sim)})
    names = _state_names(scenario)
    files = [write_cycle_table(out / "results.csv", {"speed": sim}, motors, names),
             write_json(out / "speed.json", speed.to_dict())]
    files += _figures(out, [("ideal joints", ideal), (where, sim)], scenario, _window(sim, problem),
                      f"{scenario.name}: {source}", names)
    files += _motor_figure(out, problem, motors, summary, f"{scenario.name}: {source} on the {where}")
    text = "\n".join([f"{scenario.name}: {source} on the {where}", f"  {describe_problem(problem)}", "",
                      format_table(load_table([("ideal joints", ideal), ("model", sim)], problem.drive is not None)),
                      "",
                      f"  periodic: {periodic}; ram speed within {100 * error:.2f} % over the window",
                      *_contacts_line(sim, problem.press, scenario),
                      *(["", drive_text(problem, motors)] if motors else [])])
    return _finish("simulate", out, summary, text, f"speed: {speed!r}", files, periodic is True)


def _window(sim: SimResult, problem: SpeedProblem) -> tuple[float, float]:
    """When the response's own ram is in the window, s from its first sample."""
    t1, t2 = window_times(sim, problem)
    return (t1 - sim.t[0], t2 - sim.t[0])


def design_job(scenario: Scenario, out: Path) -> JobReport:
    """The rigid (kinematic) speed design of the scenario's problem on the ideal press."""
    problem = scenario.problem
    t0 = time.perf_counter()
    d = design_speed(problem)
    wall = time.perf_counter() - t0
    const = rigid_reference(problem, FourierSpeed.constant(problem.period))
    designed = rigid_reference(problem, d.speed)
    summary = {"job": "design", "scenario": scenario.name, **problem_summary(problem), "converged": d.converged,
               "status": d.status, "t1_s": d.t1, "t2_s": d.t2, "max_ram_speed_error": d.max_error,
               "rms_ram_speed_error": d.rms_error, "min_omega_rad_s": d.min_omega, "wall_time_s": wall,
               **peak_summary(designed), **peak_summary(const, "constant_speed_"),
               "min_wrist_pin_force_N": float(designed.wrist_pin_force.min()), "versions": versions(), "run": stamp()}
    files = [write_json(out / "speed.json", d.speed.to_dict()),
             write_cycle_table(out / "results.csv", {"constant": const, "design": designed}),
             save(plot_responses([("constant speed", const), ("designed speed", designed)], window=(d.t1, d.t2),
                                 ram_speed=(problem.ram_speed, problem.tol),
                                 title=f"{scenario.name}: rigid speed design"), out / "design.png")]
    text = "\n".join([
        f"{scenario.name}: rigid speed design", f"  {describe_problem(problem)}", "",
        format_table(load_table([("constant speed", const), ("designed speed", designed)], problem.drive is not None)),
        "",
        f"  IPOPT: {d.status} ({wall:.2f} s); window t1 = {d.t1:.4f} s, t2 = {d.t2:.4f} s",
        f"  ram speed error: max {100 * d.max_error:.3f} %, RMS {100 * d.rms_error:.3f} %; "
        f"min crank speed {d.min_omega:.3f} rad/s (mean {2 * np.pi / problem.period:.3f})",
        f"  min wrist-pin force with the design on the ideal press: {format_force(summary['min_wrist_pin_force_N'])} "
        + ("(the rod stays in tension)" if summary["min_wrist_pin_force_N"] > 0.05 * problem.hanging_weight else
           "(near zero or below, the journals leave their walls and impact: see pressocp impacts)"),
    ])
    return _finish("design", out, summary, text, f"speed: {d.speed!r}", files, d.converged)


def impacts_job(scenario: Scenario, out: Path) -> JobReport:
    """Constant and rigid-designed speed on the scenario's model against the ideal press (the source
    paper's Figs. 6 and 9 for the 75 spm scenario)."""
    t0 = time.perf_counter()
    st = impacts.impact_study(scenario.problem, scenario.model, rtol=scenario.solver.verify_rtol)
    wall = time.perf_counter() - t0
    ratios = st.ratios()
    where = scenario.model.describe()
    summary = {"job": "impacts", "scenario": scenario.name, "model": where, **problem_summary(scenario.problem),
               "ratios_model_over_ideal": ratios,
               "constant": peak_summary(st.constant), "designed": peak_summary(st.designed),
               "min_wrist_pin_force_ideal_N": {"constant": float(st.constant_rigid.wrist_pin_force.min()),
                                               "designed": float(st.designed_rigid.wrist_pin_force.min())},
               "periodic": {"constant": is_periodic(st.constant), "designed": is_periodic(st.designed)},
               "wall_time_s": wall, "versions": versions(), "run": stamp()}
    files = [write_cycle_table(out / "results.csv", {"constant": st.constant, "designed": st.designed},
                               state_names=_state_names(scenario)),
             write_json(out / "speed.json", st.design.speed.to_dict()),
             save(plot_impact_study(st), out / "impacts.png")]
    rows = [["model / ideal joints", "torque", "normal force", "crank pin", "wrist pin"],
            *([f"{k} speed", *(f"×{r[n]:.2f}" for n in PEAK_SERIES)] for k, r in ratios.items())]
    missing = st.not_periodic()
    text = "\n".join([f"{scenario.name}: impacts on the {where}", f"  {describe_problem(scenario.problem)}", "",
                      format_table(rows), "",
                      *(f"  not periodic: the {k} speed's response is the 6th cycle from rest ({why})"
                        for k, why in missing.items()), f"  {wall:.1f} s"])
    return _finish("impacts", out, summary, text, "", files, not missing)


__all__ = ["FIGURES", "JOURNALS", "JobReport", "design_job", "impacts_job", "optimize_job", "read_speed", "simulate_job"]


def describe_failed(failed: dict) -> str:
    """A rate trial's missed limits by name; an optimum not verified with the reason (it is not a
    limit of the drive)."""
    return ", ".join(f"not verified: {why}" if name == "verified" else name for name, why in failed.items())


def rate_verdict(trial: RateTrial, note: int | None = None) -> str:
    """A rate trial's verdict in a word or a list, saying when the drive's limits were constraints of
    the deciding optimum (its unconstrained optimum missed them). With `note`, an optimum not
    verified reads ``not verified [note]`` and its reason is given elsewhere (a status can run to
    hundreds of characters)."""
    if trial.feasible:
        verdict = "held"
    else:
        verdict = "failed: " + ", ".join(("not verified" + (f" [{note}]" if note else f": {why}")) if name == "verified"
                                         else name for name, why in trial.failed.items())
    return verdict + (f" (limits in the NLP; unconstrained: {describe_failed(trial.unconstrained_failed)})"
                      if trial.held else "")


def rate_job(scenario: Scenario, out: Path, search: RateSearch, progress: bool = True) -> JobReport:
    """The highest stroke rate the scenario's drive allows (`pressocp.stroke_rate.max_stroke_rate`):
    every rate tried with its verdict, the found rate's optimum (speed.json, result.json) and the
    motor's cycle at that rate and 2 % above (motor.png). Flagged when no rate held every limit."""
    problem = scenario.problem
    found = max_stroke_rate(problem, scenario.build_model(), search, progress)
    rows = [["strokes/min", "verdict", "peak crank torque, N·m", "peak-curve margin", "RMS margin", "speed margin",
             "time, s"]]
    tried = sorted(found.trials, key=lambda t: t.rate_spm)
    unverified = [t for t in tried if "verified" in t.failed]  # their reasons under the table, numbered
    note = {id(t): k + 1 for k, t in enumerate(unverified)}
    notes = [f"  [{note[id(t)]}] {t.rate_spm:.2f} strokes/min: {t.failed['verified']}" for t in unverified]
    for t in tried:
        m = t.margins
        rows.append([f"{t.rate_spm:.2f}", rate_verdict(t, note.get(id(t))),
                     f"{t.peak_torque:.1f}", *(f"{100 * m[k]:+.1f} %" if k in m else "-" for k in
                                               ("peak_torque_margin", "rms_margin", "speed_margin")),
                     f"{t.wall_time:.0f}"])
    summary = {"job": "rate", "scenario": scenario.name, "model": scenario.model.describe(),
               **problem_summary(problem), "drive": problem.drive.to_dict(), **found.summary(),
               "converged": found.rate_spm is not None, "versions": versions(), "run": stamp()}
    files: list[Path] = []
    cycles = {f"{label}: {t.rate_spm:.1f} spm": t.motor for label, t in (("found", found.best), ("+2 %", found.above))
              if t is not None and t.motor is not None}
    if found.best is not None:
        files += [write_json(out / "speed.json", found.best.result.speed.to_dict()),
                  found.best.result.to_json(out / "result.json")]
    if cycles:
        title = textwrap.fill(f"{scenario.name}: the highest stroke rate", 110)
        files.append(save(plot_torque_speed(problem.drive, cycles, title), out / "motor.png"))
    d = problem.drive
    verdict = ("no rate tried held every limit" if found.rate_spm is None else
               f"{found.rate_spm:.1f} strokes/min (every limit held on the verified optimum)"
               + ("" if found.above is None else f"; at {found.above.rate_spm:.1f}: "
                  + ("held too" if found.above.feasible else rate_verdict(found.above, note.get(id(found.above))))))
    text = "\n".join([f"{scenario.name}: the highest stroke rate with its drive (peak {d.peak_torque:g} N·m, "
                      f"continuous {d.continuous_torque:g} N·m, {d.max_speed * 60 / (2 * math.pi):.0f} rpm, gear "
                      f"{d.gear_ratio:g})", f"  {describe_problem(problem)}", "", format_table(rows), *notes, "",
                      f"  {verdict}; {sum(t.optimisations for t in found.trials)} optimisations at "
                      f"{len(found.trials)} rates in {found.wall_time:.0f} s"])
    summary["status"] = verdict
    details = ("each rate: the scenario's optimum at that rate without the drive's limits in the NLP, checked on "
               "its periodic re-simulation; when it missed only the drive's limits or the pin-force cap, the "
               "optimum with them as constraints, checked the same way ('limits in the NLP'); margins are "
               "shares of the rating, negative when exceeded")
    return _finish("rate", out, summary, text, details, files, found.rate_spm is not None)
