"""AD sensitivities against central differences on the seed optimum, at equal accuracy (issue #29).

The peak motor torque of the 75 spm seed optimum (`tests/references/press75_optimum_speed.json`, a
min-max optimum with several rival peaks) on the default model (rigid rod, both clearances),
differentiated with respect to slider mass, wrist-pin clearance and crank-pin stiffness:

* AD: `po.sensitivities` (forward sensitivities of the periodic response) at rtol 1e-7 to 1e-10,
  twice: with its error estimate, as a user calls it by default (a second run at ten times rtol),
  and without (``error_estimate=False``);
* central differences: the periodic state of each perturbed press (one model with the parameters
  as inputs; settled cycle by cycle from the nominal periodic state), |torque| at each rival
  peak's time (the finest AD's), relative steps of `STEP`, at rtol 1e-9 to 1e-11; once on CasADi's
  CVODES (as the package simulates: the goal's comparison) and once on the compiled CVODES driver
  that integrates AD's sensitivities (`pressocp.cvodes_fsa`): the two methods on one integrator.

Both run their integrators on compiled right-hand sides (`PressModel.jit` True; `po.sensitivities`
compiles its sensitivity equations in any case). At a peak's time the difference of |torque| is the
  peak's derivative (the time moves with p, but d|torque|/dt = 0 there).

AD's engine is CVODES compiled with the model, the states and directions as one system
(`pressocp.cvodes_fsa`); the same call on CasADi's forward integrator is measured at `ENGINE_RTOL`
(``AD, no estimate, CasADi's forward integrator``), and one period by each engine (and by the driver
through CVODES's staggered sensitivity module), with and without the 11 directions, in
``engine_periods``.

Every derivative is compared with central differences at rtol `REFERENCE_RTOL`; a method's error is
its largest relative difference over parameters and rival peaks. Each timing is the median of
`--repeat` runs in this process: a repeated call's. Each method keeps what it builds with the model
it is given (AD: the parameterised model and CasADi's derivative functions; central differences:
their integrators), so the first run at each rtol includes that building (and the first AD run any
compile of its right-hand side); `times_s` lists every run. The goal compares the cheapest setting
of each method whose error is within `GOAL_ERROR`: central differences carry no error estimate, so
the ratio (``equal_accuracy.ratio``) is AD without one; ``ratio_with_estimate`` is AD with it.

    python benchmarks/bench_sensitivity_seed.py [--repeat 3] [--replot]

Writes results/sensitivity_seed.json and .png.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from dataclasses import replace
from pathlib import Path

import casadi as ca
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pressocp as po  # noqa: E402
import pressocp.cvodes_fsa as cvodes_fsa  # noqa: E402
import pressocp.sensitivity as sens  # noqa: E402
from pressocp.io import versions  # noqa: E402
from pressocp.model import OUTPUT_NAMES  # noqa: E402
from pressocp.plots import save  # noqa: E402
from pressocp.report import stamp  # noqa: E402
from pressocp.simulate import Integrator, direct_driver, integrator_dae, periodic_state  # noqa: E402
from status import figure_note  # noqa: E402 (a sibling script: this folder is the script's path)

OUT = Path(__file__).parent / "results"
SEED = Path(__file__).parent.parent / "tests" / "references" / "press75_optimum_speed.json"
PARAMETERS = ("slider_mass", "wrist_pin.clearance", "crank_pin.stiffness")
AD_RTOLS = (1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 1e-10)
CD_RTOLS = (1e-9, 3e-10, 1e-10, 1e-11)
#: The AD rows: label and whether `po.sensitivities` runs its error estimate.
AD_METHODS = (("AD", True), ("AD, no estimate", False))
#: AD without its estimate on CasADi's forward integrator, at `ENGINE_RTOL` (its first call, which builds, not
#: counted): the engine's share of AD's time.
AD_CASADI = "AD, no estimate, CasADi's forward integrator"
#: Central differences on CasADi's CVODES (as the package simulates), and on the compiled CVODES driver
#: that integrates AD's sensitivities (the same integrator as AD's).
CD_DRIVER = "central differences (AD's CVODES driver)"
CD_METHODS = (("central differences", False), (CD_DRIVER, True))
REFERENCE_RTOL = 1e-12
STEP = 1e-3  # relative
GOAL_ERROR = 0.02
GOAL_RATIO = 3.0
PERIODIC_TOL = 1e3  # x rtol, as `po.sensitivities` searches its periodic state
ALTERNATED = 7  # runs of each in `alternate`
SAMPLES = 20001  # of the nominal response in which central differences locate the peaks, as AD's


def central_differences(model: po.PressModel, speed: po.FourierSpeed, peaks: dict[str, np.ndarray],
                        rtol: float, driver: bool = False) -> dict[str, list[float]]:
    """d|torque|/dp at each parameter's rival peak times (s within the cycle): the nominal periodic
    state (sampled, below), as `po.sensitivities` finds its own, then for each parameter two
    perturbed periodic responses on `model`, which carries the parameters as inputs, each settled
    cycle by cycle from the nominal state, |torque| read at the peak times (CVODES, explicit form,
    no work quadratures). Its integrators are kept in ``model.functions`` for the next call at the
    same rtol, as `po.sensitivities` keeps its derivatives with the model it is given. With `driver`
    the perturbed cycles and the runs to the peaks go through the compiled CVODES driver that
    integrates AD's sensitivities (`pressocp.cvodes_fsa`, no directions) instead of CasADi's CVODES,
    and so does the nominal periodic state's search (``Integrator("cvodes-direct")``, as AD's): the
    two methods on the same integrator.

    The nominal periodic response is sampled (`SAMPLES`, its outputs evaluated) and its torque peaks
    located, as `po.sensitivities` locates the peaks it differentiates: a user of differences has to
    know where the peaks are, and AD's time includes finding them. The differences are still read at
    the `peaks` given (the finest AD's), so that both methods are compared at the same times; the
    located ones are returned beside them."""
    tol = PERIODIC_TOL * rtol
    nominal = po.simulate(model, speed, periodic=True, n_out=SAMPLES, work=False,
                          integrator=Integrator("cvodes-direct" if driver else "cvodes", rtol, periodic_tol=tol))
    x_nominal = nominal.states[:, 0] / model.x_scale
    located = sens.peak_times(nominal.t - nominal.t[0], nominal.torque, speed.period)
    times = np.unique(np.concatenate(list(peaks.values())))
    key = ("central_differences", rtol, tuple(times))
    if key not in model.functions:
        opts = {"reltol": rtol, "abstol": rtol, "max_num_steps": 10**8}
        dae = integrator_dae(model, True, False)  # compiled, as `po.sensitivities` runs its own
        model.functions[key] = (ca.integrator("cycle", "cvodes", dae, 0.0, speed.period, opts),
                                ca.integrator("to_peaks", "cvodes", dae, 0.0, [float(t) for t in times], opts))
    cycle, to_peaks = model.functions[key]
    if driver:
        fsa, none = direct_driver(model, False), (np.zeros((model.nx, 0)), np.zeros((0, 0)))

        def cycle(x0, p):  # noqa: F811 (the driver's period)
            return {"xf": fsa.run(x0, p, *none, np.array([speed.period]), rtol)[0]}

        def to_peaks(x0, p):  # noqa: F811 (the driver's runs to the peaks)
            return {"xf": fsa.run(x0, p, *none, times, rtol)[0]}
    k = OUTPUT_NAMES.index("torque")
    p0 = model.parameters(speed)
    out = {}
    for i, name in enumerate(PARAMETERS):
        h = STEP * model.params.value(name)
        values = []
        for sign in (1.0, -1.0):
            p = p0.copy()
            p[p0.size - len(PARAMETERS) + i] += sign * h
            x = x_nominal
            for _ in range(60):
                x_next = np.asarray(cycle(x0=x, p=p)["xf"]).ravel()
                change, x = float(np.max(np.abs(x_next - x))), x_next
                if change < tol:
                    break
            else:
                raise RuntimeError(f"{name} {sign * h:+g}: no periodic state (change per cycle {change:.2g})")
            X = np.asarray(to_peaks(x0=x, p=p)["xf"])
            torque = {float(t): abs(float(model.outputs(t, X[:, j], p)[k])) for j, t in enumerate(times)}
            values.append(np.array([torque[float(t)] for t in peaks[name]]))
        out[name] = list((values[0] - values[1]) / (2 * h))
    return out, sorted(located)


def ad_derivatives(model: po.PressModel, speed: po.FourierSpeed, rtol: float,
                   estimate: bool) -> tuple[dict, dict, float, float]:
    """`po.sensitivities` at `rtol`, with or without its error `estimate`: derivatives and error
    estimates per parameter at each rival peak (by time), the largest error estimate (inf without
    one), and the wall time."""
    s = po.sensitivities(model, speed, PARAMETERS, rtol=rtol, error_estimate=estimate)
    rows = s.per_peak.to_dict("records")
    derivs = {n: {float(r["time"]): float(r["derivative"]) for r in rows if r["parameter"] == n} for n in PARAMETERS}
    estimates = {n: max(float(r["error_estimate"]) for r in rows if r["parameter"] == n) for n in PARAMETERS}
    return derivs, estimates, max(estimates.values()), s.wall_time


def at_peaks(derivs: dict[float, float], times: np.ndarray) -> list[float]:
    """The derivatives (by peak time) at the peaks nearest `times` (each rtol locates them slightly
    differently)."""
    keys = np.array(sorted(derivs))
    return [derivs[float(keys[np.argmin(np.abs(keys - t))])] for t in times]


def largest_error(derivs: dict[str, list[float]], reference: dict[str, list[float]]) -> tuple[float, str]:
    """Largest |d / d_ref - 1| over parameters and rival peaks, and where."""
    worst, where = 0.0, ""
    for name in PARAMETERS:
        for k, (d, r) in enumerate(zip(derivs[name], reference[name])):
            e = abs(d / r - 1.0) if r != 0 else float("inf")
            if e > worst:
                worst, where = e, f"{name}, rival peak {k + 1}"
    return worst, where


ENGINE_RTOL = 3e-9  # the AD rtol at equal accuracy (2026-12-01)
ENGINE_REPEAT = 7


def engine_periods(model: po.PressModel, speed: po.FourierSpeed) -> dict:
    """One period of the seed optimum from its periodic state at `ENGINE_RTOL`, each engine alternately,
    `ENGINE_REPEAT` times: the 11 directions by the compiled CVODES driver both ways (with the states
    as one system, as `po.sensitivities` runs them, and through CVODES's staggered sensitivity
    module) and by CasADi's forward integrator, and a plain period (no directions) by the driver and
    by CasADi's CVODES; medians, the driver's steps, and the largest difference of each driver's
    directions from CasADi's (relative to their largest entry)."""
    msym = sens.sensitivity_model(model, PARAMETERS)
    pv = msym.parameters(speed)
    scale = sens.parameter_scale(pv[-len(PARAMETERS):])
    nx, nq, grid = msym.nx, len(PARAMETERS), [speed.period]
    x0 = periodic_state(model, speed, Integrator("cvodes", ENGINE_RTOL), tol=PERIODIC_TOL * ENGINE_RTOL)[0]
    fsa = sens.kept_fsa(msym, nq)
    staggered = cvodes_fsa.ForwardSensitivities.build(msym.dae(explicit=True, work=False), nq)
    plain_fsa = direct_driver(msym, False)
    plain = ca.integrator("period", "cvodes", integrator_dae(msym, True, False), 0.0, speed.period,
                          {"reltol": ENGINE_RTOL, "abstol": ENGINE_RTOL, "max_num_steps": 10**8})
    Q = np.hstack([np.zeros((nq, nx)), np.diag(scale)])
    runs = {
        "driver, 11 directions": lambda: fsa.run(x0, pv, np.eye(nx, nx + nq), Q, np.array(grid), ENGINE_RTOL),
        "driver, 11 directions, CVODES staggered": lambda: staggered.run(x0, pv, np.eye(nx, nx + nq), Q,
                                                                         np.array(grid), ENGINE_RTOL),
        "CasADi forward integrator, 11 directions": lambda: sens.casadi_forward(msym, grid, x0, pv, scale,
                                                                                 ENGINE_RTOL),
        "driver, plain": lambda: plain_fsa.run(x0, pv, np.zeros((nx, 0)), np.zeros((0, 0)), np.array(grid),
                                               ENGINE_RTOL),
        "CasADi CVODES, plain": lambda: plain(x0=x0, p=pv),
    }
    times: dict[str, list[float]] = {k: [] for k in runs}
    out = {}
    for _ in range(ENGINE_REPEAT + 1):  # the first of each builds what it keeps: not counted
        for k, run in runs.items():
            t0 = time.perf_counter()
            out[k] = run()
            times[k].append(time.perf_counter() - t0)
    S_casadi = out["CasADi forward integrator, 11 directions"][:, :, -1]
    fused, staggered = "driver, 11 directions", "driver, 11 directions, CVODES staggered"
    difference = {k: float(np.max(np.abs(out[k][1][:, :, -1] - S_casadi)) / np.max(np.abs(S_casadi)))
                  for k in (fused, staggered)}
    return {"rtol": ENGINE_RTOL, "repeat": ENGINE_REPEAT,
            "median_s": {k: float(np.median(v[1:])) for k, v in times.items()},
            "times_s": {k: v[1:] for k, v in times.items()},
            "driver_steps": {"11 directions": out[fused][2]["steps"],
                             "11 directions, CVODES staggered": out[staggered][2]["steps"],
                             "plain": out["driver, plain"][2]["steps"]},
            "directions_difference": difference[fused], "directions_difference_staggered": difference[staggered]}


def measure(repeat: int) -> dict:
    press = po.PressParams()
    speed = po.FourierSpeed.from_dict(json.loads(SEED.read_text()))
    model = replace(po.build_model(press), jit=True)  # its integrators compiled, as the differences'
    ad = {}
    for rtol in AD_RTOLS:
        for label, estimate in AD_METHODS:
            runs = [ad_derivatives(model, speed, rtol, estimate) for _ in range(repeat)]
            ad[label, rtol] = runs[-1][:3] + ([r[3] for r in runs],)
            print(f"{label} rtol {rtol:g}: {[round(r[3], 2) for r in runs]} s, largest error estimate "
                  f"{runs[-1][2]:.2g}", flush=True)
    # the same call on CasADi's forward integrator (the engine where the driver cannot be built), on a model
    # of its own (the driver is kept with the first)
    other, available = replace(po.build_model(press), jit=True), cvodes_fsa.unavailable
    cvodes_fsa.unavailable = lambda: "the benchmark's comparison"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            runs = [ad_derivatives(other, speed, ENGINE_RTOL, False) for _ in range(repeat + 1)][1:]
    finally:
        cvodes_fsa.unavailable = available
    ad[AD_CASADI, ENGINE_RTOL] = runs[-1][:3] + ([r[3] for r in runs],)
    print(f"{AD_CASADI} rtol {ENGINE_RTOL:g}: {[round(r[3], 2) for r in runs]} s", flush=True)
    finest = ad["AD", AD_RTOLS[-1]][0]
    peaks = {n: np.array(sorted(finest[n])) for n in PARAMETERS}
    cd_model = replace(po.build_model(press, parameters=PARAMETERS), jit=True)  # built once, as the AD's
    t0 = time.perf_counter()
    reference = central_differences(cd_model, speed, peaks, REFERENCE_RTOL)[0]
    ref_s = time.perf_counter() - t0
    print(f"reference (central differences, rtol {REFERENCE_RTOL:g}): {ref_s:.1f} s", flush=True)
    rows = []
    for (label, rtol), (derivs, _, estimate, times) in ad.items():
        d = {n: at_peaks(derivs[n], peaks[n]) for n in PARAMETERS}
        err, where = largest_error(d, reference)
        rows.append({"method": label, "rtol": rtol, "times_s": times, "median_s": float(np.median(times)),
                     "error": err, "worst": where, "error_estimate": estimate, "derivatives": d})
    for label, driver in CD_METHODS:
        for rtol in CD_RTOLS:
            times, d = [], None
            for _ in range(repeat):
                t0 = time.perf_counter()
                d, located = central_differences(cd_model, speed, peaks, rtol, driver)
                times.append(time.perf_counter() - t0)
            err, where = largest_error(d, reference)
            rows.append({"method": label, "rtol": rtol, "times_s": times,
                         "median_s": float(np.median(times)), "error": err, "worst": where, "derivatives": d,
                         "peaks_located_s": located})
            print(f"{label} rtol {rtol:g}: {[round(t, 2) for t in times]} s, error {err:.2g} ({where})", flush=True)
    methods = [label for label, _ in AD_METHODS] + [label for label, _ in CD_METHODS]
    best = {m: min((r for r in rows if r["method"] == m and r["error"] <= GOAL_ERROR), key=lambda r: r["median_s"],
                   default=None) for m in methods}

    def ratio(ad_label: str, cd_label: str = "central differences") -> float | None:
        cd = best[cd_label]
        return cd["median_s"] / best[ad_label]["median_s"] if best[ad_label] and cd else None

    cd10 = next(r for r in rows if r["method"] == "central differences" and r["rtol"] == 1e-10)["derivatives"]
    within = {f"{r['method']} rtol {r['rtol']:g}": largest_error(r["derivatives"], cd10)[0] for r in rows
              if r["method"] != "central differences"}
    engines = {label: po.sensitivities(model, speed, PARAMETERS, rtol=AD_RTOLS[0], error_estimate=estimate).engine
               for label, estimate in AD_METHODS}
    periods = engine_periods(model, speed)
    print(f"one period at rtol {ENGINE_RTOL:g}: {periods['median_s']}", flush=True)
    alternated = alternate(model, cd_model, speed, peaks, best["AD, no estimate"], best[CD_DRIVER])
    return {**stamp(), "versions": versions(), "case": "press75 seed optimum, default model, peak motor torque",
            "parameters": list(PARAMETERS), "peaks_s": {n: list(peaks[n]) for n in PARAMETERS}, "step": STEP,
            "reference_rtol": REFERENCE_RTOL, "reference_s": ref_s, "reference": reference, "repeat": repeat,
            "goal_error": GOAL_ERROR, "goal_ratio": GOAL_RATIO, "rows": rows,
            "equal_accuracy": {**{m: best[m] and {k: best[m][k] for k in ("rtol", "median_s", "error")}
                                  for m in methods},
                               "ratio": ratio("AD, no estimate"), "ratio_with_estimate": ratio("AD"),
                               "ratio_same_integrator": ratio("AD, no estimate", CD_DRIVER)},
            "ad_engine": engines["AD, no estimate"], "engine_periods": periods,
            "ad_against_cd_1e-10": within, "alternated": alternated}


def alternate(model: po.PressModel, cd_model: po.PressModel, speed: po.FourierSpeed, peaks: dict[str, np.ndarray],
              ad: dict | None, cd: dict | None) -> dict | None:
    """AD without its estimate and central differences on AD's driver, each at the rtol picked at equal
    accuracy, timed in turn `ALTERNATED` times: the ratio of the medians with the machine's drift
    shared (the rows above time each method's rtols in a block of their own, minutes apart)."""
    if ad is None or cd is None:
        return None
    times: dict[str, list[float]] = {"AD, no estimate": [], CD_DRIVER: []}
    for _ in range(ALTERNATED):
        times["AD, no estimate"].append(ad_derivatives(model, speed, ad["rtol"], False)[3])
        t0 = time.perf_counter()
        central_differences(cd_model, speed, peaks, cd["rtol"], True)
        times[CD_DRIVER].append(time.perf_counter() - t0)
    medians = {k: float(np.median(v)) for k, v in times.items()}
    print(f"alternated: {medians}", flush=True)
    return {"rtol": {"AD, no estimate": ad["rtol"], CD_DRIVER: cd["rtol"]}, "times_s": times, "median_s": medians,
            "ratio_same_integrator": medians[CD_DRIVER] / medians["AD, no estimate"]}


def plot(data: dict) -> plt.Figure:
    """Wall time against the largest error, each method at each rtol."""
    fig, ax = plt.subplots(figsize=(7.6, 5.0))
    for m, mark in (("AD", "o-"), ("AD, no estimate", "^-"), (AD_CASADI, "kx"), ("central differences", "s-"),
                    (CD_DRIVER, "d--")):
        rows = [r for r in data["rows"] if r["method"] == m]
        ax.semilogx([r["error"] for r in rows], [r["median_s"] for r in rows], mark, label=m)
        for r in rows:
            ax.annotate(f"{r['rtol']:g}", (r["error"], r["median_s"]), fontsize=7, xytext=(4, 3),
                        textcoords="offset points")
    ax.axvline(data["goal_error"], ls="--", color="tab:red", lw=0.8, label=f"{100 * data['goal_error']:g} % error")
    ax.set_ylim(bottom=0.0)
    eq = data["equal_accuracy"]
    ratio, with_estimate, same = eq["ratio"], eq.get("ratio_with_estimate"), eq.get("ratio_same_integrator")
    ax.set_xlabel(f"largest relative error of dJ/dp (against central differences at rtol {data['reference_rtol']:g})")
    ax.set_ylabel(f"wall time, s (median of {data['repeat']})")
    pair = (lambda r: "no pair" if r is None else f"{r:.2f} ×")
    ax.set_title(f"peak torque of the 75 spm seed optimum, 3 parameters, at equal accuracy (≤ {100 * data['goal_error']:g} %), "
                 f"{data['date']}\nAD without its estimate {pair(ratio)}, with it {pair(with_estimate)} (goal "
                 f"{data['goal_ratio']:g} ×) against central differences on CasADi's CVODES;\n{pair(same)} against "
                 f"central differences on AD's own CVODES driver (AD's engine: {data.get('ad_engine', '?')})",
                 fontsize=8)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3)
    fig.tight_layout()
    figure_note(fig, data)
    return fig


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--replot", action="store_true", help="redraw the figure from the JSON")
    args = ap.parse_args()
    path = OUT / "sensitivity_seed.json"
    data = json.loads(path.read_text()) if args.replot else measure(args.repeat)
    if not args.replot:
        path.write_text(json.dumps(data, indent=1, default=float))
    save(plot(data), OUT / "sensitivity_seed.png")


if __name__ == "__main__":
    main()
