"""The open issues' "must show" goals against the result files of the last runs.

`python -m benchmarks` rewrites the goals table of benchmarks/README.md (between the ``goals``
markers) after every job, from what is in results/ at that moment, with each row's source file and
the date of its measurement; ``python benchmarks/status.py`` prints it. A goal with no result file
(or none with the fields it needs) says "not measured"; nothing here is typed in by hand except the
goals themselves and the "before" times of measurements that cannot be repeated on a clean
machine (an older version's venv), which say where they come from.

The verdicts compare numbers as the issues state them: a peak "no higher than before" is compared
to the digit, and a miss is shown as a miss with its size. A time is shown with the VM it was
measured on, and a "before/after" ratio is only taken between runs on one VM: this workplace's
VMs differ by 2-4 x in speed.
"""

from __future__ import annotations

import ast
import contextlib
import io
import json
import re
import statistics
import sys
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from datetime import datetime, timedelta
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- goals:begin (written by python -m benchmarks) -->", "<!-- goals:end -->"

#: Issue #28 (fast optimiser).
GOAL_SEED_S, GOAL_SEED_PEAK = 45.0, 146.0
GOAL_SPEEDUP = 2.0
GOAL_FLEXIBLE_S = 600.0
GOAL_SWEEP_OPTIMA_S = 300.0
GOAL_SUITE_S = 3 * 3600.0
#: Issue #29 (fast simulation).
GOAL_RADAU_RATIO = 20.0
GOAL_VERIFY_RATIO, GOAL_VERIFY_PEAKS = 3.0, 1e-6
GOAL_SWEEP_RATIO = 1.8
GOAL_AD_RATIO, GOAL_AD_ERROR = 3.0, 0.02
GOAL_MODAL_CYCLE_S, GOAL_MODAL_PEAK, GOAL_MODAL_SIMEON, GOAL_MODAL_ELEMENTS = 1.0, 1e-3, 0.01, 0.02
#: Issue #31 (restructure): the limits of a public function's parameters and of any function's lines.
MAX_PARAMETERS, MAX_LINES = 10, 80
#: The final verification before issue #29: commit bd45b21's `verify_speed(model, seed optimum, 1e-9)`,
#: median of 3 calls in a fresh process, 2026-11-25 11:33 UTC (docs/measurements.md, "The final
#: verification"); its venv is not rebuilt by the suite, so its time is quoted, not re-measured.
VERIFY_BEFORE = {"median_s": 1.749, "torque": 145.144166, "source": "bd45b21, 2026-11-25T11:33"}


@dataclass(frozen=True)
class Row:
    """One goal: its issue (None: a rule of the project, not an issue), what it asks, what the files
    show, the verdict and where it comes from."""

    issue: int | None
    goal: str
    measured: str
    verdict: str
    source: str


@dataclass(frozen=True)
class Results:
    """A results folder: its JSON files by name, None (or no rows) where a file is missing."""

    folder: Path = RESULTS

    def json(self, name: str):
        path = self.folder / name
        return json.loads(path.read_text()) if path.exists() else None

    def jsonl(self, name: str) -> list[dict]:
        path = self.folder / name
        return [json.loads(line) for line in path.read_text().splitlines() if line.strip()] if path.exists() else []


def latest(rows: Iterable[dict], **match) -> dict | None:
    """The last row (file order) whose fields equal `match`."""
    found = [r for r in rows if all(r.get(k) == v for k, v in match.items())]
    return found[-1] if found else None


def vm(row: dict) -> str:
    """The virtual machine a row ran on, as its platform's kernel names it (``…-v669``): the VMs of
    this workplace differ 2-4 x in speed (docs/measurements.md), so a ratio is only taken on one."""
    return vm_of(row["run"])


def vm_of(run: dict) -> str:
    """The virtual machine of a run's stamp (`pressocp.report.stamp`: date, machine, cpus, platform,
    python; a dict with those keys among others will do): ``…-v669`` from its platform's kernel; without
    one that names it, the platform, else the hostname (``host vm``: the same on every VM, a stamp of
    before the platform was recorded), else "an unrecorded machine"."""
    platform, host = str(run.get("platform") or ""), run.get("machine")
    found = re.search(r"-(v\d+)-", platform)
    return f"…-{found.group(1)}" if found else platform or (f"host {host}" if host else "an unrecorded machine")


def job_run(file: str, date: str | None = None, folder: Path = RESULTS) -> dict:
    """The runner's record (runs.json) of the last job run that wrote `file` of `folder` (its date,
    machine, cpus, platform): for result files written before they carried their own stamp. With
    `date` (ISO), only a run that was under way at that date; {} when there is none."""
    def under_way(r: dict) -> bool:  # the stamps are to the second: the end is given one more
        end = datetime.fromisoformat(r["date"]) + timedelta(seconds=(r.get("wall_time_s") or 0.0) + 1.0)
        return r["date"] <= date[:19] <= end.isoformat(timespec="seconds")

    found = [r for r in (Results(folder).json("runs.json") or {}).values()
             if file in r.get("files", ()) and r.get("date") and (date is None or under_way(r))]
    return max(found, key=lambda r: r["date"], default={})


def figure_note(fig, *runs: dict) -> None:
    """Write when and where a figure's timings were measured at its bottom right, small and grey:
    "measured 2026-12-02 23:52 on …-v1098 (2 CPUs)". Each of `runs` is a stamp (`vm_of`); a figure
    drawn from several runs gets their date range and every machine. A missing field says so; never raises."""
    runs = tuple(r if isinstance(r, dict) else {} for r in runs) or ({},)
    dates = sorted({str(r["date"])[:16].replace("T", " ") for r in runs if r.get("date")})
    names = sorted(dict.fromkeys(vm_of(r) for r in runs), key=lambda n: n == "an unrecorded machine")
    cpus = sorted({str(r["cpus"]) for r in runs if r.get("cpus")}, key=lambda c: (len(c), c))
    where = f"on {', '.join(names)}" + (f" ({', '.join(cpus)} CPUs)" if cpus else "")
    if dates:
        text = f"measured {dates[0] if len(dates) == 1 else f'{dates[0]} to {dates[-1]}'} {where}"
    elif cpus or names != ["an unrecorded machine"]:
        text = f"measured {where}, date not recorded"
    else:
        text = "measured: date and machine not recorded"
    from matplotlib.transforms import offset_copy  # here: the runner imports this module without matplotlib

    corner = offset_copy(fig.transFigure, fig=fig, x=-3.0, y=2.0, units="points")  # 3 pt in, 2 pt up
    fig.text(1.0, 0.0, text, transform=corner, ha="right", va="bottom", fontsize=6.5, color="0.45")


def same_machine(rows: list[dict], scenario: str) -> tuple[dict | None, dict | None]:
    """The newest "after" row of `scenario` with a "before" row on the same machine, and the newest
    such "before" row; (None, None) when no machine has both."""
    afters = [r for r in rows if r.get("scenario") == scenario and r.get("label") == "after"]
    for after in reversed(afters):
        before = latest((r for r in rows if r.get("run", {}).get("platform") == after["run"].get("platform")),
                        scenario=scenario, label="before")
        if before is not None:
            return before, after
    return None, None


def verdict(ok: bool) -> str:
    return "met" if ok else "**not met**"


def missing(issue: int, goal: str, source: str) -> Row:
    return Row(issue, goal, "not measured", "not measured", source)


def speed_rows(res: Results) -> list[Row]:
    """#28: the default calls in fresh processes (bench_speed), against the version before the issue."""
    rows = res.jsonl("speed.jsonl")
    out = []
    seed, cold = latest(rows, scenario="press75", label="after"), latest(rows, scenario="press75", label="cold")
    limits = f"≤ {GOAL_SEED_S:g} s median, verified peak ≤ {GOAL_SEED_PEAK:g} N·m"
    # The issue's goal is the cold row; the "after" row empties the cache before its first run only,
    # so its median is a warm call's, shown beside the goal and not as it.
    for r, how, goal, aside in (
            (seed, "the first run with an empty compile cache", "press75 default call, fresh process, the compile "
             f"cache emptied before the first of the runs only (so a warm call's median): {limits}",
             " as a warm call, not the goal"),
            (cold, "an empty compile cache in every run",
             f"press75 default call, cold process, compile included: {limits}", "")):
        if r is None:
            out.append(missing(28, goal, "speed.jsonl"))
            continue
        walls = ", ".join(f"{w:.1f}" for w in r["wall_s"])
        peak = max(r["peaks"])
        ok = r["median_wall_s"] <= GOAL_SEED_S and r["all_verified"] and peak <= GOAL_SEED_PEAK
        out.append(Row(28, goal, f"{how}: {walls} s, median **{r['median_wall_s']:.1f} s**; peak {peak:.4f} N·m, "
                       f"{'all' if r['all_verified'] else 'not all'} verified; on {vm(r)}",
                       verdict(ok) + aside,
                       f"speed.jsonl ({r['label']}), {r['run']['date']}"))
    for name in ("press60", "large_press", "slender_rod"):
        before, after = same_machine(rows, name)
        goal = f"{name}: ≥ {GOAL_SPEEDUP:g} × faster than before the issue, peak no higher"
        if after is None or before is None:
            out.append(missing(28, goal, "speed.jsonl"))
            continue
        ratio = before["median_wall_s"] / after["median_wall_s"]
        p_after, p_before = max(after["peaks"]), max(before["peaks"])
        rel = p_after / p_before - 1.0
        faster, lower = ratio >= GOAL_SPEEDUP and after["all_verified"], p_after <= p_before
        text = (f"{before['median_wall_s']:.1f} → **{after['median_wall_s']:.1f} s** ({ratio:.1f} ×); peak "
                f"{p_before:.4f} → {p_after:.4f} N·m ({rel:+.1e}), {'all' if after['all_verified'] else 'not all'} verified; "
                f"both on {vm(after)}")
        v = "met" if faster and lower else ("**not met**: the peak is higher by " f"{rel:.1e}" if faster else "**not met**")
        out.append(Row(28, goal, text, v, f"speed.jsonl, before {before['run']['date']}, after {after['run']['date']}"))
    seconds = [r for r in (latest(rows, scenario=n, label="after") for n in ("press75", "press60", "large_press",
                                                                              "slender_rod")) if r is not None]
    goal = "the same model in a second process: compile time ≈ 0 s"
    if seconds:
        later = [c for r in seconds for c in r["compile_s"][1:]]
        first = ", ".join(f"{r['scenario']} {r['compile_s'][0]:.1f}" for r in seconds)
        out.append(Row(28, goal, f"runs after the first: at most {max(later, default=float('nan')):.2f} s of compiling "
                       f"(first runs: {first} s)", verdict(bool(later) and max(later) < 0.5),
                       f"speed.jsonl, {seconds[-1]['run']['date']}"))
    else:
        out.append(missing(28, goal, "speed.jsonl"))
    return out


def flexible_row(res: Results) -> Row:
    goal = f"ocp_flexible (75 spm, 4-element rod, both clearances): verified in ≤ {GOAL_FLEXIBLE_S / 60:g} min"
    r = latest(res.jsonl("ocp.jsonl"), case="flexible")
    if r is None:
        return missing(28, goal, "ocp.jsonl")
    walls = r.get("wall_times_s") or [r["wall_time_s"]]
    med = statistics.median(walls)
    ok = med <= GOAL_FLEXIBLE_S and bool(r.get("verified")) and bool(r.get("success"))
    date = (res.json("runs.json") or {}).get("ocp_flexible", {}).get("date", "date not recorded")
    return Row(28, goal, f"{', '.join(f'{w:.1f}' for w in walls)} s, median **{med:.1f} s**; "
               f"{r['verified_objective']:.4f} N·m {'verified' if r.get('verified') else 'not verified'}", verdict(ok),
               f"ocp.jsonl (flexible), {date}")


def sweep_optima_row(res: Results) -> Row:
    goal = f"a sweep of 8 optima on 2 workers: ≤ {GOAL_SWEEP_OPTIMA_S / 60:g} min, every row verified"
    r = res.json("sweep_optima.json")
    if r is None:
        return missing(28, goal, "sweep_optima.json")
    walls = [x["wall_time_s"] for x in r["runs"]]
    ok = r["median_s"] <= GOAL_SWEEP_OPTIMA_S and r["all_verified"]
    cold = (r.get("variants") or {}).get("cold")
    how = "continued along the clearance (`--along`): " if cold else ""
    versus = ""
    if cold:
        runs = len(cold["runs"])
        time = f"median {cold['median_s']:.0f} s of {runs} runs" if runs > 1 else f"{cold['median_s']:.0f} s, one run"
        versus = (f" (every point cold: {time}, "
                  f"{'every row verified' if cold['all_verified'] else 'not every row verified'})")
    return Row(28, goal, f"{how}{', '.join(f'{w:.0f}' for w in walls)} s, median **{r['median_s']:.0f} s**; "
               f"{'every row verified' if r['all_verified'] else 'not every row verified'}{versus}", verdict(ok),
               f"sweep_optima.json, {r['date']}")


def suite_row(res: Results) -> Row:
    goal = "`python -m benchmarks` end to end: ≤ 3 h"
    runs = res.json("runs.json") or {}
    s = runs.get("suite")
    if s is None:
        return missing(28, goal, "runs.json")
    ok = s["wall_time_s"] <= GOAL_SUITE_S and not s["failed"]
    failed = ", ".join(s["failed"]) or "none failed"
    jobs, budget = suite_now()
    measured = f"{s['jobs']} jobs in **{s['wall_time_s'] / 60:.0f} min**; {failed}"
    if jobs != s["jobs"]:  # a run of another suite does not show this one's time
        return Row(28, goal, f"{measured}; the suite has {jobs} jobs now (budgets {budget:g} min), not run whole "
                   f"since: {last_runs(runs)}", "not measured", f"runs.json (suite), {s['date']}")
    return Row(28, goal, measured, verdict(ok), f"runs.json (suite), {s['date']}")


def last_runs(runs: dict) -> str:
    """The suite's jobs' last runs by the runner added up (a job stopped over its budget counts the
    time it ran), and the jobs the runner has not run: an estimate of a whole run, not a measurement."""
    from benchmarks.__main__ import JOBS  # the runner imports this module: here, not at the top

    jobs = [j.name for j in JOBS if not j.archive]
    ran = [runs[name] for name in jobs if name in runs]
    never = [name for name in jobs if name not in runs]
    total = sum(r["wall_time_s"] for r in ran) / 60.0
    over = [name for name in jobs if runs.get(name, {}).get("over_budget")]
    return (f"the {len(ran)} jobs' last runs add up to {total:.0f} min"
            + (f" (stopped over budget: {', '.join(over)})" if over else "")
            + (f"; not run by the runner yet: {', '.join(never)}" if never else ""))


def suite_now() -> tuple[int, float]:
    """The suite's jobs as the runner lists them now (`benchmarks.__main__.JOBS`, archive left out):
    their number and their budgets' sum, min."""
    from benchmarks.__main__ import JOBS  # the runner imports this module: here, not at the top

    jobs = [j for j in JOBS if not j.archive]
    return len(jobs), float(sum(j.minutes for j in jobs))


def idas_1e6_against_radau(rows: list[dict]) -> str:
    """The issue's own reading, from the rows: IDAS at rtol 1e-6 against scipy Radau at the loosest
    rtol whose peak-torque error is no larger than IDAS's. On an impacting cycle that error does not
    fall steadily with rtol, so this ratio moves with it from run to run (the verdict stays on the
    fixed accuracy targets); "" without the rows."""
    idas = next((r for r in rows if r["method"] == "idas" and r["rtol"] == 1e-6 and r["ok"]), None)
    if idas is None:
        return ""
    radau = [r for r in rows if r["method"] == "scipy-radau" and r["ok"]
             and r["peak_torque_rel_error"] <= idas["peak_torque_rel_error"]]
    if not radau:
        return f"IDAS at 1e-6 ({idas['peak_torque_rel_error']:.1e} peak error): no Radau run as accurate"
    loosest = max(radau, key=lambda r: r["rtol"])
    return (f"IDAS at 1e-6 ({idas['peak_torque_rel_error']:.1e} peak error, {idas['time_per_cycle_s']:.2f} s) against "
            f"Radau at {loosest['rtol']:g} ({loosest['peak_torque_rel_error']:.1e}, {loosest['time_per_cycle_s']:.2f} s): "
            f"{loosest['time_per_cycle_s'] / idas['time_per_cycle_s']:.1f} ×")


def radau_row(res: Results) -> Row:
    goal = f"seed clearance model, one cycle: IDAS at rtol 1e-6 against scipy Radau at equal peak accuracy ≥ {GOAL_RADAU_RATIO:g} ×"
    r = res.json("simulation.json")
    runs = res.json("runs.json") or {}
    if r is None or "equal_accuracy" not in r:
        return missing(29, goal, "simulation.json")
    cells = {k: v for k, v in r["equal_accuracy"].items() if k.startswith("clearance@")}
    if not cells:
        return missing(29, goal, "simulation.json")
    parts = [f"at {float(k.split('@')[1]):.1%} peak error: {v['radau_over_idas']:.1f} × "
             f"(IDAS {v['idas']['time_per_cycle_s']:.2f} s at rtol {v['idas']['rtol']:g}, Radau "
             f"{v['scipy-radau']['time_per_cycle_s']:.2f} s at {v['scipy-radau']['rtol']:g})" for k, v in sorted(cells.items())]
    ok = min(v["radau_over_idas"] for v in cells.values()) >= GOAL_RADAU_RATIO
    if all("radau_over_idas_in_turn" in v for v in cells.values()):
        parts.append("the same pairs timed in turn (5 runs each): " + ", ".join(
            f"{v['radau_over_idas_in_turn']:.1f} × at {float(k.split('@')[1]):.1%}" for k, v in sorted(cells.items())))
    literal = idas_1e6_against_radau(r.get("results", {}).get("clearance", {}).get("rows", []))
    if literal:
        parts.append(literal)
    for key, what in (("radau_over_idas_interpreted", "IDAS interpreted"),
                      ("radau_over_idas_casadi_clock", "IDAS with CasADi's process clock (as without pressocp)")):
        if key in next(iter(cells.values())):
            parts.append(f"{what}: " + ", ".join(f"{v[key]:.1f} ×" for _, v in sorted(cells.items())))
    date = r.get("stamp", {}).get("date") or runs.get("simulation", {}).get("date", "date not recorded")
    source = f"simulation.json, {date}"
    orbit = res.json("simulation_periodic69.json")
    if orbit is not None:
        cells = {k: v for k, v in orbit["equal_accuracy"].items() if "radau_over_idas" in v}
        radau = [row for row in orbit["results"]["periodic69"]["rows"] if row["method"] == "scipy-radau" and row["ok"]]
        loosest = max(radau, key=lambda row: row["rtol"], default=None)
        parts.append("on the 69 spm design's periodic impacting orbit (the 75 spm cycle is not one): "
                     + ", ".join(f"{v['radau_over_idas']:.1f} × at {float(k.split('@')[1]):.1%}" for k, v in sorted(cells.items()))
                     + ("" if loosest is None else f" (Radau within {loosest['peak_torque_rel_error']:.0e} already at "
                        f"its loosest rtol {loosest['rtol']:g}, {loosest['time_per_cycle_s']:.1f} s)"))
        source += f"; simulation_periodic69.json, {orbit['stamp']['date']}"
    smooth = res.json("simulation_seed.json")
    if smooth is not None:
        literal = idas_1e6_against_radau(smooth["results"]["seed"]["rows"])
        cells = {k: v for k, v in smooth["equal_accuracy"].items() if "radau_over_idas" in v}
        pieces = ([literal] if literal else []) + [f"{v['radau_over_idas']:.1f} × at {float(k.split('@')[1]):.1%}"
                                                   for k, v in sorted(cells.items())]
        parts.append("on the seed optimum's smooth periodic cycle (journals on their walls): " + ", ".join(pieces))
        source += f"; simulation_seed.json, {smooth['stamp']['date']}"
    return Row(29, goal, "; ".join(parts), verdict(ok), source)


def verification_row(res: Results) -> Row:
    goal = f"the seed optimum's final verification at rtol 1e-9: ≥ {GOAL_VERIFY_RATIO:g} × faster, the same peaks to 1e-6"
    r = res.json("verification.json")
    if r is None or "after" not in r.get("runs", {}):
        return missing(29, goal, "verification.json")
    after = r["runs"]["after"]
    before = r["runs"].get("before")
    if before is not None:
        b_s, b_peak, b_src = before["median_s"], before["peaks"]["torque"], "in the same run"
    else:
        b_s, b_peak, b_src = VERIFY_BEFORE["median_s"], VERIFY_BEFORE["torque"], f"quoted: {VERIFY_BEFORE['source']}"
    ratio = b_s / after["median_s"]
    rel = abs(after["peaks"]["torque"] / b_peak - 1.0)
    ok = ratio >= GOAL_VERIFY_RATIO and rel <= GOAL_VERIFY_PEAKS
    return Row(29, goal, f"{b_s:.3f} s ({b_src}) → **{after['median_s']:.3f} s**, {ratio:.2f} ×; torque peak "
               f"differs by {rel:.1e}", verdict(ok), f"verification.json, {r['date']}")


def sweep_parallel_row(res: Results) -> Row:
    goal = f"a sweep of 8 simulations: 2 workers ≥ {GOAL_SWEEP_RATIO:g} × faster than 1, identical tables"
    r = res.json("sweep_parallel.json")
    if r is None:
        return missing(29, goal, "sweep_parallel.json")
    same = all(r["identical_tables"].values())
    ok = r["speedup_2_workers"] >= GOAL_SWEEP_RATIO and same
    med = r["median_s"]
    plain = (f"; a plain ProcessPoolExecutor of the caller's: {r['speedup_plain_pool']:.2f} ×"
             if "speedup_plain_pool" in r else "")
    return Row(29, goal, f"the package's pool: 1 worker {med['1 worker']:.1f} s, 2 workers {med['2 workers']:.1f} s: "
               f"**{r['speedup_2_workers']:.2f} ×** (dask {r['speedup_dask']:.2f} ×{plain}); tables "
               f"{'identical' if same else 'differ'}", verdict(ok), f"sweep_parallel.json, {r['date']}")


def optimum_sensitivity_row(res: Results) -> Row:
    goal = "`optimum_sensitivities` on the seed optimum: cheaper than one re-solve"
    r = res.json("optimum_sensitivity.json")
    case = latest((r or {}).get("cases", []), scenario="press75")
    if case is None:
        return missing(29, goal, "optimum_sensitivity.json")
    cost = case["sensitivity_resolve_s"] + case["sensitivity_kkt_s"]
    one = case["two_resolves_s"] / 2.0
    agree = case["derivative_check"] != 0 and (case["derivative"] * case["derivative_check"] > 0)
    return Row(29, goal, f"{cost:.1f} s against one re-solve {one:.1f} s (**{cost / one:.2f} ×**); derivative "
               f"{case['derivative']:.4g}, check {case['derivative_check']:.4g}"
               f"{'' if agree else ' (opposite signs)'}", verdict(cost < one),
               f"optimum_sensitivity.json (press75, {case['parameter']}), {case.get('date', r.get('date'))}")


def _simeon_error(r: dict, cycle: dict) -> float | None:
    """The largest of Simeon's errors on the rod of `cycle` (its ideal-joint run in ``r["simeon"]``), or
    None when it was not run."""
    name = cycle["model"].replace(", clearance in crank_pin and wrist_pin", ", ideal joints")
    sim = next((s for s in r["simeon"] if s["model"] == name), None)
    return None if sim is None else max(sim["errors"].values())


def _reduced_agreement_row(r: dict, reduced: list[dict], goal: str, src: str) -> Row:
    """The fastest reduced rod within Simeon's and the 8-element rod's tolerances (else the one nearest
    to them), when no reduced rod meets the peak goal of the cycle."""
    def errors(c):
        sim_err = _simeon_error(r, c)
        return (float("inf") if sim_err is None else sim_err), max(c["errors"].values())

    fits = [c for c in reduced if errors(c)[0] <= GOAL_MODAL_SIMEON and errors(c)[1] <= GOAL_MODAL_ELEMENTS]
    c = min(fits, key=lambda c: c["median_s"]) if fits else min(
        reduced, key=lambda c: max(errors(c)[0] / GOAL_MODAL_SIMEON, errors(c)[1] / GOAL_MODAL_ELEMENTS))
    sim_err, el_err = errors(c)
    return Row(29, goal, f"{c['model']}: Simeon within {sim_err:.2%}; peaks within {el_err:.2%} of the full rod "
               "(one transient from rest: its impacts are sensitive to rounding, see "
               "docs/decisions/2026-11-26-reduced-rod.md)",
               "**not robust**: met by this run's transient" if fits else verdict(False), src)


def _short(model: str) -> str:
    return model.replace(", clearance in crank_pin and wrist_pin", "")


def _fastest_within(per: dict, reduced_only: bool = False) -> tuple[dict, dict] | None:
    """The flexible level (reduced only: one of a few modes) and timed cycle of the periodic scene `per`
    that is fastest with its peak torque within `GOAL_MODAL_PEAK` of the full rod at its rtol, at every
    tighter rtol timed and at the reference rtol: a loose rtol whose error happens to cancel the
    level's own model error does not count (one mode of the 8-element rod on the impacting scene:
    4.8e-4 at rtol 1e-5, 2.6e-3 at 1e-6, 2026-11-27)."""
    def within(lv, c):
        tighter = [d["errors"]["torque"] for d in lv["timed"] if d["rtol"] <= c["rtol"]]
        return max(tighter + [lv["reference_cycle"]["errors"]["torque"]]) <= GOAL_MODAL_PEAK

    runs = [(lv, c) for lv in per["levels"] if lv["spec"]["rod"] == "flexible"
            and (not reduced_only or lv["spec"].get("n_modes") is not None)
            for c in lv["timed"] if within(lv, c)]
    return min(runs, key=lambda lc: lc[1]["median_s"]) if runs else None


def _said(lc: tuple[dict, dict] | None, repeat: int) -> str:
    if lc is None:
        return "none within the peak tolerance"
    lv, c = lc
    return (f"{_short(lv['model'])} at rtol {c['rtol']:g}: **{c['median_s']:.2f} s** (median of {repeat}), peak "
            f"torque {c['errors']['torque']:.1e} from the full rod (at rtol {lv['reference_cycle']['rtol']:g}: "
            f"{lv['reference_cycle']['errors']['torque']:.1e})")


def _return_speed(per: dict) -> float:
    """The periodic scene's fastest return of a journal to its bearing wall, m/s (on the full rod)."""
    return max((i["return_speed_m_s"] for i in per["levels"][0]["reference_cycle"]["impacts"].values()), default=0.0)


def _impacts(per: dict) -> str:
    imp = per["levels"][0]["reference_cycle"]["impacts"]
    if not imp:
        return "no clearance joints"
    return (f"contact losses crank/wrist pin {imp['crank_pin']['losses']}/{imp['wrist_pin']['losses']} a cycle, back at "
            f"the wall at up to {1e3 * _return_speed(per):.1f} mm/s")


def _periodic_modal_rows(r: dict, goal: str, goal2: str, src: str) -> list[Row]:
    """The rod goals on the periodic scenes of `bench_modal_rod`, judged on the impacting one (the
    fastest return to a bearing wall): the fastest flexible level and rtol within the peak tolerance of
    the full element rod, the fastest reduced one, and the reduced rods' model error (their periodic
    cycles at the reference rtol) with Simeon's; the other scenes are quoted."""
    scenes = sorted(r["periodic"], key=_return_speed, reverse=True)
    per, others = scenes[0], scenes[1:]
    best, best_reduced = _fastest_within(per), _fastest_within(per, reduced_only=True)
    also = "" if best_reduced is None or best_reduced == best else f"; the fastest reduced rod: {_said(best_reduced, per['repeat'])}"
    quoted = "".join(f"; on the {o['scene']} ({_impacts(o)}): {_said(_fastest_within(o), o['repeat'])}" for o in others)
    row1 = Row(29, goal, f"on the {per['scene']} ({_impacts(per)}): {_said(best, per['repeat'])}{also}{quoted}; the "
               "75 spm design's impacts have no periodic orbit to judge on (its per-cycle peaks wander by 5 %)",
               verdict(best is not None and best[1]["median_s"] < GOAL_MODAL_CYCLE_S), src)
    reduced = [lv for lv in per["levels"] if lv["spec"]["rod"] == "flexible" and lv["spec"].get("n_modes") is not None]
    model_err = {lv["model"]: max(lv["reference_cycle"]["errors"].values()) for lv in reduced}
    sims = {lv["model"]: _simeon_error(r, lv) for lv in reduced}
    fits = [lv for lv in reduced if sims[lv["model"]] is not None and sims[lv["model"]] <= GOAL_MODAL_SIMEON
            and model_err[lv["model"]] <= GOAL_MODAL_ELEMENTS]
    worst_sim = max((v for v in sims.values() if v is not None), default=float("nan"))
    names = ", ".join(_short(lv["model"]).replace("flexible rod ", "") for lv in reduced)
    row2 = Row(29, goal2, f"{names}: Simeon within {worst_sim:.2%}; peaks (torque, pin forces) within "
               f"{max(model_err.values(), default=float('nan')):.1e} of the full rod on the {per['scene']}, each "
               f"periodic at rtol {per['reference_rtol']:g}",
               verdict(bool(reduced) and len(fits) == len(reduced)), src)
    return [row1, row2]


def modal_rod_rows(res: Results) -> list[Row]:
    """The reduced rod: the fastest level that meets the peak goal, and its Simeon and 8-element checks."""
    goal = (f"flexible rod with both clearances, one impact cycle within {GOAL_MODAL_PEAK:g} of the full FE rod: "
            f"< {GOAL_MODAL_CYCLE_S:g} s")
    goal2 = (f"the reduced rod: Simeon's reference within {GOAL_MODAL_SIMEON:.0%}, the 8-element rod within "
             f"{GOAL_MODAL_ELEMENTS:.0%} on the impacting scene")
    r = res.json("modal_rod.json")
    if r is None:
        return [missing(29, goal, "modal_rod.json"), missing(29, goal2, "modal_rod.json")]
    src = f"modal_rod.json, {r['date']}"
    if r.get("periodic"):
        return _periodic_modal_rows(r, goal, goal2, src)
    reduced = [c for c in r["cycles"] if c["spec"].get("n_modes") is not None]
    good = [c for c in reduced if c["errors"]["torque"] <= GOAL_MODAL_PEAK]
    best = min(good, key=lambda c: c["median_s"]) if good else None
    fe4 = next((c for c in r["cycles"] if c["spec"]["rod"] == "flexible" and c["spec"].get("n_modes") is None
                and c["spec"]["n_elements"] == 4), None)
    base = f"; the 4-element rod {fe4['median_s']:.2f} s" if fe4 else ""
    window = r.get("t_end", 0.8)
    part = "" if window >= 0.8 else f" for {window:g} s of the 0.8 s cycle"
    fastest = min(reduced, key=lambda c: c["median_s"])
    if best is None:
        row1 = Row(29, goal, f"no reduced rod within the peak tolerance: the fastest, {fastest['model']}, "
                   f"{fastest['median_s']:.2f} s{part}, peak torque {fastest['errors']['torque']:.1e} from the full "
                   f"rod{base}", verdict(False), src)
        return [row1, _reduced_agreement_row(r, reduced, goal2, src)]
    # a window shorter than the cycle bounds the cycle's time from below: a miss is a miss, a pass is not shown
    ok = best["median_s"] < GOAL_MODAL_CYCLE_S
    row1 = Row(29, goal, f"{best['model']}: **{best['median_s']:.2f} s**{part} (median of {r['repeat']}), peak "
               f"torque {best['errors']['torque']:.1e} from the full rod{base}",
               verdict(ok) if window >= 0.8 or not ok else "not measured (a window of the cycle)", src)
    sim_err = _simeon_error(r, best)
    el_err = max(best["errors"].values())
    row2 = Row(29, goal2, f"{best['model']}: Simeon within {float('nan') if sim_err is None else sim_err:.2%} "
               f"(largest of slider position, velocity, midspan deflection and its extremes); peaks within "
               f"{el_err:.2%} of the full rod",
               verdict(sim_err is not None and sim_err <= GOAL_MODAL_SIMEON and el_err <= GOAL_MODAL_ELEMENTS), src)
    return [row1, row2]


def shooting_row(res: Results) -> Row:
    """#29: IDAS multiple shooting on the slender-rod scene from collocation's answer (archive job
    transcriptions_flexible_shooting)."""
    goal = "`MultipleShooting(\"idas\")` on the slender-rod scene: converged, within 0.5 % of collocation"
    d = res.json("transcriptions_flexible_shooting.json")
    if d is None or not d.get("runs"):
        return missing(29, goal, "transcriptions_flexible_shooting.json")
    r, colloc = d["runs"][0], d["collocation_verified"]
    if "error" in r:
        return Row(29, goal, f"started from collocation's verified {colloc:.3f} N·m: {r['error'].splitlines()[0]}",
                   verdict(False), f"transcriptions_flexible_shooting.json, {d['date']}")
    rel = r["verified_objective"] / colloc - 1
    held = r.get("periodic") is True and r.get("ram_speed_violation_m_s", 1.0) <= 0.0
    text = (f"{r['status']}, {r['iterations']} iterations, {r['wall_time_s']:.0f} s "
            f"({r['wall_time_s'] / max(r['iterations'], 1):.1f} s per iteration, compile included); verified "
            f"{r['verified_objective']:.3f} N·m against collocation's {colloc:.3f} ({rel:+.1%})"
            + ("" if held else ", its re-simulation not periodic with the ram speed in tolerance"))
    # a lower verified peak than collocation's is better, not a miss: the goal is no more than 0.5 % above
    return Row(29, goal, text, verdict(r["success"] and held and rel <= 0.005),
               f"transcriptions_flexible_shooting.json, {d['date']}")


def drive_row(res: Results) -> Row:
    """#32: press75's optimum with a drive between the floor and today's optimum holds its envelope
    on the re-simulation; a too-weak motor is named (job drive)."""
    goal = ("press75 with a motor between the rigid floor and today's optimum: the drive envelope holds on the "
            "re-simulated optimum; a too-weak motor named")
    d = res.json("drive.json")
    if d is None:
        return missing(32, goal, "drive.json")
    held, weak, m = d["held"], d["weak"], d["held"]["motor"]
    named = "drive.peak_torque" in weak["status"] and not weak["success"]
    cb = held.get("counterbalance_N", 0.0)
    text = (f"motor {held['drive']['peak_torque']:g} N·m (crank equivalent {held['crank_equivalent_peak_N_m']:.0f} N·m)"
            + (f", press75 with a {cb:.0f} N counterbalance chosen with the speed" if cb else "") + ": "
            f"{'verified' if held['verified'] else 'NOT verified'} at {held['peak_torque_N_m']:.2f} N·m crank torque, "
            f"motor peak {m['peak_torque']:.3g} N·m (margin {m['peak_torque_margin']:+.1%}), RMS {m['rms_torque']:.3g} "
            f"N·m (margin {m['rms_margin']:+.1%}), top speed margin "
            f"{m['speed_margin']:+.1%}, {held['wall_time_s']:.0f} s; a {weak['drive']['peak_torque']:g} N·m motor: "
            + ("named in the status" if named else f"status {weak['status'][:80]!r}"))
    if not held["success"]:
        text += f"; the answer is not a converged optimum ({held['status']})"
    return Row(32, goal, text, verdict(bool(d["envelope_held"]) and named and held["success"]),
               f"drive.json, {d['date_run']['date']}")


def counterbalance_rows(res: Results) -> list[Row]:
    """#32: the optimised counterbalance against none on press75 (verified peaks, reversals); the
    process-force curve against the constant force, and a deep-drawing curve verified (job
    counterbalance)."""
    goals = ("press75: the optimised counterbalance lowers the verified peak torque below 145.4 N·m; reversals "
             "before/after",
             "process force: a tabulated curve equal to the constant force gives the same optimum (±0.1 %); a "
             "deep-drawing curve gives a verified optimum")
    d = res.json("counterbalance.json")
    if d is None:
        return [missing(32, g, "counterbalance.json") for g in goals]
    by, when = {c["case"]: c for c in d["cases"]}, f"counterbalance.json, {d['date_run']['date']}"

    def line(c: dict) -> str:
        cb = c["counterbalance"]
        losses = "/".join(str(v) for v in c["contact_losses"].values())
        return (f"{c['case']}: {'verified' if c['verified'] else 'NOT verified'} {c['peak_torque_N_m']:.1f} N·m"
                + (f" with {cb['force']:.0f} N" if cb["force"] else "")
                + f", {c['rod_load_reversals']} rod-load reversals, contact losses (crank/wrist pin) {losses}, {c['wall_time_s']:.0f} s")

    first = "; ".join(line(by[k]) for k in ("none", "constant", "gas") if k in by)
    rows = [Row(32, goals[0], first, verdict(bool(d["counterbalance_lowers_peak"])), when)]
    if "drawing_curve" in by:
        rel, draw = d["curve_against_constant"], by["drawing"]
        text = (f"curve against constant {rel:+.4%}; {line(by['drawing_constant'])}; {line(by['drawing_curve'])}; "
                f"{line(draw)}")
        rows.append(Row(32, goals[1], text, verdict(abs(rel) <= 1e-3 and draw["verified"]), when))
    return rows


def flights(contacts: dict | None) -> str:
    """The deepest separation and fastest return of a job's ``contacts`` record (`pressocp.journals`),
    as " (deepest ... µm, back at up to ... mm/s)"; "" without a record or a separation."""
    lost = [c for c in (contacts or {}).values() if c["losses"]]
    if not lost:
        return ""
    deep = max(lost, key=lambda c: c["depth"])
    return (f" (deepest {deep['depth'] * 1e6:.2g} µm, {deep['depth_ratio']:.2%} of the clearance; back at the wall at "
            f"up to {max(c['return_speed'] for c in lost) * 1e3:.2g} mm/s)")


def forming_row(res: Results) -> Row:
    """#32: the forming press with its 60 kN force: verified without journal impacts with an
    optimised counterbalance, within 1.5 x its rigid floor; said up front without one (job forming)."""
    goal = ("forming press (60 kN): with an optimised counterbalance a verified optimum without journal impacts, "
            "within 1.5 x its rigid floor; without one, said at the start")
    d = res.json("forming.json")
    if d is None:
        return missing(32, goal, "forming.json")
    losses = sum(d["contact_losses"].values())
    converged = d.get("success", True)
    text = (f"{'verified' if d['verified'] else 'NOT verified'} {d['peak_torque_N_m'] / 1e3:.2f} kN·m with a "
            f"{d['counterbalance_N'] / 1e3:.1f} kN counterbalance, {d['ratio_to_floor']:.2f} x the rigid floor "
            f"({d['rigid_floor_without_counterbalance_N_m'] / 1e3:.2f} kN·m), {d['rod_load_reversals']} rod-load "
            f"reversals, {losses} contact losses{flights(d.get('contacts'))}, {d['wall_time_s']:.0f} s; without a "
            "counterbalance: "
            + ("warned before any solve" if d["warning_without_counterbalance"] else "no warning")
            + ("" if converged else f"; IPOPT did not converge ({d['status']}, iteration limit "
               f"{d.get('max_iter') or 'the default'}): the answer is the best verified iterate, not an optimum"))
    ok = d["verified"] and losses == 0 and d["ratio_to_floor"] <= 1.5 and bool(d["warning_without_counterbalance"])
    return Row(32, goal, text, verdict(ok and converged), f"forming.json, {d['date_run']['date']}")


def stroke_rate_row(res: Results) -> Row:
    """#32: press75's highest stroke rate with a given motor, verified; +2 % fails (job stroke_rate)."""
    goal = ("press75 with a given motor: the highest stroke rate, verified with every limit held; at +2 % some "
            "limit fails; the time it takes")
    d = res.json("stroke_rate.json")
    if d is None:
        return missing(32, goal, "stroke_rate.json")
    if d["max_stroke_rate_spm"] is None:
        return Row(32, goal, "no rate tried held every limit", verdict(False), f"stroke_rate.json, {d['date_run']['date']}")
    best, above = d["best"], d["above"]
    text = (f"motor {d['drive']['peak_torque']:g} N·m (gear {d['drive']['gear_ratio']:g}): {d['max_stroke_rate_spm']:.1f} "
            f"strokes/min, verified peak {best['peak_torque']:.1f} N·m at the crank, peak-curve margin "
            f"{best['margins']['peak_torque_margin']:+.1%}; at {above['rate_spm']:.1f} spm failed "
            f"{', '.join(above['failed']) or 'nothing'}; {len(d['trials'])} rates tried"
            + (f" ({d['optimisations']} optimisations: a rate whose optimum missed the drive is optimised again with "
               "its limits held)" if "optimisations" in d else "") + f" in {d['wall_time']:.0f} s")
    sources = f"stroke_rate.json, {d['date_run']['date']}"
    big = res.json("stroke_rate_press60_big_rotor.json")
    if big is not None and big.get("unconstrained_only"):
        rate = big["max_stroke_rate_spm"]
        text += (f"; press60 with a large rotor (J i² about the crank's inertia): "
                 f"{'no rate' if rate is None else f'{rate:.1f} strokes/min'}, against "
                 f"{big['unconstrained_only']['max_stroke_rate_spm']:.1f} when each rate's optimum is only checked")
        sources += f"; stroke_rate_press60_big_rotor.json, {big['date_run']['date']}"
    return Row(32, goal, text, verdict(bool(d["above_fails"])), sources)


def slow_tests_row(res: Results) -> Row:
    """The tests the default run leaves out (marked slow; the property tests at many examples) all
    pass (job slow_tests): met only when none failed or errored, and some ran."""
    goal = "the tests marked slow and the property tests at the thorough profile (`-m \"slow or hypothesis\"`) pass"
    d = res.json("slow_tests.json")
    if d is None:
        return Row(None, goal, "not measured", "not measured", "slow_tests.json")
    bad = d["failed_tests"]
    text = (f"{d['passed']} passed, **{d['failed']} failed, {d['errors']} errors**, {d['skipped']} skipped in "
            f"{d['wall_time_s'] / 60:.1f} min on {d['workers']} workers" + (f": {', '.join(bad[:5])}" if bad else ""))
    ok = d["failed"] == 0 and d["errors"] == 0 and d["passed"] > 0 and d["exit_status"] == 0
    return Row(None, goal, text, verdict(ok), f"slow_tests.json, {d['date_run']['date']}")


def ad_row(res: Results) -> Row:
    """#29: AD against central differences on the seed optimum (bench_sensitivity_seed): the cheapest
    setting of each within the error goal, and AD there against central differences at rtol 1e-10."""
    goal = (f"AD sensitivities of the peak torque to 3 parameters on the seed optimum: ≥ {GOAL_AD_RATIO:g} × faster "
            f"than central differences at equal accuracy, each within {100 * GOAL_AD_ERROR:g} % of them at rtol 1e-10")
    r = res.json("sensitivity_seed.json")
    if r is None:
        return missing(29, goal, "sensitivity_seed.json")
    eq = r["equal_accuracy"]
    label = "AD, no estimate"  # central differences carry no error estimate; AD with one is shown beside
    ad, cd, full = eq.get(label), eq["central differences"], eq["AD"]
    if ad is None or cd is None:
        which = label if ad is None else "central differences"
        return Row(29, goal, f"{which} reached no error within {100 * GOAL_AD_ERROR:g} % at the tolerances run",
                   verdict(False), f"sensitivity_seed.json, {r['date']}")
    against = r["ad_against_cd_1e-10"][f"{label} rtol {ad['rtol']:g}"]
    ok = eq["ratio"] >= GOAL_AD_RATIO and against <= GOAL_AD_ERROR
    with_estimate = ("" if full is None else f"; AD with its error estimate (a second run at ten times rtol) "
                     f"{full['median_s']:.1f} s (rtol {full['rtol']:g}): {eq['ratio_with_estimate']:.2f} ×")
    return Row(29, goal, f"errors against central differences at rtol {r['reference_rtol']:g}: AD without its error "
               f"estimate {ad['median_s']:.2f} s (rtol {ad['rtol']:g}, error {ad['error']:.1e}) against central "
               f"differences {cd['median_s']:.2f} s (rtol {cd['rtol']:g}, error {cd['error']:.1e}): "
               f"**{eq['ratio']:.2f} ×**{with_estimate}; AD against central differences at rtol 1e-10: "
               f"{100 * against:.2g} %{same_integrator(r)}", verdict(ok), f"sensitivity_seed.json, {r['date']}")


def same_integrator(r: dict) -> str:
    """The AD row's comparison on one integrator: central differences on the compiled CVODES driver
    that integrates AD's sensitivities (empty for a run before it was measured)."""
    eq, label = r["equal_accuracy"], "central differences (AD's CVODES driver)"
    if eq.get("ratio_same_integrator") is None or eq.get(label) is None:
        return ""
    alt = r.get("alternated")
    alternated = ("" if not alt else f" (timed in turn, {len(alt['times_s'][label])} runs each: "
                  f"{alt['median_s']['AD, no estimate']:.2f} s against {alt['median_s'][label]:.2f} s, "
                  f"**{alt['ratio_same_integrator']:.2f} ×**)")
    return (f"; AD's engine: {r.get('ad_engine', '?')}; central differences on that same compiled CVODES driver "
            f"{eq[label]['median_s']:.2f} s (rtol {eq[label]['rtol']:g}): **{eq['ratio_same_integrator']:.2f} ×** "
            f"on one integrator{alternated}")


CHECKS: tuple[Callable[[Results], Row | list[Row]], ...] = (
    speed_rows, flexible_row, sweep_optima_row, suite_row, radau_row, verification_row, optimum_sensitivity_row,
    sweep_parallel_row, modal_rod_rows, shooting_row, drive_row, counterbalance_rows, forming_row, stroke_rate_row,
    slow_tests_row, ad_row)


def layer_row() -> Row:
    """`lint-imports` with the contracts of pyproject.toml, on the package as it is now."""
    goal = "`lint-imports` passes with contracts for the layers: no import circle, no upward import"
    try:
        from importlinter.cli import lint_imports
    except ImportError:
        return missing(31, goal, "import-linter not installed")
    with contextlib.redirect_stdout(io.StringIO()) as out:
        code = lint_imports(config_filename=str(ROOT / "pyproject.toml"), no_cache=True)
    kept = [line for line in out.getvalue().splitlines() if line.startswith("Contracts:")]
    return Row(31, goal, kept[0] if kept else f"exit status {code}", verdict(code == 0), "the code, now")


def size_row(package: Path = ROOT / "pressocp") -> Row:
    """Public functions with more than `MAX_PARAMETERS` parameters (self and cls not counted) and
    functions longer than `MAX_LINES` lines (docstring included), read from the package's source."""
    wide, long = [], []
    for path in sorted(package.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            a, name = node.args, f"{path.stem}.{node.name}"
            count = len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + (a.vararg is not None) + \
                (a.kwarg is not None) - (bool(a.args) and a.args[0].arg in ("self", "cls"))
            if count > MAX_PARAMETERS and not node.name.startswith("_"):
                wide.append(f"{name} ({count})")
            if node.end_lineno - node.lineno + 1 > MAX_LINES:
                long.append(f"{name} ({node.end_lineno - node.lineno + 1})")
    goal = f"no public function with more than {MAX_PARAMETERS} parameters, no function over {MAX_LINES} lines"
    measured = (f"{len(wide)} with more parameters: {', '.join(wide) or 'none'}; "
                f"{len(long)} longer: {', '.join(long) or 'none'}")
    return Row(31, goal, measured, verdict(not wide and not long), "the code, now")


#: A result's ISO date as the rows quote it.
STAMP = re.compile(r"\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}")


def stale(row: Row, runs: dict) -> Row:
    """`row`, its verdict marked stale when the job named after its result file (``drive`` for
    ``drive.json``) ran after the row's latest date and did not finish (a non-zero exit status: failed,
    or stopped over its budget): the row then reads a file that run did not refresh."""
    dates = STAMP.findall(row.source)  # "file.json, DATE", or "file.jsonl, before DATE, after DATE"
    run = runs.get(Path(row.source.split(",")[0].split(" ")[0]).stem)
    if not run or not dates or run.get("date", "") <= max(dates) or run.get("exit_status") == 0:
        return row
    how = f"stopped over its budget ({run['wall_time_s'] / 60:.0f} min)" if run.get("over_budget") else \
        f"failed (exit status {run.get('exit_status')})"
    return replace(row, verdict=f"{row.verdict}; **stale**: the job's last run ({run['date']}) {how}, so this row "
                                "is from the run before")


def rows(folder: Path = RESULTS) -> list[Row]:
    """Every goal's row from the result files in `folder`, marked `stale` where the job that writes the
    file last ran after it and did not finish."""
    res, out = Results(folder), []
    for check in CHECKS:
        got = check(res)
        out += got if isinstance(got, list) else [got]
    runs = res.json("runs.json") or {}
    return [stale(r, runs) for r in out]


def table(folder: Path = RESULTS) -> str:
    """The markdown table of the goals, read now from `folder`."""
    found = rows(folder) + [layer_row(), size_row()]
    lines = ["| issue | goal | measured | verdict | source, date |", "|---|---|---|---|---|"]
    lines += [f"| {'tests' if r.issue is None else f'#{r.issue}'} | {r.goal} | {r.measured} | {r.verdict} | "
              f"{r.source} |" for r in found]
    return "\n".join(lines)


def replace_block(readme: Path, markers: tuple[str, str], body: str, heading: str) -> None:
    """Replace the text between `markers` (begin, end) of `readme` with `body`; when they are missing,
    add them with `body` at its end under a ``## heading``."""
    begin, end = markers
    text = readme.read_text()
    block = f"{begin}\n{body}\n{end}"
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        text = head + block + rest.split(end, 1)[1]
    else:
        text = text.rstrip("\n") + f"\n\n## {heading}\n\n" + block + "\n"
    readme.write_text(text)


def write_readme(readme: Path, folder: Path = RESULTS) -> None:
    """Replace the goals block of `readme` (added at its end when missing) with the table of `folder`."""
    replace_block(readme, (BEGIN, END), table(folder), "The open issues' goals, from the last runs")


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))  # run as a script: `suite_now` imports the runner as `benchmarks`
    sys.stdout.write(table() + "\n")
