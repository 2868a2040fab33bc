"""Work against precision of every integrator `simulate` offers, on the clearance model and the
flexible rod (2 / 4 / 8 elements), in a smooth and an impacting scene (issue #17, item 1).

Scenes (the default press, both clearances, T = 0.8 s):

* ``smooth``: constant crank speed; the journals rest on their walls (no impact).
* ``impacting``: the kinematic design of the 75 spm problem (the rod goes into compression and the
  journals hit).

One cycle from the same start per model and scene: the periodic state of the rigid-rod clearance
model (`periodic_state`, CVODES rtol 1e-9); for the flexible rod, those journal states with no
elastic deformation, then one warm-up cycle (as `bench_simulation.py`). The reference is CVODES at
rtol 1e-11 from the same start (``--reference-method`` cvodes / idas / scipy-radau and
``--reference-rtol`` set another; every row records its ``reference_method``, ``reference_rtol`` and the
reference's wall time, and the figure names a panel's reference when it is not CVODES 1e-11).
``--reference-check METHOD RTOL`` runs a second, independent reference and records in every row of the
pair how far its torque is from the reference's (``reference_check``: peak and RMS difference, relative,
as the errors below), so that a reference's own error can be told from the errors it measures.
``--reference-timeout`` S runs the reference (and the check) in a child process and stops it after S s:
the pair then gets one row, method ``reference``, not ok, with how long it ran, and no method is run on
it. Rows are kept per (scene, model, reference method, reference rtol).

Why not always CVODES 1e-11: on the 8-element rod its steps collapse to about 2e-8 s (1e7 and more
per cycle; `docs/measurements.md` says why), so that pair (smooth scene) is run with
``--reference-rtol 1e-10 --reference-check scipy-radau 1e-10``.

Methods: IDAS and CVODES (rtol 1e-4 ... 1e-8), scipy Radau and BDF (1e-4, 1e-6), CasADi's fixed-step
``rk`` (RK4) and ``collocation`` (Radau, 3 points) at N steps per cycle. A fixed-step run's outputs are
its step points (``n_out = N + 1``: CasADi puts at least one step in each output interval), so its
peak is sampled there. RK4 is run only where its step is within its stability bound
(`bench_stability.py`: 105 µs for the rigid rod, 9.7 µs for the 2-element rod, less with more
elements); an N that would need more than `MAX_RK_STEPS` steps is recorded as skipped.

Errors against the reference: the peak motor torque (relative), and a time-series norm, the RMS of the
torque difference at the run's output times (the reference interpolated from its 16001 samples)
over the reference torque's RMS. Work: wall time (a warm-up run, then the median of 3 when a run
takes under `REPEAT_BELOW` s, else that one run) and right-hand-side evaluations (CVODES ``nfevals``,
IDAS residual evaluations ``nresevals``, scipy ``nfev``; RK4: 4 N; CasADi's collocation does not
report its Newton iterations, so none). A method's tighter tolerances are skipped once one of its
runs exceeds `BUDGET` s.

    python benchmarks/bench_work_precision.py [--models clearance flexible-2 ...] [--scenes smooth impacting]
        [--reference-method cvodes] [--reference-rtol 1e-11] [--reference-check METHOD RTOL]
        [--reference-timeout S] [--replot]

Writes results/work_precision.json and work_precision.png.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import statistics
import textwrap
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import NullFormatter

from pressocp import FourierSpeed, PressParams, SpeedProblem, build_model, design_speed, simulate
from pressocp.io import versions
from pressocp.plots import save
from pressocp.report import stamp
from pressocp.simulate import Integrator, SimulationError, periodic_state

from bench_simulation import flexible_start  # noqa: E402  (a sibling script: this folder is the script's path)

OUT = Path(__file__).parent / "results"
T = 0.8
REF_RTOL = 1e-11
REF_METHOD = "cvodes"
#: Integrators a reference (or its check) may use: adaptive, with a relative tolerance.
REF_METHODS = ("cvodes", "idas", "scipy-radau")
#: Printed names of the methods in titles.
NAMES = {"cvodes": "CVODES", "idas": "IDAS", "scipy-radau": "scipy Radau", "scipy-bdf": "scipy BDF"}
REF_SAMPLES = 16001
#: Goals: IDAS this many times faster than scipy Radau at equal accuracy, and one cycle of the
#: 4-element rod within this many seconds.
GOAL_RADAU_RATIO = 20.0
GOAL_CYCLE_S, GOAL_CYCLE_MODEL = 1.0, "flexible-4"
ADAPTIVE = {"idas": (1e-4, 1e-6, 1e-8), "cvodes": (1e-4, 1e-6, 1e-8), "scipy-radau": (1e-4, 1e-6),
            "scipy-bdf": (1e-4, 1e-6)}
FIXED = {"rk": (8000, 16000, 32000, 128000), "collocation": (400, 1600, 6400)}
MAX_RK_STEPS = 200_000
REPEAT_BELOW = 10.0
BUDGET = 300.0
#: RK4 stability bounds measured by bench_stability.py (s), by model.
RK_BOUND = {"clearance": 105e-6, "flexible-2": 9.68e-6, "flexible-4": 0.78e-6, "flexible-8": 0.2e-6}


def model_of(name: str, press: PressParams):
    return build_model(press) if name == "clearance" else build_model(press, "flexible", n_elements=int(name[-1]))


def start_of(model, speed) -> np.ndarray:
    return periodic_state(model, speed, integrator=Integrator(method="cvodes", rtol=1e-9))[0] if model.rod == "rigid" else flexible_start(model, speed)


def timed(run) -> tuple:
    """(result, wall times): a warm-up run, then the median of 3 when it took under `REPEAT_BELOW` s."""
    t0 = time.perf_counter()
    r = run()
    first = time.perf_counter() - t0
    if first >= REPEAT_BELOW:
        return r, [first]
    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        r = run()
        times.append(time.perf_counter() - t0)
    return r, times


def errors(sim, ref) -> tuple[float, float]:
    """(peak-torque error, time-series RMS error) of `sim` against `ref` (relative)."""
    peak = abs(sim.peak("torque") / ref.peak("torque") - 1)
    at = np.interp(sim.t, ref.t, ref.torque)
    rms = float(np.sqrt(np.mean((sim.torque - at) ** 2)) / np.sqrt(np.mean(ref.torque**2)))
    return float(peak), rms


def runs_of(model_name: str) -> list[tuple[str, float | int]]:
    out = [(m, tol) for m, tols in ADAPTIVE.items() for tol in tols]
    out += [("collocation", n) for n in FIXED["collocation"]]
    out += [("rk", n) for n in FIXED["rk"]]
    return out


def key(row: dict) -> tuple[str, str, str, float]:
    """(scene, model, reference method, reference rtol) of a row; rows written before rows recorded them
    used `REF_METHOD` and `REF_RTOL`."""
    return row["scene"], row["model"], row.get("reference_method", REF_METHOD), row.get("reference_rtol", REF_RTOL)


def write(data: dict, path: Path) -> None:
    """Write `data`, keeping the rows of (scene, model, reference method, reference rtol) it does not hold
    from the file."""
    rows = data["rows"]
    if path.exists():
        done = {key(r) for r in rows}
        old = json.loads(path.read_text())["rows"]
        rows = [{**r, "reference_method": key(r)[2], "reference_rtol": key(r)[3]} for r in old
                if key(r) not in done] + rows
    path.write_text(json.dumps({**data, "rows": rows}, indent=1, default=float))


def _run_reference(model, speed, x0: np.ndarray, method: str, rtol: float) -> tuple:
    """(SimResult, wall time s) of one reference run of one cycle, `REF_SAMPLES` outputs."""
    t0 = time.perf_counter()
    sim = simulate(model, speed, x0=x0, integrator=Integrator(method=method, rtol=rtol), n_out=REF_SAMPLES)
    return sim, time.perf_counter() - t0


def _reference_child(conn, model, speed, x0: np.ndarray, runs: list[tuple[str, float]]) -> None:
    """Child process of `reference`: sends ("ok", [(SimResult, wall s), ...]) or ("error", first line of the
    message)."""
    try:
        conn.send(("ok", [_run_reference(model, speed, x0, m, r) for m, r in runs]))
    except SimulationError as err:
        conn.send(("error", str(err).splitlines()[0]))
    finally:
        conn.close()


def reference(model, speed, x0: np.ndarray, runs: list[tuple[str, float]], timeout: float | None) -> tuple:
    """The reference run of one cycle, and its check when `runs` holds two.

    Parameters
    ----------
    model : PressModel
        The model.
    speed : FourierSpeed
        The crank speed of the scene.
    x0 : ndarray
        Scaled start state.
    runs : list of (str, float)
        (method, rtol) of the reference, then of the check if any; the absolute tolerance (scaled
        states) is the rtol.
    timeout : float or None
        Wall-time limit of all the runs together, s. None: run in this process, no limit; else in a
        forked child, killed after `timeout` s.

    Returns
    -------
    tuple
        (list of (SimResult, wall time s) per run, or None; wall time of all, s; None or why there is no
        result).
    """
    t0 = time.perf_counter()
    what = " and its check" if len(runs) > 1 else ""
    if timeout is None:
        try:
            out = [_run_reference(model, speed, x0, m, r) for m, r in runs]
        except SimulationError as err:
            return None, time.perf_counter() - t0, str(err).splitlines()[0]
        return out, time.perf_counter() - t0, None
    ctx = mp.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_reference_child, args=(send, model, speed, x0, runs), daemon=True)
    child.start()
    send.close()
    try:
        if recv.poll(timeout):
            try:
                status, out = recv.recv()
            except EOFError:
                status, out = "error", f"the reference process ended without a result (exit code {child.exitcode})"
            wall = time.perf_counter() - t0
            return (out, wall, None) if status == "ok" else (None, wall, out)
        wall = time.perf_counter() - t0
        method, rtol = runs[0]
        return None, wall, (f"{NAMES[method]} rtol {rtol:g} reference{what} stopped unfinished after {wall:.0f} s "
                            f"(limit {timeout:g} s)")
    finally:
        if child.is_alive():
            child.kill()
        child.join()
        recv.close()


def measure(model_names: list[str], scene_names: list[str], path: Path, ref_rtol: float = REF_RTOL,
            ref_timeout: float | None = None, ref_method: str = REF_METHOD,
            ref_check: tuple[str, float] | None = None) -> dict:
    """Every run; the JSON is written after each run, so a stopped run keeps what it did (a pair stopped
    part-way has rows only for the runs it finished).

    Parameters
    ----------
    model_names, scene_names : list of str
        The pairs to measure.
    path : Path
        The JSON to merge into.
    ref_rtol : float
        rtol of the reference.
    ref_timeout : float or None
        Wall-time limit of the reference and its check, s (see `reference`).
    ref_method : str
        Integrator of the reference, one of `REF_METHODS`.
    ref_check : (str, float) or None
        (method, rtol) of a second reference run; its peak and RMS torque differences from the reference
        are recorded in every row of the pair as ``reference_check``.
    """
    press = PressParams()
    speeds = {"smooth": FourierSpeed.constant(T),
              "impacting": design_speed(SpeedProblem(press, period=T, ram_speed=-0.1)).speed}
    rows = []
    meta = {**stamp(), "versions": versions(), "period_s": T, "reference_method": REF_METHOD,
            "reference_rtol": REF_RTOL}
    runs = [(ref_method, ref_rtol)] + ([tuple(ref_check)] if ref_check else [])
    refname = f"{NAMES[ref_method]} rtol {ref_rtol:g}"
    for scene in scene_names:
        speed = speeds[scene]
        for mname in model_names:
            model = model_of(mname, press)
            t0 = time.perf_counter()
            x0 = start_of(model, speed)
            t1 = time.perf_counter()
            done, all_wall, why = reference(model, speed, x0, runs, ref_timeout)
            if done is None:
                print(f"{scene} / {mname}: start {t1 - t0:.1f} s, no reference ({why})", flush=True)
                rows.append({"scene": scene, "model": mname, "method": "reference", "nx": model.nx,
                             "reference_method": ref_method, "reference_rtol": ref_rtol, "ok": False, "error": why,
                             "reference_wall_time_s": all_wall})
                write({**meta, "rows": rows}, path)
                continue
            (ref, ref_wall), check = done[0], None
            print(f"{scene} / {mname}: start {t1 - t0:.1f} s, reference ({refname}) {ref_wall:.1f} s, "
                  f"peak {ref.peak('torque'):.4f} N m", flush=True)
            if len(done) > 1:
                (csim, cwall), (cmethod, crtol) = done[1], runs[1]
                cpeak, crms = errors(csim, ref)
                check = {"method": cmethod, "rtol": crtol, "wall_time_s": cwall, "peak_torque": csim.peak("torque"),
                         "peak_torque_difference": cpeak, "rms_torque_difference": crms,
                         "steps": csim.stats.get("steps")}
                print(f"  check ({NAMES[cmethod]} rtol {crtol:g}) {cwall:.1f} s: peak {cpeak:.1e}, RMS {crms:.1e} from "
                      f"the reference", flush=True)
            over = set()
            for method, setting in runs_of(mname):
                write({**meta, "rows": rows}, path)  # every finished row, before the next run
                row = {"scene": scene, "model": mname, "method": method, "nx": model.nx,
                       "reference_peak_torque": ref.peak("torque"), "reference_method": ref_method,
                       "reference_rtol": ref_rtol, "reference_wall_time_s": ref_wall,
                       "reference_steps": ref.stats.get("steps")}
                if check:
                    row["reference_check"] = check
                if method in ("rk", "collocation"):
                    row["steps_per_cycle"] = setting
                    row["step_s"] = T / setting
                    kwargs = {"integrator": Integrator(method, step=T / setting), "n_out": setting + 1}
                else:
                    row["rtol"] = setting
                    kwargs = {"integrator": Integrator(method, setting), "n_out": REF_SAMPLES}
                if method in over:
                    rows.append({**row, "ok": False, "skipped": f"a looser setting took over {BUDGET:g} s"})
                    continue
                if method == "rk" and (T / setting > RK_BOUND[mname] or setting > MAX_RK_STEPS):
                    why = ("step above the RK4 stability bound" if T / setting > RK_BOUND[mname]
                           else f"more than {MAX_RK_STEPS} steps")
                    rows.append({**row, "ok": False, "skipped": why})
                    continue
                try:
                    sim, times = timed(lambda: simulate(model, speed, x0=x0, **kwargs))
                except SimulationError as err:
                    rows.append({**row, "ok": False, "error": str(err).splitlines()[0]})
                    print(f"  {method} {setting}: failed ({str(err).splitlines()[0]})", flush=True)
                    continue
                peak, rms = errors(sim, ref)
                rhs = sim.stats.get("rhs_evaluations")
                if method == "rk":
                    rhs = 4 * setting
                row.update(ok=bool(np.isfinite(peak)), wall_time_s=statistics.median(times), repeats=len(times),
                           peak_torque_error=peak, rms_torque_error=rms, rhs_evaluations=rhs,
                           steps=sim.stats.get("steps"))
                rows.append(row)
                print(f"  {method} {setting}: {row['wall_time_s']:.2f} s, peak error {peak:.1e}, RMS error {rms:.1e}, "
                      f"RHS {rhs}", flush=True)
                if row["wall_time_s"] > BUDGET:
                    over.add(method)
            write({**meta, "rows": rows}, path)
    return {**meta, "rows": rows}


def plot(data: dict) -> plt.Figure:
    """Error against wall time per (scene, model, reference method, reference rtol): for each scene a row
    of peak-torque panels over a row of RMS panels, one column per model (rigid-rod clearance model
    first). A panel whose reference is not the default names it in its title, with its check's
    differences when there was one. A pair without a reference (method ``reference`` not ok) gets the
    reason instead of curves."""
    every = data["rows"]
    default = data.get("reference_rtol", REF_RTOL)
    default_method = data.get("reference_method", REF_METHOD)

    def ref_of(r: dict) -> tuple[str, float]:
        return r.get("reference_method", default_method), r.get("reference_rtol", default)

    scenes = sorted({r["scene"] for r in every}, key=lambda s: s != "smooth")
    order = ["clearance", "flexible-2", "flexible-4", "flexible-8"]
    panels = {s: sorted({(r["model"], *ref_of(r)) for r in every if r["scene"] == s},
                        key=lambda k: (order.index(k[0]), k[1] != default_method, -k[2])) for s in scenes}
    ncol = max((len(p) for p in panels.values()), default=1)
    fig, axes = plt.subplots(2 * len(scenes), ncol, figsize=(4.2 * ncol, 3.75 * 2 * len(scenes)), squeeze=False)
    methods = ["idas", "cvodes", "scipy-radau", "scipy-bdf", "rk", "collocation"]
    marks = dict(zip(methods, "os^vDx"))
    for i0, scene in enumerate(scenes):
        for j in range(len(panels[scene]), ncol):
            axes[2 * i0, j].axis("off")
            axes[2 * i0 + 1, j].axis("off")
        for j, (mname, rmethod, rtol) in enumerate(panels[scene]):
            mine = [r for r in every if r["scene"] == scene and r["model"] == mname and ref_of(r) == (rmethod, rtol)]
            for method in methods:
                pts = sorted(((r["wall_time_s"], r["peak_torque_error"], r["rms_torque_error"]) for r in mine
                              if r.get("ok") and r["method"] == method))
                if not pts:
                    continue
                x, yp, yr = (np.array(v) for v in zip(*pts))
                style = {"marker": marks[method], "color": f"C{methods.index(method)}", "label": method}
                axes[2 * i0, j].loglog(x, np.maximum(yp, 1e-12), **style)
                axes[2 * i0 + 1, j].loglog(x, np.maximum(yr, 1e-12), **style)
                if method == "scipy-radau":  # goal: IDAS 20x faster than scipy Radau at equal accuracy
                    goal = {"color": style["color"], "ls": ":", "lw": 1, "label": "goal: Radau's time / 20"}
                    axes[2 * i0, j].loglog(x / GOAL_RADAU_RATIO, np.maximum(yp, 1e-12), **goal)
                    axes[2 * i0 + 1, j].loglog(x / GOAL_RADAU_RATIO, np.maximum(yr, 1e-12), **goal)
            title = f"{scene}, {mname}"
            if (rmethod, rtol) != (default_method, default):
                title += f"\nreference {NAMES.get(rmethod, rmethod)} rtol {rtol:g}"
            check = next((r["reference_check"] for r in mine if r.get("reference_check")), None)
            if check:
                title += (f"; check {NAMES.get(check['method'], check['method'])} {check['rtol']:g}: "
                          f"{check['peak_torque_difference']:.0e} / {check['rms_torque_difference']:.0e}")
            failed = [r for r in mine if r["method"] == "reference" and not r.get("ok")]
            if failed:
                for i in range(2):
                    ax = axes[2 * i0 + i, j]
                    ax.set_xticks([])
                    ax.set_yticks([])
                    ax.set_title(title, fontsize=9)
                    ax.text(0.5, 0.5, textwrap.fill("no reference: " + failed[-1]["error"], 40), ha="center",
                            va="center", fontsize=8, transform=ax.transAxes)
                continue
            for i, what in enumerate(("peak-torque error", "RMS torque error")):
                ax = axes[2 * i0 + i, j]
                ax.axhline(1e-3, color="k", ls="--", lw=0.8, label="error 1e-3")
                if mname == GOAL_CYCLE_MODEL:
                    ax.axvline(GOAL_CYCLE_S, color="tab:red", ls="--", lw=0.8, label="goal: 1 s per cycle")
                ax.set_title(title, fontsize=9)
                ax.set_ylabel(f"{what} (relative)")
                ax.set_xlabel("wall time of one cycle, s")
                ax.grid(alpha=0.3, which="both")
                ax.xaxis.set_minor_formatter(NullFormatter())
            dead = [m for m in methods if any(r["method"] == m and r.get("error") for r in mine)
                    and not any(r["method"] == m and r.get("ok") for r in mine)]
            if dead:  # methods that ran and failed at every setting leave no curve: say so
                axes[2 * i0 + 1, j].text(0.02, 0.02, "failed at every setting: " + ", ".join(dead), fontsize=7,
                                         transform=axes[2 * i0 + 1, j].transAxes, va="bottom")
    fig.suptitle(f"Work against precision, T = {data['period_s']} s, "
                 f"reference {NAMES.get(default_method, default_method)} "
                 f"rtol {default:g} unless a panel says otherwise (check: peak / RMS difference of a second "
                 f"reference) ({data['date'][:10]}, {data['cpus']} CPUs)", fontsize=10, y=0.997)
    # one legend for every panel, under the title (per-panel legends covered points)
    handles: dict = {}
    for ax in axes.flat:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    fig.legend(handles.values(), handles.keys(), loc="upper center", ncol=len(handles), fontsize=9,
               bbox_to_anchor=(0.5, 0.985), frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 0.965))
    return fig


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", nargs="+", default=["clearance", "flexible-2", "flexible-4", "flexible-8"],
                    choices=["clearance", "flexible-2", "flexible-4", "flexible-8"])
    ap.add_argument("--scenes", nargs="+", default=["smooth", "impacting"], choices=["smooth", "impacting"])
    ap.add_argument("--reference-method", default=REF_METHOD, choices=REF_METHODS,
                    help=f"integrator of the reference (default {REF_METHOD}); rows record it")
    ap.add_argument("--reference-rtol", type=float, default=REF_RTOL,
                    help=f"rtol of the reference (default {REF_RTOL:g}); rows record it")
    ap.add_argument("--reference-check", nargs=2, metavar=("METHOD", "RTOL"), default=None,
                    help=f"a second reference ({', '.join(REF_METHODS)}) whose torque differences from the "
                         "reference every row records as reference_check")
    ap.add_argument("--reference-timeout", type=float, default=None,
                    help="stop the reference (and its check) after this many s (wall) and record that; "
                         "default no limit")
    ap.add_argument("--replot", action="store_true", help="redraw the figure from the JSON")
    a = ap.parse_args()
    OUT.mkdir(exist_ok=True)
    path = OUT / "work_precision.json"
    if a.replot:
        data = json.loads(path.read_text())
    else:
        check = None
        if a.reference_check:
            if a.reference_check[0] not in REF_METHODS:
                ap.error(f"--reference-check METHOD must be one of {', '.join(REF_METHODS)}")
            check = (a.reference_check[0], float(a.reference_check[1]))
        measure(a.models, a.scenes, path, a.reference_rtol, a.reference_timeout, a.reference_method, check)
        data = json.loads(path.read_text())
    save(plot(data), OUT / "work_precision.png")


if __name__ == "__main__":
    main()
