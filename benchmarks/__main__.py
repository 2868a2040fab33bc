"""Regenerate the benchmarks with one command.

    python -m benchmarks                  every benchmark, in order (many hours on 2 cores)
    python -m benchmarks --list           the benchmarks, their commands and rough durations
    python -m benchmarks --only figures stability_quick
    python -m benchmarks --skip ocp_slsqp --dry-run

Each benchmark runs as its own process (`sys.executable`), one after the other, so that no two
share the cores and each timing is its own. Its output goes to ``results/logs/<name>.log``. After
each run, ``results/runs.json`` records the command, date, machine, wall time, exit status and the
result files it created or changed (by content; a file rewritten unchanged is not listed), and the
table between the ``runs`` markers in ``benchmarks/README.md`` is rewritten from it (a ``note``
added by hand to a record of runs.json is shown with its status). The other tables of that README
are measurements with their discussion, written by hand from the JSON files; the table says which
files each run refreshed and when.

Every job has a time budget (`Job.minutes`); one still running after 1.5 x its budget
(``--budget-factor``) is stopped and recorded as over budget. A failing or stopped benchmark is
recorded with its exit status and the next one runs; the command exits with status 1 if any failed.
Ctrl-C stops the running benchmark and the command.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from pressocp.report import stamp

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
README = HERE / "README.md"
RUNS = RESULTS / "runs.json"
BEGIN, END = "<!-- runs:begin (written by python -m benchmarks) -->", "<!-- runs:end -->"


@dataclass(frozen=True)
class Job:
    """One benchmark run: a script of this folder and its arguments."""

    name: str
    script: str
    args: tuple[str, ...]
    minutes: float  # its budget on the 2-core machine: stopped after `BUDGET_FACTOR` x this
    what: str

    def command(self) -> list[str]:
        return [sys.executable, str(HERE / self.script), *self.args]


JOBS = (
    Job("figures", "figures.py", (), 2, "committed figures: rigid design, six-bar, impacts, Simeon"),
    Job("simulation", "bench_simulation.py", (), 120, "work-precision of the integrators, two models"),
    Job("work_precision", "bench_work_precision.py",
        ("--models", "clearance", "flexible-2", "--reference-timeout", "1800"), 30,
        "every integrator, clearance model and 2-element rod, both scenes"),
    Job("work_precision_4", "bench_work_precision.py", ("--models", "flexible-4", "--scenes", "smooth"), 10,
        "every integrator, 4-element rod, smooth scene"),
    Job("work_precision_8", "bench_work_precision.py",
        ("--models", "flexible-8", "--scenes", "smooth", "--reference-rtol", "1e-10",
         "--reference-check", "scipy-radau", "1e-10", "--reference-timeout", "1800"), 15,
        "8-element rod, smooth scene (CVODES 1e-10 reference, checked)"),
    Job("work_precision_impacting_4", "bench_work_precision.py",
        ("--models", "flexible-4", "--scenes", "impacting", "--reference-rtol", "1e-10", "--reference-check", "cvodes",
         "1e-9", "--reference-timeout", "1500"), 26, "4-element rod through impacts (its reference did not finish)"),
    Job("work_precision_impacting_8", "bench_work_precision.py",
        ("--models", "flexible-8", "--scenes", "impacting", "--reference-rtol", "1e-9", "--reference-check", "cvodes",
         "1e-8", "--reference-timeout", "1200"), 21, "8-element rod through impacts (its reference did not finish)"),
    Job("stability", "bench_stability.py", (), 60, "stability maps of the fixed-step integrators"),
    Job("ocp_default", "bench_ocp.py", ("default", "--repeat", "3"), 5, "default call, 60 spm scene"),
    Job("ocp_seed", "bench_ocp.py", ("seed", "--repeat", "3"), 20, "default call, 75 spm scene"),
    Job("speed", "bench_speed.py", ("--repeat", "3", "--cold-first"), 12,
        "the bundled scenarios' default calls, each in a fresh process, compile cache empty then filled"),
    Job("verification", "bench_verification.py", (), 1,
        "the seed optimum's final verification, this version (with --before-python: against another)"),
    Job("ocp_seed_collocation", "bench_ocp.py", ("seed_collocation", "--repeat", "3"), 15,
        "75 spm, every stage, collocation on CasADi's virtual machine"),
    Job("ocp_seed_collocation_jit", "bench_ocp.py", ("seed_collocation_jit", "--repeat", "3"), 6,
        "75 spm, every stage, collocation compiled"),
    Job("ocp_pin_cap_7000", "bench_ocp.py", ("pin_cap", "--cap-N", "7000"), 8, "pin-force cap 7 kN"),
    Job("ocp_pin_cap_6000", "bench_ocp.py", ("pin_cap", "--cap-N", "6000"), 8, "pin-force cap 6 kN"),
    Job("ocp_flexible", "bench_ocp.py", ("flexible", "--repeat", "3"), 4,
        "75 spm default call on the flexible rod with clearances (53 s a call)"),
    Job("ocp_slender", "bench_ocp.py", ("slender",), 12, "slender rod: the flexible stage runs"),
    Job("model_levels", "bench_model_levels.py", (), 25, "error and cost of each model level across scenes"),
    Job("ocp_slsqp", "bench_ocp.py", ("slsqp", "--ref", "seed"), 30, "SLSQP single-shooting baseline"),
    Job("collocation", "bench_collocation.py", ("--jit",), 30, "collocation element sweep"),
    Job("transcriptions_smooth", "bench_transcriptions.py", ("--case", "smooth", "--shooting-wall", "900"), 40,
        "transcriptions from one start, smooth case"),
    Job("transcriptions_seed", "bench_transcriptions.py", ("--case", "seed"), 45,
        "transcriptions from one start, 75 spm (IDAS shooting capped at 30 min)"),
    Job("transcriptions_flexible", "bench_transcriptions.py", ("--case", "flexible", "--shooting-wall", "900"), 60,
        "transcriptions from one start, slender flexible rod"),
    Job("reversal", "bench_reversal.py", (), 10, "rod-tension bound against impacts"),
    Job("transcriptions_map", "bench_transcriptions.py", ("--case", "map", "--shooting-wall", "600"), 110,
        "which transcription converges over stroke rate x clearance"),
    Job("sensitivity", "bench_sensitivity.py", (), 12, "AD sensitivities against differences, rtol 1e-10 .. 1e-13"),
    Job("optimum_sensitivity", "bench_optimum_sensitivity.py", (), 40, "dJ*/dp against re-solved optima"),
    Job("optimum_tracking", "bench_optimum_tracking.py", ("press75",), 40, "dJ*/dp against the tracked optimum"),
    Job("sweep_parallel", "bench_sweep.py", ("parallel",), 10, "sweep speed-up, 1/2 workers and dask"),
    Job("sweep_continuation", "bench_sweep.py", ("continuation",), 60, "warm path against cold starts"),
    Job("sweep_continuation_90", "bench_sweep.py",
        ("continuation", "--ram-speed", "-0.15", "--side-by-side", "--rates", "60", "65", "70", "75", "80", "85", "90"),
        60, "warm path against cold starts, 60 -> 90 spm at -0.15 m/s"),
    Job("studies", "bench_studies.py", ("stroke_rate", "clearance", "ram_speed", "slider_mass", "wear", "tornado"),
        140, "optima against stroke rate, clearance, ram speed, mass; wear; tornado"),
)


def result_contents() -> dict[str, str]:
    """SHA-1 of each file under results/ (logs and runs.json left out), by path relative to results/."""
    return {str(p.relative_to(RESULTS)): hashlib.sha1(p.read_bytes()).hexdigest() for p in RESULTS.rglob("*")
            if p.is_file() and p.parent.name != "logs" and p != RUNS}


def result_files(before: dict[str, str]) -> list[str]:
    """Files under results/ that are new or changed since `before` (`result_contents`). A file that
    another process wrote meanwhile is listed too: run the benchmarks alone for a clean record."""
    return sorted(name for name, digest in result_contents().items() if before.get(name) != digest)


def load_runs() -> dict:
    return json.loads(RUNS.read_text()) if RUNS.exists() else {}


def table(runs: dict) -> str:
    """The markdown table of the latest run of each benchmark, in `JOBS` order."""
    lines = ["| benchmark | command | date | machine (CPUs) | wall time | status | files refreshed |",
             "|---|---|---|---|---|---|---|"]
    for job in JOBS:
        r = runs.get(job.name)
        if r is None:
            lines.append(f"| {job.name} | `{' '.join([job.script, *job.args])}` | not run by this command yet | | | | |")
            continue
        status = "ok" if r["exit_status"] == 0 else (
            f"**over budget** (stopped at {r['wall_time_s'] / 60:.1f} min; budget {r.get('budget_min', job.minutes):g} min)"
            if r.get("over_budget") else f"**failed ({r['exit_status']})**")
        if r.get("note"):  # written by hand in runs.json: what the record alone does not say
            status += f": {r['note']}"
        files = ", ".join(f"`{f}`" for f in r["files"]) or "none"
        lines.append(f"| {job.name} | `{' '.join([job.script, *job.args])}` | {r['date']} | {r['machine']} "
                     f"({r['cpus']}) | {r['wall_time_s'] / 60:.1f} min | {status} | {files} |")
    return "\n".join(lines)


def write_readme(runs: dict) -> None:
    """Replace the text between the markers of benchmarks/README.md (added at its end when missing)."""
    text = README.read_text()
    block = f"{BEGIN}\n{table(runs)}\n{END}"
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        text = head + block + rest.split(END, 1)[1]
    else:
        text = text.rstrip("\n") + "\n\n## Latest runs of `python -m benchmarks`\n\n" + block + "\n"
    README.write_text(text)


#: A job is stopped when it runs this many times its budget (`Job.minutes`).
BUDGET_FACTOR = 1.5
#: Exit status recorded for a job stopped over its budget.
OVER_BUDGET = -1000


def run(job: Job, budget_factor: float = BUDGET_FACTOR) -> dict:
    """Run one job; its record for runs.json (`stamp` of its start: date, machine, CPUs, Python). A
    job still running after `budget_factor` x its budget is stopped (its process group killed) and
    recorded with exit status `OVER_BUDGET` and ``over_budget``."""
    logs = RESULTS / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    started, before, wall0 = stamp(), result_contents(), time.perf_counter()
    limit = budget_factor * job.minutes * 60.0
    with open(logs / f"{job.name}.log", "w") as log:
        proc = subprocess.Popen(job.command(), stdout=log, stderr=subprocess.STDOUT, cwd=HERE.parent,
                                start_new_session=True)  # its own process group: its workers stop with it
        try:
            status = proc.wait(timeout=limit)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            status = OVER_BUDGET
            log.write(f"\n[python -m benchmarks] stopped after {limit / 60:.1f} min, "
                      f"{budget_factor:g} x its budget of {job.minutes:g} min\n")
        except BaseException:  # Ctrl-C: stop the job too
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            raise
    return {"command": " ".join([job.script, *job.args]), **started, "budget_min": job.minutes,
            "wall_time_s": time.perf_counter() - wall0, "exit_status": status,
            "over_budget": status == OVER_BUDGET, "files": result_files(before)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.splitlines()[0])
    names = [j.name for j in JOBS]
    ap.add_argument("--only", nargs="+", choices=names, metavar="NAME", help="run these (in the usual order)")
    ap.add_argument("--skip", nargs="+", choices=names, metavar="NAME", default=[], help="run all but these")
    ap.add_argument("--list", action="store_true", help="list the benchmarks and stop")
    ap.add_argument("--dry-run", action="store_true", help="print the commands, run nothing")
    ap.add_argument("--budget-factor", type=float, default=BUDGET_FACTOR,
                    help=f"stop a job after this many times its budget (default {BUDGET_FACTOR:g})")
    args = ap.parse_args(argv)
    if not args.budget_factor > 0:
        ap.error(f"--budget-factor must be > 0, got {args.budget_factor:g}")
    jobs = [j for j in JOBS if (args.only is None or j.name in args.only) and j.name not in args.skip]
    if args.list or args.dry_run:
        for j in jobs:
            print(f"{j.name:24s} ~{j.minutes:>4g} min  {' '.join([j.script, *j.args])}  ({j.what})")
        print(f"{len(jobs)} benchmarks, about {sum(j.minutes for j in jobs) / 60:.1f} h on 2 cores")
        return 0
    failed = []
    for j in jobs:
        print(f"{j.name}: {' '.join([j.script, *j.args])} (budget {j.minutes:g} min) ...", flush=True)
        record = run(j, args.budget_factor)
        runs = load_runs()
        runs[j.name] = record
        RUNS.write_text(json.dumps(runs, indent=1) + "\n")
        write_readme(runs)
        print(f"  exit {record['exit_status']}, {record['wall_time_s'] / 60:.1f} min, "
              f"{len(record['files'])} files; log results/logs/{j.name}.log", flush=True)
        if record["exit_status"] != 0:
            failed.append(j.name)
    if failed:
        print(f"failed: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
