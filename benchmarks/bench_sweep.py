"""Sweep benchmark: parallel speed-up and continuation.

Cases (one per call; each writes benchmarks/results/sweep_<case>.json and .png):

* ``parallel``      8 periodic simulations on the clearance model (60 spm scenario, its kinematic
                    design, wrist-pin clearance 0.05..0.4 mm) with 1 and 2 workers of the package's
                    pool (`pressocp.workers.process_pool`: what ``po.sweep`` starts by default and
                    ``pressocp sweep --workers N`` uses, one native thread and the worker's malloc
                    settings each; the goal's pair), 1 and 2 workers of a plain spawned
                    ``ProcessPoolExecutor`` (a pool of the caller's, which the package does not
                    configure) and a dask ``LocalCluster`` of 2 workers, in one run, each
                    ``--repeat`` times (median); the tables must be identical apart from wall times.
* ``continuation``  optima along the stroke rate 60 -> 75 spm (7 points, 75 spm scenario): a path
                    (each optimum warm-started from its neighbour's, ``Strategy(mode="continue")``)
                    against cold starts (the default call at each point), one worker each; time per
                    point and the optima compared. At the scenario's -0.1 m/s the path stops at
                    75 spm: from 80 spm no 15-harmonic speed keeps the rod in tension over the window
                    and the default call gives no answer (docs/measurements.md). With
                    ``--ram-speed -0.15`` the window is crossed faster and the path runs
                    60 -> 90 spm; its files are named ``sweep_continuation_ram0.15*``. ``--side-by-side`` runs the path and the cold
                    starts at the same time, one worker (one core) each.
* ``optima``        the 8-optima sweep as a user runs it: ``pressocp sweep press75 --vary
                    press.wrist_pin.clearance=5e-5,1e-4,2e-4,3e-4 --vary problem.stroke_rate_spm=60,75
                    --task optimize --workers 2`` in a fresh process per run, timed from outside
                    (start-up and compile included; the compile cache as the last run left it), in
                    two variants alternating: continued along the clearance in segments of two
                    (``--along press.wrist_pin.clearance``, ``continued``, the goal's) ``--repeat``
                    times, and every point cold (``cold``, the comparison) ``--cold-repeat`` times
                    (default: as many); every row's verified flag and peak, and the medians.

    python benchmarks/bench_sweep.py CASE [--repeat R] [--cold-repeat R] [--rates 60 65 70 75] [--ram-speed V] [--side-by-side] [--replot]
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import os
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

import pressocp as po  # noqa: E402
from pressocp.io import versions  # noqa: E402
from pressocp.plots import save  # noqa: E402
from pressocp.report import stamp  # noqa: E402
from pressocp.workers import process_pool  # noqa: E402
from status import figure_note  # noqa: E402 (a sibling script: this folder is the script's path)

OUT = Path(__file__).parent / "results"


def machine() -> dict:
    return {**stamp(), "versions": versions()}


def spawn_pool(workers: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"))


def timed(fn) -> tuple[float, pd.DataFrame]:
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def parallel(repeat: int) -> dict:
    scenario = po.Scenario.load("press60")
    vary = {"wrist_pin.clearance": [float(c) for c in np.linspace(5e-5, 4e-4, 8)]}
    pools = {"1 worker": (process_pool, 1), "2 workers": (process_pool, 2),
             "1 worker, plain pool": (spawn_pool, 1), "2 workers, plain pool": (spawn_pool, 2)}
    times: dict[str, list[float]] = {**{label: [] for label in pools}, "dask, 2 workers": []}
    tables = {}
    for _ in range(repeat):
        for label, (pool_of, workers) in pools.items():
            with pool_of(workers) as pool:
                pool.submit(int).result()  # workers started (and pressocp imported lazily) inside the timing below
                dt, tables[label] = timed(lambda: po.sweep(scenario, vary, "simulate", executor=pool, progress=False))
            times[label].append(dt)
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                Client(cluster) as client:
            ex = client.get_executor()
            dt, tables["dask, 2 workers"] = timed(lambda: po.sweep(scenario, vary, "simulate", executor=ex,
                                                                   progress=False))
        times["dask, 2 workers"].append(dt)
    ref = tables["1 worker"].drop(columns="wall_time_s")
    identical = {k: bool(t.drop(columns="wall_time_s").equals(ref)) for k, t in tables.items()}
    med = {k: statistics.median(v) for k, v in times.items()}
    row = {"case": "parallel", **machine(), "points": 8, "repeat": repeat, "wall_times_s": times,
           "median_s": med, "speedup_2_workers": med["1 worker"] / med["2 workers"],
           "speedup_dask": med["1 worker"] / med["dask, 2 workers"],
           "speedup_plain_pool": med["1 worker, plain pool"] / med["2 workers, plain pool"],
           "identical_tables": identical,
           "table": tables["1 worker"].drop(columns="speed").to_dict("records")}
    parallel_figure(row)
    return row


GOAL_SPEEDUP = 1.8  # issue #29: 2 workers >= 1.8x faster than 1 on the same machine, same run
GOAL_CONTINUATION = 0.005  # issue #16: the continuation's optima within +-0.5 % of the cold starts'


def parallel_figure(row: dict) -> None:
    """Median wall time per executor, with the 2-worker goal (1 worker's time / `GOAL_SPEEDUP`)."""
    med = row["median_s"]
    fig, ax = plt.subplots(figsize=(6.6, 3.6))
    ax.barh(list(med), list(med.values()), color=[f"C{i}" for i in range(len(med))])
    for i, (label, v) in enumerate(med.items()):
        one = med["1 worker, plain pool"] if label.endswith("plain pool") else med["1 worker"]
        ax.text(v, i, f" {v:.1f} s (x{one / v:.2f})", va="center", fontsize=8)
    goal = med["1 worker"] / GOAL_SPEEDUP
    ax.axvline(goal, color="tab:red", ls="--", lw=0.8)
    ax.text(goal, 1.0, f"goal for 2 workers: ≥ {GOAL_SPEEDUP:g}× ({goal:.1f} s)", transform=ax.get_xaxis_transform(),
            color="tab:red", fontsize=7, ha="center", va="bottom")
    ax.set_xlim(0, 1.3 * max(med.values()))
    ax.set_xlabel(f"wall time of 8 periodic simulations, s (median of {row['repeat']})")
    ax.set_title(f"pressocp.sweep on {row.get('cpus', os.cpu_count())} cores, {row.get('date', '')}\n"
                 "'1 worker', '2 workers': the package's pool; each against 1 worker of its own kind\n", fontsize=8)
    fig.tight_layout()
    save(fig, OUT / "sweep_parallel.png")


def continuation(rates: list[float], ram_speed: float | None = None, side_by_side: bool = False) -> dict:
    scenario = po.Scenario.load("press75")
    if ram_speed is not None:
        scenario = scenario.with_overrides({"problem.ram_speed": ram_speed})
    name = continuation_name(ram_speed)
    path = [{"problem.stroke_rate_spm": r} for r in rates]

    def run(vary, label: str) -> tuple[float, pd.DataFrame]:
        with spawn_pool(1) as pool:
            return timed(lambda: po.sweep(scenario, vary, "optimize", executor=pool, progress=not side_by_side,
                                          csv=OUT / f"{name}_{label}.csv"))

    jobs = ((path, "warm"), ({"problem.stroke_rate_spm": rates}, "cold"))
    if side_by_side:
        with ThreadPoolExecutor(2) as threads:
            (dt_warm, warm), (dt_cold, cold) = threads.map(lambda job: run(*job), jobs)
    else:
        (dt_warm, warm), (dt_cold, cold) = (run(*job) for job in jobs)
    cols = ["problem.stroke_rate_spm", "ok", "peak_torque_N_m", "rigid_peak_torque_N_m", "wall_time_s", "status"]
    run = machine()
    row = {"case": "continuation", **run, "ram_speed_m_s": scenario.problem.ram_speed,
           "side_by_side": side_by_side, "total_s": {"path (warm)": dt_warm, "cold": dt_cold},
           "warm": warm[cols].to_dict("records"), "cold": cold[cols].to_dict("records"),
           "relative_difference": (warm["peak_torque_N_m"] / cold["peak_torque_N_m"] - 1).tolist()}
    continuation_figure(warm, cold, name, scenario.problem.ram_speed, run)
    return row


def continuation_name(ram_speed: float | None) -> str:
    """File stem of a continuation run: the scenario's ram speed has none, another says it."""
    return "sweep_continuation" if ram_speed is None else f"sweep_continuation_ram{abs(ram_speed):g}"


def continuation_figure(warm: pd.DataFrame, cold: pd.DataFrame, name: str, ram_speed: float, *runs: dict) -> None:
    """Optimal peak torque, the path's difference to the cold starts (with the ±0.5 % goal) and time
    per point along the path, warm against cold; `runs`: the stamps of the runs the tables come from."""
    fig, axes = plt.subplots(3, 1, figsize=(6, 7), sharex=True, gridspec_kw={"height_ratios": (1.2, 0.8, 1)})
    axes = [axes[0], axes[2], axes[1]]  # torque, time, difference (drawn between them)
    for table, label, style in ((cold, "cold start", "o-"), (warm, "continuation", "x--")):
        axes[0].plot(table["problem.stroke_rate_spm"], table["peak_torque_N_m"], style, label=label)
        axes[1].plot(table["problem.stroke_rate_spm"], table["wall_time_s"], style, label=label)
        bad = table[~table["ok"].astype(bool)]
        axes[0].plot(bad["problem.stroke_rate_spm"], bad["peak_torque_N_m"], "s", mfc="none", ms=11, color="C3",
                     label=f"{label}: not converged" if len(bad) else None)
    axes[0].plot(cold["problem.stroke_rate_spm"], cold["rigid_peak_torque_N_m"], ":", color="0.5", label="rigid floor")
    key = "problem.stroke_rate_spm"
    both = warm.merge(cold, on=key, suffixes=("_warm", "_cold")).sort_values(key)
    diff = 100 * (both["peak_torque_N_m_warm"] / both["peak_torque_N_m_cold"] - 1)
    dx = axes[2]
    dx.plot(both[key], diff, "x--", color="C1")
    bad = ~(both["ok_warm"].astype(bool) & both["ok_cold"].astype(bool))
    dx.plot(both[key][bad], diff[bad], "s", mfc="none", ms=11, color="C3")
    for v in (-100 * GOAL_CONTINUATION, 100 * GOAL_CONTINUATION):
        dx.axhline(v, color="tab:red", ls="--", lw=0.8)
    dx.text(dx.get_xlim()[0], 100 * GOAL_CONTINUATION, f" goal: within ±{GOAL_CONTINUATION:.1%}", color="tab:red",
            fontsize=7, va="bottom")
    dx.axhline(0, color="0.5", lw=0.6)
    dx.set_yscale("symlog", linthresh=1.0)
    lo, hi = min(-2.0, 3 * float(diff.min())), max(2.0, 3 * float(diff.max()))
    dx.set_ylim(lo, hi)
    ticks = [v for v in (-100, -10, -1, -0.5, 0, 0.5, 1, 10, 100) if lo <= v <= hi]
    dx.set_yticks(ticks, [f"{v:g}" for v in ticks])
    dx.set_ylabel("path / cold − 1 [%]")
    dx.text(0.99, 0.03, "symmetric log axis: linear within ±1 %", transform=dx.transAxes, ha="right", va="bottom",
            fontsize=7, color="0.4")
    axes[0].set_ylabel("optimal peak torque [N·m]")
    axes[1].set_ylabel("time per point [s]")
    axes[1].set_xlabel("stroke rate [strokes/min]")
    axes[0].set_title(f"75 spm scenario along the stroke rate, ram at {ram_speed:g} m/s in the window", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
        if ax is not dx:  # its markers are the top panel's
            ax.legend(fontsize=8)
    fig.tight_layout()
    figure_note(fig, *runs)
    save(fig, OUT / f"{name}.png")


OPTIMA_CLEARANCES_M = (5e-5, 1e-4, 2e-4, 3e-4)
OPTIMA_RATES_SPM = (60, 75)
GOAL_OPTIMA_S = 300.0  # issue #28: the 8-optima sweep on 2 workers in <= 5 min, every row verified


#: The two ways the optima sweep runs: extra command-line arguments. "continued" is the goal's.
OPTIMA_VARIANTS = {"cold": [], "continued": ["--along", "press.wrist_pin.clearance"]}


def optima(repeat: int, cold_repeat: int | None = None) -> dict:
    """The 8-optima sweep through the command line, each run in a fresh process and output folder, the
    variants alternating: "continued" `repeat` times, "cold" `cold_repeat` times (None: `repeat`)."""
    command = [sys.executable, "-m", "pressocp", "sweep", "press75", "--quiet", "--task", "optimize", "--workers", "2",
               "--vary", "press.wrist_pin.clearance=" + ",".join(f"{c:g}" for c in OPTIMA_CLEARANCES_M),
               "--vary", "problem.stroke_rate_spm=" + ",".join(f"{r:g}" for r in OPTIMA_RATES_SPM)]
    runs: dict[str, list] = {name: [] for name in OPTIMA_VARIANTS}
    times = {"cold": repeat if cold_repeat is None else cold_repeat, "continued": repeat}
    for i in range(max(times.values())):
        for name, extra in OPTIMA_VARIANTS.items():
            if i < times[name]:
                runs[name].append(optima_run([*command, *extra]))
    variants = {name: {"command": " ".join([*command[1:], *OPTIMA_VARIANTS[name]]),
                       "median_s": statistics.median(r["wall_time_s"] for r in rs),
                       "all_verified": all(r["all_verified"] for r in rs), "runs": rs} for name, rs in runs.items()}
    goal = variants["continued"]
    row = {"case": "optima", **machine(), "command": goal["command"], "repeat": repeat, "median_s": goal["median_s"],
           "goal_s": GOAL_OPTIMA_S, "all_verified": goal["all_verified"], "runs": goal["runs"],
           "cold_over_continued": variants["cold"]["median_s"] / goal["median_s"], "variants": variants}
    optima_figure(row)
    return row


def optima_run(command: list[str]) -> dict:
    """One sweep in a fresh process and output folder: its wall time, exit status and rows."""
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        proc = subprocess.run([*command, "--out", out], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        table = pd.read_csv(Path(out) / "sweep.csv") if (Path(out) / "sweep.csv").exists() else pd.DataFrame()
    if proc.returncode != 0:
        print(proc.stdout[-2000:], proc.stderr[-4000:], sep="\n")
    cols = [c for c in ("press.wrist_pin.clearance", "problem.stroke_rate_spm", "ok", "peak_torque_N_m",
                        "wall_time_s", "start", "status", "error") if c in table]
    return {"wall_time_s": wall, "exit_status": proc.returncode,
            "all_verified": bool(len(table) == len(OPTIMA_CLEARANCES_M) * len(OPTIMA_RATES_SPM)
                                 and table["ok"].astype(bool).all()),
            "rows": table[cols].astype(object).where(table[cols].notna(), None).to_dict("records")}


def optima_figure(row: dict) -> None:
    """Each run's wall time per variant against the goal, and every row's verified peak torque per
    clearance (continued: solid, cold: dashed)."""
    variants = row.get("variants") or {"continued": {"runs": row["runs"], "median_s": row["median_s"]}}
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 3.6), gridspec_kw={"width_ratios": (1, 1.4)})
    x = 0
    for v, (name, var) in enumerate(variants.items()):
        walls = [r["wall_time_s"] for r in var["runs"]]
        xs = range(x + 1, x + len(walls) + 1)
        ax.bar(xs, walls, color=[f"C{v}" if r["all_verified"] else "C3" for r in var["runs"]],
               label=f"{name}: median {var['median_s']:.0f} s of {len(walls)}" if len(walls) > 1
               else f"{name}: {var['median_s']:.0f} s (one run)")
        for i, w in zip(xs, walls):
            ax.text(i, w, f"{w:.0f}", ha="center", va="bottom", fontsize=7)
        x += len(walls) + 1
    ax.axhline(row["goal_s"], color="tab:red", ls="--", lw=0.8)
    ax.text(x - 0.5, row["goal_s"], f"goal {row['goal_s']:.0f} s", color="tab:red", fontsize=7, va="bottom", ha="right")
    ax.set_xticks([])
    ax.set_xlabel("run (a fresh process each; red: a row not verified)")
    ax.set_ylabel("wall time of the sweep, s")
    ax.set_ylim(0, 1.25 * max(max(r["wall_time_s"] for var in variants.values() for r in var["runs"]), row["goal_s"]))
    ax.legend(fontsize=7, loc="upper right")
    n = len(OPTIMA_CLEARANCES_M) * len(OPTIMA_RATES_SPM)
    ax.set_title(f"{n} optima on 2 workers", fontsize=9)
    ref = optima_reference(variants)
    for v, (name, var) in enumerate(variants.items()):
        for k, run in enumerate(var["runs"]):
            t = pd.DataFrame(run["rows"])
            if t.empty:
                continue
            for j, (rate, g) in enumerate(t.groupby("problem.stroke_rate_spm")):
                g = g.sort_values("press.wrist_pin.clearance")
                c = g["press.wrist_pin.clearance"]
                y = g["peak_torque_N_m"] if ref is None else \
                    100 * (g["peak_torque_N_m"] / [ref[(rate, x)] for x in c] - 1)
                bad = ~g["ok"].astype(bool)
                bx.plot(1e3 * c, y, "o-" if name == "continued" else "x--", color=f"C{j}", alpha=0.6,
                        label=f"{rate:g} spm, {name}" if k == 0 else None)
                bx.plot(1e3 * c[bad], y[bad], "s", mfc="none", ms=10, color="C3",
                        label="not verified" if bad.any() else None)
    bx.set_xlabel("wrist-pin clearance [mm]")
    bx.set_ylabel("verified peak torque [N·m]" if ref is None else "verified peak torque\nagainst the cold median [%]")
    bx.set_title("every run's optima (re-simulated)" if ref is None else
                 "every run's optima (re-simulated); the cold grid's median peaks:\n"
                 + ", ".join(f"{r:g} spm {min(v for (q, _), v in ref.items() if q == r):.1f}–"
                             f"{max(v for (q, _), v in ref.items() if q == r):.1f} N·m"
                             for r in sorted({q for q, _ in ref})), fontsize=8)
    bx.grid(alpha=0.3)
    bx.legend(fontsize=7)
    fig.suptitle(f"pressocp sweep --task optimize (continued: --along press.wrist_pin.clearance), "
                 f"{row.get('date', '')[:16]}, {row.get('cpus', '')} cores", fontsize=9)
    fig.tight_layout()
    save(fig, OUT / "sweep_optima.png")


def optima_reference(variants: dict) -> dict | None:
    """The cold grid's median verified peak per (stroke rate, clearance), N·m; None without a cold run."""
    if "cold" not in variants:
        return None
    rows = pd.DataFrame([r for run in variants["cold"]["runs"] for r in run["rows"]])
    if rows.empty:
        return None
    med = rows.groupby(["problem.stroke_rate_spm", "press.wrist_pin.clearance"])["peak_torque_N_m"].median()
    return {k: float(v) for k, v in med.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("case", choices=("parallel", "continuation", "optima"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cold-repeat", type=int, default=None,
                    help="optima: runs of the cold variant (default: --repeat)")
    ap.add_argument("--replot", action="store_true", help="only redraw the figure (continuation: from its CSVs; parallel: from its JSON)")
    ap.add_argument("--rates", type=float, nargs="+", default=[60.0, 62.5, 65.0, 67.5, 70.0, 72.5, 75.0],
                    help="stroke rates of the continuation path, spm")
    ap.add_argument("--ram-speed", type=float, default=None, help="ram speed in the window, m/s (default: the scenario's)")
    ap.add_argument("--side-by-side", action="store_true", help="run the path and the cold starts at the same time")
    args = ap.parse_args()
    name = continuation_name(args.ram_speed) if args.case == "continuation" else f"sweep_{args.case}"
    if args.replot:
        if args.case in ("parallel", "optima"):
            (parallel_figure if args.case == "parallel" else optima_figure)(
                json.loads((OUT / f"sweep_{args.case}.json").read_text()))
            return
        ram = po.Scenario.load("press75").problem.ram_speed if args.ram_speed is None else args.ram_speed
        cold = pd.read_csv(OUT / f"{name}_cold.csv")
        stamped = {n: json.loads((OUT / f"{n}.json").read_text()) if (OUT / f"{n}.json").exists() else {}
                   for n in (name, f"{name}_nofallback")}  # the CSVs' runs: their JSON (stamp, tables)
        continuation_figure(pd.read_csv(OUT / f"{name}_warm.csv"), cold, name, ram, stamped[name])
        if (OUT / f"{name}_warm_nofallback.csv").exists():  # the path measured before the cold fallback,
            then = stamped[f"{name}_nofallback"]  # against that run's own cold starts when its JSON has them
            continuation_figure(pd.read_csv(OUT / f"{name}_warm_nofallback.csv"),
                                pd.DataFrame(then["cold"]) if then.get("cold") else cold, f"{name}_nofallback", ram,
                                then, *(() if then.get("cold") else (stamped[name],)))
        return
    OUT.mkdir(exist_ok=True)
    row = parallel(args.repeat) if args.case == "parallel" else optima(args.repeat, args.cold_repeat) if args.case == "optima" else \
        continuation(args.rates, args.ram_speed, args.side_by_side)
    (OUT / f"{name}.json").write_text(json.dumps(row, indent=2, default=str) + "\n")
    print(json.dumps({k: v for k, v in row.items() if k not in ("table", "warm", "cold", "runs")}, indent=2, default=str))


if __name__ == "__main__":
    main()
