"""The tests the default ``pytest`` run leaves out: those marked ``slow`` (the long solves and the
notebooks that solve) and the property tests at the "thorough" hypothesis profile (200 examples;
the default run draws 12).

    python benchmarks/bench_slow_tests.py [--workers 2] [--out FOLDER] [-- PYTEST-ARGS ...]

Runs ``python -m pytest -m "slow or hypothesis" -p no:cacheprovider -n 2 --dist loadfile`` from the
repository root, with HYPOTHESIS_PROFILE=thorough; arguments after ``--`` go to pytest as they are
(``-- -k drive`` runs a selection). Writes ``slow_tests.json`` (date and machine, the command, wall
time, the numbers of tests passed, failed, with errors and skipped, the names of those that failed,
and each test's seconds) and ``slow_tests.png`` (the slowest tests' times) to ``results/``. Exits
with pytest's status: 0 only when every selected test passed.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import matplotlib.pyplot as plt

from pressocp.plots import save
from pressocp.report import stamp
from status import figure_note  # a sibling script: this folder is the script's path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "results"
#: The tests this job runs: the slow ones, and the property tests (hypothesis) at many examples.
MARKS = "slow or hypothesis"
#: The slowest tests drawn in the figure.
SHOWN = 25


def command(workers: int, junit: Path, extra: list[str]) -> list[str]:
    """The pytest command: the `MARKS` tests on `workers` processes, each test file in one of them,
    a JUnit XML report to `junit`, then `extra`."""
    return [sys.executable, "-m", "pytest", "-m", MARKS, "-p", "no:cacheprovider", "-n", str(workers),
            "--dist", "loadfile", "-q", f"--junitxml={junit}", *extra]


def read_junit(path: Path) -> dict:
    """Counts and per-test seconds from a JUnit XML report (each test's setup, call and teardown)."""
    counts = {"passed": 0, "failed": 0, "errors": 0, "skipped": 0}
    failed, seconds = [], {}
    if not path.exists():
        return {**counts, "failed_tests": failed, "seconds": seconds}
    for case in ET.parse(path).getroot().iter("testcase"):
        name = f"{case.get('classname', '')}::{case.get('name', '')}"
        seconds[name] = float(case.get("time") or 0.0)
        kinds = {child.tag for child in case}
        if "error" in kinds:
            counts["errors"] += 1
            failed.append(name)
        elif "failure" in kinds:
            counts["failed"] += 1
            failed.append(name)
        elif "skipped" in kinds:
            counts["skipped"] += 1
        else:
            counts["passed"] += 1
    return {**counts, "failed_tests": failed, "seconds": seconds}


def plot(data: dict, path: Path) -> Path:
    """Bars of the `SHOWN` slowest tests' seconds, failed ones in red."""
    slowest = sorted(data["seconds"].items(), key=lambda kv: kv[1], reverse=True)[:SHOWN][::-1]
    fig, ax = plt.subplots(figsize=(11, 0.28 * max(len(slowest), 4) + 1.2))
    names = [name.removeprefix("tests.").removeprefix("notebooks.")[:90] for name, _ in slowest]
    colours = ["tab:red" if name in data["failed_tests"] else "tab:blue" for name, _ in slowest]
    ax.barh(range(len(slowest)), [s for _, s in slowest], color=colours)
    ax.set_yticks(range(len(slowest)), names, fontsize=6)
    ax.set_xlabel("time per test [s] (setup, call and teardown)")
    ax.set_title(f"-m \"{MARKS}\": {data['passed']} passed, {data['failed']} failed, {data['errors']} errors, "
                 f"{data['wall_time_s'] / 60:.1f} min wall on {data['workers']} workers", fontsize=9)
    fig.subplots_adjust(left=0.5, right=0.98, top=1 - 0.5 / fig.get_figheight(), bottom=0.7 / fig.get_figheight())
    figure_note(fig, data.get("date_run"))
    return save(fig, path)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2, help="pytest-xdist worker processes (default 2)")
    ap.add_argument("--out", type=Path, default=OUT, help="folder of slow_tests.json and .png (default results/)")
    ap.add_argument("pytest_args", nargs="*", help="after --: passed to pytest (e.g. -- -k drive)")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        junit = Path(tmp) / "junit.xml"
        cmd = command(args.workers, junit, args.pytest_args)
        started, wall0 = stamp(), time.perf_counter()
        status = subprocess.run(cmd, cwd=ROOT, env={**os.environ, "HYPOTHESIS_PROFILE": "thorough",
                                                    "MPLBACKEND": "Agg"}).returncode
        wall = time.perf_counter() - wall0
        found = read_junit(junit)
    data = {"date_run": started, "command": shlex.join(["python", *cmd[1:]]).replace(str(junit), "JUNIT.xml"),
            "hypothesis_profile": "thorough", "workers": args.workers, "exit_status": status,
            "wall_time_s": wall, **found}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "slow_tests.json").write_text(json.dumps(data, indent=1) + "\n")
    print(f"{data['passed']} passed, {data['failed']} failed, {data['errors']} errors, {data['skipped']} skipped "
          f"in {wall / 60:.1f} min; {plot(data, args.out / 'slow_tests.png')}")
    return status


if __name__ == "__main__":
    sys.exit(main())
