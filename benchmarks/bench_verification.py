"""The final verification of the seed optimum: its periodic re-simulation at rtol 1e-9, now and before.

    python benchmarks/bench_verification.py [--before-commit SHA | --before-python EXE] [--repeat 3]

The seed optimum (`results/seed_optimum_speed.json`, the 75 spm default call's answer) re-simulated on
the clearance model by `verify_speed(model, speed, 1e-9)` from rest (the periodic search started
from centred journals), as the default call's verification does when no stage's state is at hand:
on the model as the optimiser verifies with it (`pressocp.simulate.for_repeated_use`: compiled where
a C compiler is found), or on the model as built where a version has no such function.
Each interpreter runs in a fresh process from a temporary folder: one call to warm up (integrator
construction, the compiled outputs' link), then `--repeat` timed calls; the median is reported. With
``--before-python`` (a virtual environment with an earlier version installed) both run in this one
invocation, so the ratio is measured in one run; ``--before-commit`` does the same with this
checkout's package at an earlier commit (extracted by ``git archive`` into a temporary folder and
put first on ``PYTHONPATH``, run by this interpreter with today's dependencies). Writes
``results/verification.json`` and ``results/verification.png`` with the date and machine.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from pressocp.report import stamp
from status import figure_note  # a sibling script: this folder is the script's path

OUT = Path(__file__).parent / "results"
SPEED = OUT / "seed_optimum_speed.json"
#: Goal of the fast-simulation issue: 3 x faster than before, the same peaks to 1e-6.
GOAL_RATIO, GOAL_PEAKS = 3.0, 1e-6

CHILD = """
import json, sys, time
import pressocp as po
from pressocp.model import build_model
try:
    from pressocp.verify import verify_speed
except ImportError:  # before 2026-11-26 it lived in pressocp.ocp
    from pressocp.ocp.verify import verify_speed
from pressocp.speed import FourierSpeed
problem = po.Scenario.load("press75").problem
speed = FourierSpeed.from_dict(json.loads(open(sys.argv[1]).read()))
model = build_model(problem.press, n_harmonics=problem.n_harmonics)
try:
    from pressocp.simulate import for_repeated_use
except ImportError:  # a version before the optimiser's checks ran compiled
    for_repeated_use = None
if for_repeated_use is not None:
    model = for_repeated_use(model)
t0 = time.perf_counter()
sim = verify_speed(model, speed, 1e-9)
first = time.perf_counter() - t0
times = []
for _ in range(int(sys.argv[2])):
    t0 = time.perf_counter()
    sim = verify_speed(model, speed, 1e-9)
    times.append(time.perf_counter() - t0)
names = ("torque", "slider_normal_force", "crank_pin_force", "wrist_pin_force")
print("RESULT" + json.dumps({"first_s": first, "times_s": times, "peaks": {n: sim.peak(n) for n in names},
                             "steps": sim.stats.get("steps"), "periodic": sim.stats.get("periodic")}))
"""


def run(python: str, repeat: int, source: Path | None = None) -> dict:
    """One fresh process of `python` verifying the seed optimum (with the package from `source` first on
    ``PYTHONPATH`` when given); its times and peaks."""
    env = None
    if source is not None:
        env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(source), os.environ.get("PYTHONPATH")]))}
    with tempfile.TemporaryDirectory() as cwd:  # not this checkout: `python -c` imports from its cwd
        out = subprocess.run([python, "-c", CHILD, str(SPEED), str(repeat)], capture_output=True, text=True, cwd=cwd,
                             env=env)
    line = [x for x in out.stdout.splitlines() if x.startswith("RESULT")]
    if out.returncode != 0 or not line:
        raise RuntimeError(f"{python} failed:\n{(out.stderr or out.stdout)[-2000:]}")
    r = json.loads(line[0][len("RESULT"):])
    r["median_s"] = statistics.median(r["times_s"])
    return r


def package_at(commit: str, folder: Path) -> Path:
    """This checkout's ``pressocp`` package at `commit`, extracted into `folder` (``git archive``)."""
    repo = Path(__file__).resolve().parent.parent
    git = subprocess.run(["git", "-C", str(repo), "archive", commit, "pressocp"], capture_output=True)
    if git.returncode != 0:  # e.g. a shallow clone without that commit
        raise RuntimeError(f"--before-commit {commit}: git archive failed: {git.stderr.decode().strip()}")
    subprocess.run(["tar", "-x", "-C", str(folder)], input=git.stdout, check=True)
    return folder


def figure(row: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = [k for k in ("before", "after") if k in row["runs"]]
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for i, k in enumerate(labels):
        r = row["runs"][k]
        ax.bar(i, r["median_s"], color="C0" if k == "before" else "C1")
        ax.plot([i] * len(r["times_s"]), r["times_s"], "k.")
        ax.text(i, r["median_s"], f"{r['median_s']:.2f} s\n{r['peaks']['torque']:.6f} N·m", ha="center", va="bottom")
    ax.set_xticks(range(len(labels)), labels)
    ax.set_ylabel("wall time, s (median; dots: every call)")
    title = "verify_speed(model, seed optimum, 1e-9): periodic, CVODES, 20 001 samples"
    if "ratio" in row:
        title += f"\n{row['ratio']:.1f} x faster; peaks agree to {row['max_peak_difference']:.1e} (goal {GOAL_RATIO:g} x, {GOAL_PEAKS:g})"
    ax.set_title(title, fontsize=9)
    ax.set_ylim(0, 1.3 * max(row["runs"][k]["median_s"] for k in labels))
    fig.tight_layout()
    figure_note(fig, row)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    before = ap.add_mutually_exclusive_group()
    before.add_argument("--before-python", default=None, help="interpreter with the earlier version installed")
    before.add_argument("--before-commit", default=None, help="an earlier commit of this checkout's package")
    ap.add_argument("--repeat", type=int, default=3, help="timed calls per process (median)")
    ap.add_argument("--replot", action="store_true", help="redraw the figure from results/verification.json")
    a = ap.parse_args()
    if a.replot:
        figure(json.loads((OUT / "verification.json").read_text()), OUT / "verification.png")
        return
    if a.repeat < 1:
        ap.error(f"--repeat must be >= 1, got {a.repeat}")
    runs = {"after": run(sys.executable, a.repeat)}
    if a.before_python:
        runs["before"] = run(a.before_python, a.repeat)
    if a.before_commit:
        with tempfile.TemporaryDirectory() as folder:
            runs["before"] = run(sys.executable, a.repeat, package_at(a.before_commit, Path(folder)))
    row = {**stamp(), "what": "verify_speed(model, seed optimum, rtol 1e-9) from rest, fresh process each side, "
                              "on the model as the optimiser verifies with it",
           "runs": runs, "before_python": a.before_python, "before_commit": a.before_commit}
    if "before" in runs:
        b, n = runs["before"], runs["after"]
        row["ratio"] = b["median_s"] / n["median_s"]
        row["max_peak_difference"] = max(abs(n["peaks"][k] / b["peaks"][k] - 1) for k in b["peaks"])
        row["goals_met"] = bool(row["ratio"] >= GOAL_RATIO and row["max_peak_difference"] <= GOAL_PEAKS)
    OUT.mkdir(exist_ok=True)
    (OUT / "verification.json").write_text(json.dumps(row, indent=1))
    figure(row, OUT / "verification.png")
    for k, r in runs.items():
        print(f"{k}: median {r['median_s']:.3f} s of {[round(x, 3) for x in r['times_s']]}, first {r['first_s']:.2f} s, "
              f"peak torque {r['peaks']['torque']:.9g} N m")
    if "ratio" in row:
        print(f"ratio {row['ratio']:.2f} x, peaks agree to {row['max_peak_difference']:.2g}")


if __name__ == "__main__":
    main()
