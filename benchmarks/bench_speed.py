"""The bundled scenarios' default calls, each run in a fresh process, timed from the parent.

    python benchmarks/bench_speed.py [--scenarios press75 press60 ...] [--repeat 3] [--label after]
                                     [--python EXE] [--cold-first | --cold-all]

Every run is ``Scenario.load(name).optimize(progress=False)`` in a new Python process (import and
set-up included, as a user starts it). ``--cold-all``: every run with an empty compile cache of its
own. ``--cold-first``: the first run of each scenario uses an empty
compile cache (``PRESSOCP_CACHE_DIR`` in a fresh folder: the compile paid), the others the cache it
left (a second process with the same model). ``--python EXE`` runs another interpreter, e.g. a
virtual environment with an earlier version of the package installed (the "before" rows; it must
accept the same call). Each run records its wall time, peak
torque, verification, stages with iterations and times, and (when the package has it) the time
table (`OcpResult.time_table`) with the compiler's time summed over it (``compile_s``: with a filled
cache, 0 s). Rows are appended to ``results/speed.jsonl`` with the label, date and
machine; ``results/speed.png`` is drawn from the newest row of each (scenario, label): medians with
every run, the goals, and for press75 the stage times of the newest "before" and "after" rows.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pressocp.report import stamp
from status import figure_note  # a sibling script: this folder is the script's path

OUT = Path(__file__).parent / "results"
ROWS = OUT / "speed.jsonl"
SCENARIOS = ("press75", "press60", "large_press", "slender_rod")
#: The fast-optimiser goals: the seed call in 45 s (20 s the moonshot) at <= 146.0 N m verified, the
#: other scenarios 2 x faster than before.
GOAL_SEED_S, MOONSHOT_S, GOAL_SEED_NM, GOAL_SPEEDUP = 45.0, 20.0, 146.0, 2.0

CHILD = """
import json, sys, time
t0 = time.perf_counter()
import pressocp as po
r = po.Scenario.load(sys.argv[1]).optimize(progress=False)
table = r.time_table() if hasattr(r, "time_table") else []
print("RESULT" + json.dumps({
    "inside_s": time.perf_counter() - t0, "peak_torque": r.peak_torque, "verified": bool(r.verified),
    "success": bool(r.success), "objective_value": r.objective_value, "verified_objective": r.verified_objective,
    "max_ram_speed_violation": r.max_ram_speed_violation, "rigid_peak_torque": r.rigid_peak_torque,
    "stages": [{"name": s.name, "iterations": s.iterations, "wall_time": s.wall_time, "objective": s.objective,
                "status": s.status, "superseded": s.superseded,
                "verified_value": s.details.get("verified_value", s.details.get("candidate_value"))}
               for s in r.stages],
    "time_table": table, "compile_s": sum(t.get("compile", 0.0) for t in table) if table else None}))
"""


def run_once(name: str, env: dict, python: str) -> dict:
    """One default call in a new process; wall time measured here."""
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as cwd:  # not this checkout's folder: `python -c` imports from its cwd
        out = subprocess.run([python, "-c", CHILD, name], env=env, capture_output=True, text=True, cwd=cwd)
    wall = time.perf_counter() - t0
    line = [x for x in out.stdout.splitlines() if x.startswith("RESULT")]
    if out.returncode != 0 or not line:
        return {"wall_s": wall, "error": (out.stderr or out.stdout)[-2000:]}
    return {"wall_s": wall, **json.loads(line[0][len("RESULT"):])}


def measure(name: str, repeat: int, label: str, python: str, cold_first: bool, cold_all: bool = False) -> dict:
    env = dict(os.environ)
    runs = []
    with tempfile.TemporaryDirectory(prefix="pressocp-cache-") as cache:
        for k in range(repeat):
            if cold_all:  # a new empty cache for every run
                env["PRESSOCP_CACHE_DIR"] = os.path.join(cache, f"run{k}")
            elif cold_first:
                env["PRESSOCP_CACHE_DIR"] = cache  # empty for the first run, filled by it for the others
            r = run_once(name, env, python)
            r["compile_cache"] = "empty" if cold_all or (cold_first and k == 0) else (
                "filled" if cold_first else "user's")
            runs.append(r)
            print(f"{name} [{label}] run {k + 1}: {r['wall_s']:.1f} s, peak "
                  f"{r.get('peak_torque', float('nan')):.4f} N m, verified {r.get('verified')}, compile "
                  f"{r.get('compile_s') if r.get('compile_s') is not None else float('nan'):.1f} s "
                  f"({r['compile_cache']} cache)", flush=True)
    ok = [r for r in runs if "error" not in r]
    return {"scenario": name, "label": label, "run": stamp(), "python": python, "repeat": repeat,
            "median_wall_s": statistics.median(r["wall_s"] for r in runs),
            "wall_s": [r["wall_s"] for r in runs], "compile_s": [r.get("compile_s") for r in runs],
            "peaks": [r.get("peak_torque") for r in runs], "all_verified": bool(ok) and all(r["verified"] for r in ok),
            "answers_agree": bool(ok) and max(r["peak_torque"] for r in ok) - min(r["peak_torque"] for r in ok)
            <= 1e-3 * min(r["peak_torque"] for r in ok), "runs": runs}


def newest(rows: list[dict]) -> dict:
    """The newest row of each (scenario, label) among those measured on the newest row's machine
    (its platform string, which names the VM's build: the same "2-core VM" ran 2 x slower in some
    sessions than in others, so one figure shows one session's rows)."""
    platform = rows[-1]["run"].get("platform") if rows else None
    return {(r["scenario"], r["label"]): r for r in rows if r["run"].get("platform") == platform}


def stage_times(row: dict) -> list[tuple[str, float]]:
    """(stage, s) of the run nearest the row's median; the verification and set-up when recorded."""
    runs = [r for r in row["runs"] if "error" not in r]
    run = min(runs, key=lambda r: abs(r["wall_s"] - row["median_wall_s"]))
    if run.get("time_table"):
        return [(t["stage"], t["wall"]) for t in run["time_table"]]
    parts = [(s["name"], s["wall_time"]) for s in run["stages"]]
    return parts + [("rest", run["wall_s"] - sum(w for _, w in parts))]


def timeline(parts: list[tuple[str, float]]) -> list[tuple[int, str, float, float]]:
    """(lane, stage, start, length) of each stage: a candidate's stages (``name@margin``) one after the
    other on a lane of their own from the end of the stages before them (they ran side by side), the
    "prepare" (compiled ahead in a worker from the call's start) on a lane of its own from 0, the
    others on lane 0 after everything before them."""
    lanes: dict[str, int] = {}
    out, t_common, ends = [], 0.0, {}
    for name, t in parts:
        if name == "prepare":
            out.append((lanes.setdefault(name, len(lanes)), name, 0.0, t))
            continue
        if "@" in name:
            m = name.split("@", 1)[1]
            lane = lanes.setdefault(m, len(lanes))
            start = ends.get(m, t_common)
            ends[m] = start + t
        else:
            lane, start = 0, max([t_common, *ends.values()])
            t_common = start + t
        out.append((lane, name, start, t))
    return out


#: What each label of the speed rows means, for the figure's legend.
LABEL_TEXT = {"before": "before: the code before #28",
              "after": "after: fresh process, compile cache emptied before the first run only",
              "cold": "cold: compile cache emptied before every run"}


def stage_kind(name: str) -> str:
    """The stage's kind, the same colour on every lane: ``polish_1@0.05`` -> ``polish``."""
    return name.split("@", 1)[0].rstrip("0123456789").rstrip("_")


def plot(rows: list[dict]) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    last = newest(rows)
    scen = [s for s in SCENARIOS if any(k[0] == s for k in last)]
    labels = sorted({k[1] for k in last}, key=lambda x: (x != "before", x))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(13, 5), gridspec_kw={"width_ratios": [1.2, 1]})
    width = 0.8 / max(len(labels), 1)
    compiles: dict[str, str] = {}
    # a linear axis from 0, so that a bar's length is its time; labels above the highest run, neighbours
    # at alternating heights so that they do not overlap
    top = max([GOAL_SEED_S, *(max(r["wall_s"], default=r["median_wall_s"]) for r in last.values())])
    for j, lab in enumerate(labels):
        for i, s in enumerate(scen):
            row = last.get((s, lab))
            if row is None:
                continue
            x = i + (j - (len(labels) - 1) / 2) * width
            a1.bar(x, row["median_wall_s"], width, color=f"C{j}", label=LABEL_TEXT.get(lab, lab) if i == 0 else None)
            a1.plot([x] * len(row["wall_s"]), row["wall_s"], "k.", ms=4)
            pk = [p for p in row["peaks"] if p is not None]
            a1.annotate(f"{row['median_wall_s']:.0f} s\n{min(pk):.1f} N·m" if pk else "failed",
                        (x, max(row["wall_s"], default=row["median_wall_s"]) + top * (0.14 if j % 2 else 0.02)),
                        ha="center", va="bottom", fontsize=7, bbox={"facecolor": "white", "alpha": 0.8,
                                                                     "edgecolor": "none", "pad": 0.5})
            comp = [c for c in row.get("compile_s", []) if c is not None]
            if comp:  # the compiler's time in each run (the first with an empty cache), under the axis
                compiles[s] = " / ".join(f"{c:.1f}" for c in comp)
    a1.axhline(GOAL_SEED_S, color="g", ls="--", lw=1, label=f"press75 goal {GOAL_SEED_S:.0f} s")
    a1.axhline(MOONSHOT_S, color="g", ls=":", lw=1, label=f"moonshot {MOONSHOT_S:.0f} s")
    a1.set_xticks(range(len(scen)), [f"{sc}\ncompile {compiles[sc]} s" if sc in compiles else sc for sc in scen],
                  fontsize=8)
    a1.set_ylabel("wall time of the default call, s (median; dots: every run)")
    a1.set_ylim(0, top * 1.4)  # room for the labels above the tallest bar
    a1.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
    a1.set_title("Scenario.load(name).optimize(), fresh process each run")
    ticks, colours = [], {}
    for j, lab in enumerate(labels):
        row = last.get(("press75", lab))
        if row is None:
            continue
        lane_names = {0: lab}
        for lane, name, t0, t in timeline(stage_times(row)):
            y = j + 0.3 * lane
            kind = stage_kind(name)
            first = kind not in colours  # the legend names each kind once
            colour = colours.setdefault(kind, f"C{len(colours) % 10}")
            a2.barh(y, t, left=t0, height=0.25, color=colour, edgecolor="w", label=kind if first else None)
            if t > 3:
                a2.text(t0 + t / 2, y, f"{t:.0f}", ha="center", va="center", fontsize=6)
            if name == "prepare":
                lane_names[lane] = "compiled ahead in a worker"
            elif "@" in name:
                lane_names[lane] = f"{lab + ': ' if lane == 0 else ''}candidate @{name.split('@', 1)[1]}"
        ticks += [(j + 0.3 * lane, text) for lane, text in lane_names.items()]
    a2.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=4)
    a2.axvline(GOAL_SEED_S, color="g", ls="--", lw=1)
    a2.text(GOAL_SEED_S, 1.0, f"goal {GOAL_SEED_S:.0f} s ", transform=a2.get_xaxis_transform(), color="g",
            fontsize=7, ha="right", va="top")
    a2.set_yticks([y for y, _ in ticks], [text for _, text in ticks], fontsize=7)
    a2.set_xlabel("s (the run nearest the median; candidate chains side by side, one lane each)", fontsize=8)
    a2.set_title("press75: where the time went, stage by stage")
    fig.tight_layout()
    figure_note(fig, *(r["run"] for r in last.values()))
    path = OUT / "speed.png"
    fig.savefig(path, dpi=130)
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", nargs="+", default=list(SCENARIOS), choices=SCENARIOS)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--label", default="after")
    ap.add_argument("--python", default=sys.executable, help="the interpreter that runs the calls")
    cold = ap.add_mutually_exclusive_group()
    cold.add_argument("--cold-all", action="store_true", help="every run with an empty compile cache of its own")
    cold.add_argument("--cold-first", action="store_true", help="the first run of each scenario with an empty "
                    "compile cache, the others with what it left")
    ap.add_argument("--plot-only", action="store_true")
    a = ap.parse_args(argv)
    OUT.mkdir(exist_ok=True)
    if not a.plot_only:
        for name in a.scenarios:
            row = measure(name, a.repeat, a.label, a.python, a.cold_first, a.cold_all)
            with ROWS.open("a") as f:
                f.write(json.dumps(row) + "\n")
    rows = [json.loads(x) for x in ROWS.read_text().splitlines() if x.strip()]
    print(plot(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
