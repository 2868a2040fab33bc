"""The flexible rod reduced to a few bending modes against the element rod it comes from.

    python benchmarks/bench_modal_rod.py [--repeat 1] [--elements 8] [--rtol 1e-7] [--t-end 0.2] [--method idas] [--interpreted]

Four scenes, compiled IDAS, 4 001 output samples a cycle, no work quadratures: three periodic ones
and a transient.

The periodic scenes: the 75 spm seed optimum (`tests/references/press75_optimum_speed.json`), the
cycle a user verifies, whose crank pin barely leaves its wall; the kinematic design at 69 spm
(period 0.87 s, -0.1 m/s over h/H 0.7 -> 0.3), whose journals leave their walls some 20 times a
cycle and hit them again at 20-40 mm/s, and which has an attracting periodic orbit (its peak torque
repeats to 1e-7 from cycle to cycle; at 75 spm the same design's per-cycle peaks wander by 5 % on
the flexible rods, docs/decisions/2026-11-27-periodic-yardstick.md), both with both clearances. Every level (the rigid rod,
the 4- and ``--elements``-element rods, 1-3 modes of the latter) is brought to its periodic state
(IDAS rtol 1e-9, the search timed), then one cycle from that state is timed at rtol 1e-5, 1e-6 and
1e-7 (median of ``--repeat``, at least 3). Errors are against the ``--elements`` rod's periodic
cycle at rtol 1e-10 (the full element rod). The contact losses per cycle and the journals' radial
speed as they reach the wall again are recorded. The third is the bundled slender-rod scene
(Simeon's rod at 100 rad/s, ideal joints) driven by its kinematic design: there the rod's first mode
lies within the loads' harmonics, which is where `recommend_model` asks for the flexible rod (its
levels: the 4-element rod and 1-3 modes of the ``--elements`` rod; it says how many modes that level
names, `pressocp.recommend.REDUCED_ROD`).

The transient scene: the default press at 75 spm driven by its kinematic design (-0.1 m/s over h/H 0.7 -> 0.3),
whose rod force reverses: both journals cross their clearances and hit. ``--t-end`` seconds from
rest (journals centred, rod undeformed; 0.8 s is one cycle), ``--method`` (IDAS) at ``--rtol``,
compiled (``model.jit``; ``--interpreted`` for CasADi's virtual machine), 4 001 output samples, no
work quadratures. Each model level is timed `--repeat` times (integrator construction
included: 0.02-0.3 s); its peak torque and pin forces are compared with the ``--elements`` rod at the same tolerance (the
reference: at rtol 1e-8 and 1e-9 its 0.2 s took over 5 min, and a transient with impacts differs by
about 1 % between equivalent models, docs/decisions/2026-11-26-reduced-rod.md). The levels: the rigid
rod (for scale), the 4-element rod, and the ``--elements`` rod reduced to 1, 2 and 3 modes. Simeon's slider crank (shared/reference/benchmarks.md section 1) is run on
the same rods: the slider position and velocity and the midspan deflection at 0.1 s against the
reference values. Writes ``results/modal_rod.json`` and ``results/modal_rod.png`` with the date and
machine.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import numpy as np

from pressocp import PressParams, Scenario, SpeedProblem, design_speed
from pressocp.journals import contact_losses
from pressocp.model import ModelSpec
from pressocp.report import stamp
from pressocp.simulate import Integrator, periodic_state, simulate
from pressocp.speed import FourierSpeed
from pressocp.studies import SIMEON_REFERENCE, simeon_crank
from status import figure_note  # a sibling script: this folder is the script's path

OUT = Path(__file__).parent / "results"
PEAKS = ("torque", "crank_pin_force", "wrist_pin_force")
SEED = Path(__file__).parent.parent / "tests" / "references" / "press75_optimum_speed.json"
#: The impacting periodic scene's cycle, s (69 spm): see the module docstring.
IMPACTING_PERIOD = 0.87
#: The periodic scenes: the periodic search's and the reference cycle's rtol, and the timed ones.
PERIODIC_RTOL, REFERENCE_RTOL, TIMED_RTOLS = 1e-9, 1e-10, (1e-5, 1e-6, 1e-7)
#: The figure's log axes draw an error below this at it (and say so).
ERROR_FLOOR = 1e-9
#: Goals of the fast-simulation issue: one impact cycle under 1 s with the peak torque within 1e-3 of
#: the full element rod; Simeon within 1 %; the 8-element rod within 2 % on the impacting scene.
GOAL_CYCLE_S, GOAL_PEAK, GOAL_SIMEON, GOAL_ELEMENTS = 1.0, 1e-3, 0.01, 0.02


def levels(elements: int) -> list[ModelSpec]:
    return [ModelSpec("rigid"), ModelSpec("flexible", n_elements=4),
            *(ModelSpec("flexible", n_elements=elements, n_modes=m) for m in (1, 2, 3))]


def cycle(spec: ModelSpec, rtol: float, repeat: int, t_end: float, method: str = "idas", jit: bool = True) -> dict:
    """`t_end` seconds from rest of the impacting design on `spec` with `method`, compiled (`jit`, the
    compile timed apart by a short first run) or interpreted: times, steps, peaks."""
    problem = SpeedProblem(PressParams(), period=0.8, ram_speed=-0.1)
    speed = design_speed(problem).speed
    model = spec.build(problem.press, problem.n_harmonics)
    model.jit = jit
    t0 = time.perf_counter()
    simulate(model, speed, t_end=1e-3, integrator=Integrator(method=method, rtol=rtol), n_out=3, work=False)
    compile_s = time.perf_counter() - t0

    def once():
        t0 = time.perf_counter()
        sim = simulate(model, speed, t_end=t_end, integrator=Integrator(method=method, rtol=rtol), n_out=4001, work=False)
        return time.perf_counter() - t0, sim

    runs = [once() for _ in range(repeat)]
    sim = runs[-1][1]
    return {"model": spec.describe(), "spec": spec.to_dict(), "states": model.nx, "rtol": rtol, "t_end": t_end,
            "method": method, "jit": jit, "compile_s": compile_s if jit else None,
            "times_s": [r[0] for r in runs], "median_s": statistics.median(r[0] for r in runs),
            "steps": sim.stats.get("steps"), "peaks": {n: sim.peak(n) for n in PEAKS}}


def impacts(sim, press: PressParams, joints: tuple[str, ...] = ("crank_pin", "wrist_pin")) -> dict:
    """Per clearance joint of `joints`: how often it leaves its bearing wall in the cycle, and its largest
    radial speed (m/s) as it reaches the wall again (`pressocp.journals.contact_losses`)."""
    return {j: {"losses": c.losses, "return_speed_m_s": c.return_speed}
            for j, c in contact_losses(sim, press, joints).items()}


def periodic_scene(spec: ModelSpec, speed, repeat: int, press: PressParams) -> dict:
    """`spec` of `press` on `speed`: its periodic state at `PERIODIC_RTOL` (the search timed), its cycle
    from there at `REFERENCE_RTOL` (peaks, impacts) and at each of `TIMED_RTOLS` (median of `repeat`,
    peaks)."""
    model = spec.build(press, speed.a.size)
    model.jit = True
    simulate(model, speed, t_end=1e-3, integrator=Integrator("idas", rtol=1e-6), n_out=3, work=False)  # compile
    t0 = time.perf_counter()
    x0, info = periodic_state(model, speed, Integrator("idas", rtol=PERIODIC_RTOL))
    search_s = time.perf_counter() - t0

    def cycle_at(rtol: float):
        t0 = time.perf_counter()
        sim = simulate(model, speed, integrator=Integrator("idas", rtol=rtol), x0=x0, n_out=4001, work=False)
        return time.perf_counter() - t0, sim

    wall, ref = cycle_at(REFERENCE_RTOL)
    timed = []
    for rtol in TIMED_RTOLS:
        runs = [cycle_at(rtol) for _ in range(repeat)]
        sim = runs[-1][1]
        timed.append({"rtol": rtol, "times_s": [r[0] for r in runs], "median_s": statistics.median(r[0] for r in runs),
                      "steps": sim.stats.get("steps"), "peaks": {n: sim.peak(n) for n in PEAKS},
                      "initial_conditions": sim.stats.get("initial_conditions")})
    return {"model": spec.describe(), "spec": spec.to_dict(), "states": model.nx,
            "periodic_search": {**info, "wall_s": search_s},
            "reference_cycle": {"rtol": REFERENCE_RTOL, "wall_s": wall, "steps": ref.stats.get("steps"),
                                "peaks": {n: ref.peak(n) for n in PEAKS},
                                "impacts": impacts(ref, model.params, model.clearance)},
            "timed": timed}


def periodic_scenes(elements: int) -> list[tuple[str, FourierSpeed, PressParams, ModelSpec, list[ModelSpec]]]:
    """The periodic scenes: name, crank speed, press, the full rod (the reference) and the levels
    compared with it. The seed optimum and the impacting kinematic design of the default press (both
    clearances), and the slender-rod scene's kinematic design (ideal joints)."""
    seed = json.loads(SEED.read_text())
    problem = SpeedProblem(PressParams(), period=IMPACTING_PERIOD, ram_speed=-0.1)
    full = ModelSpec("flexible", n_elements=elements)
    slender = Scenario.load("slender_rod")
    ideal = [ModelSpec("flexible", (), 4), *(ModelSpec("flexible", (), elements, m) for m in (1, 2, 3))]
    return [("press75 seed optimum", FourierSpeed(seed["period"], seed["a"], seed["b"], seed["theta0"]),
             PressParams(), full, levels(elements)),
            (f"kinematic design at {60 / IMPACTING_PERIOD:.0f} spm (period {IMPACTING_PERIOD:g} s), impacting",
             design_speed(problem).speed, PressParams(), full, levels(elements)),
            ("slender-rod scene's kinematic design", design_speed(slender.problem).speed,
             slender.press, ModelSpec("flexible", (), elements), ideal)]


def periodic_scene_of(name: str, speed: FourierSpeed, press: PressParams, full: ModelSpec, specs: list[ModelSpec],
                      repeat: int) -> dict:
    """The periodic scene `name` on the `full` rod (the reference) and on `specs`; errors against the
    full rod's cycle at `REFERENCE_RTOL`."""
    runs = [periodic_scene(spec, speed, repeat, press) for spec in (full, *specs)]
    ref_peaks = runs[0]["reference_cycle"]["peaks"]
    for lv in runs:
        for c in (lv["reference_cycle"], *lv["timed"]):
            c["errors"] = {n: abs(c["peaks"][n] / ref_peaks[n] - 1) for n in PEAKS}
        print(f"{name}, {lv['model']}: search {lv['periodic_search']['wall_s']:.1f} s; "
              + "; ".join(f"rtol {c['rtol']:g} {c['median_s']:.3f} s, torque error {c['errors']['torque']:.1e}"
                          for c in lv["timed"]), flush=True)
    return {"scene": name, "period": speed.period, "reference": runs[0]["model"], "reference_rtol": REFERENCE_RTOL,
            "repeat": repeat, "levels": runs}


def simeon(spec: ModelSpec) -> dict:
    """Simeon's slider crank on the rod of `spec`: relative errors at 0.1 s against the reference."""
    p = PressParams.simeon()
    t0 = time.perf_counter()
    r = simeon_crank(n_elements=spec.n_elements, n_modes=spec.n_modes)
    wall = time.perf_counter() - t0
    ref = SIMEON_REFERENCE
    got = {"slider_position": p.crank_radius + p.rod_length - r.ram_height[-1],
           "slider_velocity": -r.ram_velocity[-1], "midspan_deflection": r.rod_midspan_deflection[-1],
           "midspan_extremes": 0.5 * (np.max(r.rod_midspan_deflection) - np.min(r.rod_midspan_deflection))}
    return {"model": spec.describe(), "wall_s": wall, "values": got,
            "errors": {k: abs(v / ref[k] - 1) for k, v in got.items()}}


def periodic_panel(px, per: dict) -> None:
    """Time of one periodic cycle against its relative peak torque error, a line per level over the
    rtols; the marker's size is the rtol (labels at every point ran into each other), an error below
    `ERROR_FLOOR` is drawn at it and the panel says so."""
    sizes = {rtol: 3.5 + 3.0 * k for k, rtol in enumerate(sorted(TIMED_RTOLS, reverse=True))}
    floored = False
    for k, lv in enumerate(per["levels"]):
        xs = [c["median_s"] for c in lv["timed"]]
        ys = [max(c["errors"]["torque"], ERROR_FLOOR) for c in lv["timed"]]
        floored |= any(c["errors"]["torque"] < ERROR_FLOOR for c in lv["timed"])
        px.plot(xs, ys, "-", color=f"C{k}", label=f"{lv['model'].replace(', clearance in crank_pin and wrist_pin', '')} "
                f"({lv['states']} states)")
        for x, y, c in zip(xs, ys, lv["timed"]):
            px.plot(x, y, "o", color=f"C{k}", ms=sizes.get(c["rtol"], 5.0))
    for rtol, ms in sizes.items():  # the sizes' key, grey
        px.plot([], [], "o", color="0.5", ms=ms, label=f"IDAS rtol {rtol:g}")
    if floored:
        px.text(0.01, 0.01, f"errors below {ERROR_FLOOR:g} drawn at it", transform=px.transAxes, fontsize=6,
                color="0.4")
    imp = per["levels"][0]["reference_cycle"]["impacts"]
    joints = (f"both clearances:\ncontact losses crank/wrist pin {imp['crank_pin']['losses']}/"
              f"{imp['wrist_pin']['losses']} a cycle, back at the wall at up to "
              f"{max(i['return_speed_m_s'] for i in imp.values()) * 1e3:.1f} mm/s" if imp else "no clearance joints")
    px.axvline(GOAL_CYCLE_S, color="k", ls=":", lw=1, label=f"goals: {GOAL_CYCLE_S:g} s a cycle, {GOAL_PEAK:g} error")
    px.axhline(GOAL_PEAK, color="k", ls=":", lw=1)
    px.set_xscale("log")
    px.set_yscale("log")
    px.set_xlabel(f"one periodic cycle ({per['period']:.3g} s), wall s\n(median of {per['repeat']}; IDAS at the rtol "
                  "marked, compiled)")
    px.set_ylabel(f"relative peak torque error against the {per['reference'].split(',')[0]}\n(periodic, rtol "
                  f"{per['reference_rtol']:g})")
    px.set_title(f"{per['scene']}, {joints}", fontsize=8)
    lo, hi = px.get_ylim()
    px.set_ylim(lo, hi * (hi / lo) ** 0.6)  # a log axis's room above the points for the legend
    px.legend(fontsize=6, loc="upper right")


def figure(row: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = row.get("periodic") or []
    panels = 2 + len(scenes)
    cols = min(panels, 3)  # rows of at most three panels, so that a page shows the text at its size
    rows = -(-panels // cols)
    fig, grid = plt.subplots(rows, cols, figsize=(6 * cols, 4.8 * rows), squeeze=False)
    axes = grid.ravel()
    for spare in axes[panels:]:
        spare.set_visible(False)
    ax, bx = axes[panels - 2 : panels]
    for px, per in zip(axes, scenes):
        periodic_panel(px, per)
    for k, c in enumerate(row["cycles"]):
        err = max(c["errors"][n] for n in PEAKS)
        ax.plot(c["median_s"], max(err, 1e-8), "o", color=f"C{k}", label=f"{c['model']} ({c['states']} states)")
        ax.plot(c["times_s"], [max(err, 1e-8)] * len(c["times_s"]), ".", color=f"C{k}", alpha=0.5)
    ax.axvline(GOAL_CYCLE_S, color="k", ls=":", lw=1)
    ax.axhline(GOAL_PEAK, color="k", ls=":", lw=1)
    ax.set_xscale("log")
    ax.set_yscale("log")
    how = ("compiled" if row.get("jit") else "interpreted") if "jit" in row else "interpreted"
    ax.set_xlabel(f"{row['t_end']:g} s from rest (the cycle is 0.8 s), wall s\n(median of {row['repeat']}; "
                  f"{row.get('method', 'cvodes').upper()} rtol {row['rtol']:g}, {how})")
    ax.set_ylabel("largest peak error (torque, pin forces)\nagainst the full element rod (the same rtol)")
    ax.set_title("75 spm kinematic design, both clearances, a transient from rest: cost against error", fontsize=9)
    ax.legend(fontsize=7)
    names = [s["model"].replace("flexible rod ", "").replace(", ideal joints", "") for s in row["simeon"]]
    keys = ("slider_position", "slider_velocity", "midspan_deflection", "midspan_extremes")
    x = np.arange(len(names))
    for j, key in enumerate(keys):
        bx.bar(x + (j - 1.5) * 0.2, [max(s["errors"][key], 1e-9) for s in row["simeon"]], 0.2, label=key)
    bx.axhline(GOAL_SIMEON, color="k", ls=":", lw=1)
    bx.set_yscale("log")
    bx.set_xticks(x, names, fontsize=7, rotation=15)
    bx.set_ylabel("relative error at 0.1 s")
    bx.set_title("Simeon's flexible slider crank against its reference values", fontsize=9)
    bx.legend(fontsize=7)
    fig.tight_layout()
    figure_note(fig, row)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--elements", type=int, default=8, help="elements of the rod the modes come from")
    ap.add_argument("--rtol", type=float, default=1e-7)
    ap.add_argument("--method", choices=("idas", "cvodes"), default="idas")
    ap.add_argument("--interpreted", action="store_true", help="CasADi's virtual machine instead of compiled code")
    ap.add_argument("--t-end", type=float, default=0.2, help="seconds simulated from rest (0.8: one cycle)")
    ap.add_argument("--replot", action="store_true", help="redraw the figure from results/modal_rod.json")
    a = ap.parse_args()
    if a.replot:
        figure(json.loads((OUT / "modal_rod.json").read_text()), OUT / "modal_rod.png")
        return
    if a.repeat < 1:
        ap.error(f"--repeat must be >= 1, got {a.repeat}")
    full = ModelSpec("flexible", n_elements=a.elements)
    scenes = [periodic_scene_of(*scene, max(3, a.repeat)) for scene in periodic_scenes(a.elements)]
    reference = cycle(full, a.rtol, a.repeat, a.t_end, a.method, not a.interpreted)
    print(f"reference {reference['model']} at rtol {a.rtol:g}: {reference['median_s']:.1f} s, "
          f"peak torque {reference['peaks']['torque']:.6g} N m", flush=True)
    cycles = []
    for spec in levels(a.elements):
        c = cycle(spec, a.rtol, a.repeat, a.t_end, a.method, not a.interpreted)
        c["errors"] = {n: abs(c["peaks"][n] / reference["peaks"][n] - 1) for n in PEAKS}
        cycles.append(c)
        print(f"{c['model']}: {c['median_s']:.3f} s, {c['steps']} steps, peak torque {c['peaks']['torque']:.6g} N m "
              f"(error {c['errors']['torque']:.2e})", flush=True)
    sims = [simeon(ModelSpec("flexible", (), n)) for n in (4, 8)]
    sims += [simeon(ModelSpec("flexible", (), a.elements, m)) for m in (1, 2, 3)]
    for s in sims:
        print(f"Simeon, {s['model']}: " + ", ".join(f"{k} {v:.2e}" for k, v in s["errors"].items()), flush=True)
    row = {**stamp(), "scene": f"default press, 75 spm kinematic design, both clearances, {a.t_end:g} s from rest",
           "repeat": a.repeat, "rtol": a.rtol, "method": a.method, "jit": not a.interpreted, "t_end": a.t_end, "reference": reference, "cycles": cycles, "simeon": sims,
           "periodic": scenes,
           "goals": {"cycle_s": GOAL_CYCLE_S, "peak": GOAL_PEAK, "simeon": GOAL_SIMEON, "elements": GOAL_ELEMENTS}}
    OUT.mkdir(exist_ok=True)
    (OUT / "modal_rod.json").write_text(json.dumps(row, indent=1))
    figure(row, OUT / "modal_rod.png")


if __name__ == "__main__":
    main()
