"""pressocp: crank-speed design for servo mechanical presses (run `pressocp COMMAND -h` for a command).

Also `python -m pressocp`.

    pressocp                                   the main job: optimise the 75 spm scenario, write out/
    pressocp optimize [SCENARIO] --out DIR     minimum peak torque (or the scenario's objective)
    pressocp simulate [SCENARIO] [--speed F]   a speed (default: the rigid design) on the model
    pressocp design [SCENARIO]                 rigid speed design (seconds)
    pressocp impacts [SCENARIO]                constant and designed speed: impacts in the clearances
    pressocp sweep [SCENARIO] --vary KEY=A:B:N one task over a grid of values, in parallel
    pressocp compare A B [-o DIR]              two designs side by side (results folders, scenarios, speeds)
    pressocp rate [SCENARIO]                   the highest stroke rate its [drive] allows (tens of minutes)
    pressocp scenario new PATH                 a commented scenario file to edit
    pressocp scenario show [SCENARIO]          the scenario as it will be run (bundled: press75, ...)

SCENARIO is a TOML file or a bundled scenario's name (default press75). Any key can be overridden:
``--set problem.stroke_rate_spm=60 --set press.wrist_pin.clearance=5e-5``.

Exit codes: 0 success; 1 solved but not converged or not verified (results written and flagged);
2 bad input (one message, nothing solved); 130 interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import os
import sys
import tomllib
import warnings
from pathlib import Path

#: The scenario every command runs by default.
DEFAULT_SCENARIO = "press75"


class InputError(ValueError):
    """Bad command-line input: reported in one line, exit code 2."""


def warn_other_press(path: str | None, scenario) -> None:
    """A warning on stderr when `path` (a ``--speed``) is a result designed for a press that differs
    from the scenario's, naming each differing parameter (simulating it on another press is allowed:
    that is what a wear study does)."""
    if path is None:
        return
    from .jobs import press_differences

    diff = press_differences(path, scenario.press)
    if diff:
        print(f"warning: --speed {path} was designed for another press than {scenario.name}'s: "
              + "; ".join(diff), file=sys.stderr)


def parse_set(items: list[str]) -> dict:
    """``KEY=VALUE`` strings to overrides; VALUE is read as TOML (``60``, ``[0.6, 0.25]``, ``true``,
    ``"text"``) and taken as a plain string when it is not TOML (``model.rod=flexible``)."""
    out = {}
    for item in items:
        key, sep, raw = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise InputError(f"--set {item!r}: expected KEY=VALUE, e.g. --set problem.stroke_rate_spm=60")
        try:
            value = tomllib.loads(f"v = {raw.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            value = raw.strip()
        if key in out and out[key] != value:
            raise InputError(f"--set {key} given twice ({out[key]!r} and {value!r}): give it once")
        out[key] = value
    return out


def load_scenario(name: str | None, overrides: list[str]):
    """The scenario named on the command line with its ``--set`` overrides (checked)."""
    from .scenario import Scenario

    scenario = Scenario.load(name or DEFAULT_SCENARIO)
    sets = parse_set(overrides)
    return scenario.with_overrides(sets) if sets else scenario


TEMPLATE_HEAD = """\
# pressocp scenario: a press, the speed asked of it, the model and the solver.
# SI units (m, kg, s, N, Pa) unless the key says otherwise (stroke_rate_spm: strokes per minute).
# Run it:   pressocp optimize {path}        Check it: pressocp scenario show {path}
# Every key below can also be set on the command line: --set problem.stroke_rate_spm=60
"""


#: Comments of the template's keys (units and choices).
TEMPLATE_NOTES = {
    "crank_radius": "m (stroke H = 2 x crank radius)", "rod_length": "m, centre to centre",
    "crank_inertia": "kg m^2 about the crank axis (crank, gears, motor referred to the crank)",
    "crank_mass": "kg", "crank_com": "m, centre of mass from the axis along the crank",
    "rod_mass": "kg", "rod_youngs_modulus": "Pa (flexible rod)", "rod_area_moment": "m^4 (flexible rod)",
    "rod_damping_ratio": "- at the first bending mode (flexible rod)", "slider_mass": "kg, ram and upper die",
    "gravity": "m/s^2 along the slide toward the bed (0: horizontal press)",
    "clearance": "m, radial (0.1 mm = 1.0e-4)", "journal_radius": "m",
    "exponent": "- Hertz exponent n of K delta^n", "law": "hunt-crossley or kelvin-voigt",
    "tangential_damping": "N s/m, lubricant film along the bearing surface",
    "force": "N, forming force (0: none)", "h_top": "m above bottom dead centre where it starts",
    "h_bottom": "m where it ends", "edge": "m, smoothing of its edges", "speed_edge": "m/s, smoothing of the "
    "downstroke switch", "period_s": "s per stroke (or stroke_rate_spm = strokes per minute)",
    "ram_speed": "m/s in the working window (negative: down)",
    "window": "h/H at entry and exit of the working window (h above bottom dead centre)",
    "objective": "peak_torque, peak_slider_normal_force, peak_pin_force, rms_torque, peak_power; with a "
                 "[drive]: rms_motor_torque, energy_per_stroke or bus_energy_swing",
    "n_harmonics": "Fourier harmonics of the crank speed", "rod": "rigid or flexible",
    "n_elements": "beam elements of the flexible rod",
    "n_modes": "bending modes the flexible rod is reduced to (unset: every element DOF)", "transcription": "auto, collocation, shooting-idas or "
    "shooting-cvodes", "jit": "\"auto\", true or false: compile collocation with the C compiler",
    "verify_rtol": "tolerance of the verifying re-simulation",
    "polish_rounds": "most re-solves of the last stage from its answer, each restarting the barrier (0: the first pass only)",
    "flexible_backoffs": "a flexible rod between ideal joints: extra starts at these shares of the ram-speed tolerance ([]: none)",
}
#: Notes of keys whose meaning depends on their table.
TEMPLATE_TABLE_NOTES = {
    ("model", "clearance"): "joints with clearance (crank_pin, wrist_pin; [] for ideal joints)",
    ("press.process_force", "window"): "h/H where the force starts and ends on the downstroke",
    ("press.counterbalance", "force"): "N, slide counterbalance: up on the ram at bottom dead centre (0: none)",
    ("press.counterbalance", "gas_length"): "m, gas volume at bottom dead centre over the piston area",
    ("press.counterbalance", "exponent"): "- polytropic: 0 constant force, 1 isothermal, 1.4 adiabatic",
}
#: Optional keys the template shows commented out, after the line of the key named first.
TEMPLATE_OPTIONAL = {
    "objective": ["# ram_speed_tol = 0.001               # m/s (default 1 % of |ram_speed|)",
                  "# max_pin_force = 8000.0              # N, cap on the crank-pin and wrist-pin forces",
                  "# omega_min = 0.5                     # rad/s (default 5 % of the mean crank speed)",
                  "# omega_max = 40.0                    # rad/s, motor speed limit at the crank",
                  "# alpha_max = 2000.0                  # rad/s^2, motor acceleration limit at the crank"],
    "speed_edge": ["# window = [0.1, 0.0]                 # h/H where the force starts and ends (instead of h_top, h_bottom)",
                   "# heights = [0.005, 0.03, 0.04]          # m above bottom dead centre, increasing: a curve",
                   "# forces = [0.0, 8000.0, 0.0]            # N at those heights (instead of force)"],
    "n_elements": ["# n_modes = 2                         # reduce the flexible rod to its first bending modes"],
    "gravity": ["",
                "# Another linkage than the slider-crank (six_bar or knuckle_joint): uncomment, and drop",
                "# crank_radius and rod_length above (its drive's links give them). Bundled: knuckle40.",
                "# [mechanism]",
                "# name = \"knuckle_joint\"",
                "# input_inertia = 0.05                  # kg m^2, the input crank",
                "# coupler_mass = 3.0                    # kg, the connecting rod to the knee",
                "# [mechanism.drive]                     # its geometry: KnucklePress or SixBarPress fields",
                "# input_crank = 0.04                    # m",
                "# coupler = 0.45                        # m",
                "# upper_link = 0.16                     # m, pivot to knee (the press's crank_radius)",
                "# lower_link = 0.25                     # m, knee to slide (the press's rod_length)",
                "# drive_angle = 1.5707963267948966      # rad, clock angle from the straight knee to the input axis"],
    "flexible_backoffs": ["",
                      "# The servo drive: every result then reports the motor's figures (motor.png, summary.json).",
                      "# [drive]",
                      "# gear_ratio = 10.0                     # motor speed / crank speed",
                      "# peak_torque = 40.0                    # N m at the motor, up to the corner speed",
                      "# continuous_torque = 15.0              # N m, rated RMS torque",
                      "# max_speed = 314.0                     # rad/s at the motor (3000 rpm)",
                      "# power_limit = 5000.0                  # W: above the corner speed, peak torque = power / speed",
                      "# gear_efficiency = 0.95",
                      "# motor_inertia = 0.004                 # kg m^2, rotor",
                      "# gear_inertia = 0.0                    # kg m^2 at the motor shaft",
                      "# regeneration_efficiency = 0.0         # share of regenerated energy the supply gets back"],
    "journal_radius": ["# stiffness = 6.2e11                   # N/m^1.5 (default: Hertz, steel on steel)",
                       "# damping = 3.0                       # s/m, Hunt-Crossley hysteresis (default 3.0: e = 0.9 at 0.05 m/s)"],
}


def template(path: str) -> str:
    """A scenario file with every table, each key commented with its unit, optional keys commented
    out."""
    from .scenario import Scenario

    lines, table = [], ""
    for line in Scenario.bundled(DEFAULT_SCENARIO).to_toml().splitlines():
        key = line.split("=")[0].strip()
        table = line.strip("[]") if line.startswith("[") else table
        note = TEMPLATE_TABLE_NOTES.get((table, key), TEMPLATE_NOTES.get(key))
        if "=" in line and note:
            line = f"{line:<40s} # {note}"
        lines.append(line)
        if "=" in line and key in TEMPLATE_OPTIONAL and table != "press.wrist_pin":  # a bearing's, once
            lines += TEMPLATE_OPTIONAL[key]
    return TEMPLATE_HEAD.format(path=path) + "\n" + "\n".join(lines) + "\n"


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="pressocp", description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", metavar="COMMAND")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("scenario", nargs="?", default=None,
                        help=f"TOML file or bundled scenario name (default {DEFAULT_SCENARIO})")
    common.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="override a scenario key, e.g. problem.stroke_rate_spm=60 (repeatable)")
    common.add_argument("--out", type=Path, default=Path("out"), help="output folder (default: out)")
    common.add_argument("--quiet", "-q", action="store_true", help="no progress bars, no report on the terminal")
    common.add_argument("--strict", action="store_true",
                        help="refuse values that look like unit slips (a mass in g, a speed limit in rpm)")
    sub.add_parser("optimize", parents=[common], help="optimal crank speed, verified (minutes)")
    sim = sub.add_parser("simulate", parents=[common], help="a speed on the scenario's model")
    sim.add_argument("--speed", type=Path, default=None,
                     help="speed.json or result.json from optimize (default: the rigid design)")
    sub.add_parser("design", parents=[common], help="rigid speed design (seconds)")
    sub.add_parser("impacts", parents=[common], help="impacts of constant and designed speed")
    rate = sub.add_parser("rate", parents=[common], help="the highest stroke rate the scenario's [drive] allows, "
                          "each rate's optimum verified (tens of minutes)")
    rate.add_argument("--tolerance-spm", type=float, default=1.0, help="width of the final bracket, strokes/min")
    rate.add_argument("--max-trials", type=int, default=12, help="most rates tried (each one or two optimisations)")
    rate.add_argument("--unconstrained-only", action="store_true",
                      help="judge each rate by its optimum without the drive's limits in the NLP only (one "
                           "optimisation per rate; a rate the drive runs can then be called infeasible)")
    sw = sub.add_parser("sweep", parents=[common], help="a task over a grid or a path of values (sweep.csv)")
    sw.add_argument("--vary", action="append", default=[], metavar="KEY=VALUES", required=True,
                    help="values of a scenario key: START:STOP:N (evenly spaced) or V1,V2,... (repeatable: a grid)")
    sw.add_argument("--task", choices=("optimize", "simulate", "impacts"), default="optimize")
    sw.add_argument("--path", action="store_true",
                    help="the --vary lists (of equal length) are one path, not a grid; optima are warm-started "
                         "from their neighbour's")
    sw.add_argument("--along", default=None, metavar="KEY",
                    help="a grid of optima warm-started along this --vary key: its lines cut into segments of "
                         "--segment points, each solved cold at its first point and from its neighbour's optimum "
                         "after that, the segments side by side")
    sw.add_argument("--segment", type=int, default=None, help="points per segment of --along (default 2)")
    sw.add_argument("--speed", type=Path, default=None, help="the speed a simulate sweep evaluates (default: "
                    "each point's rigid design)")
    sw.add_argument("--workers", type=int, default=None, help="worker processes (default: one per core)")
    sw.add_argument("--resume", action="store_true", help="skip the points already done in OUT/sweep.csv")
    cmp = sub.add_parser("compare", help="two designs side by side: sizing figures, B/A, overlaid figures")
    for side in ("A", "B"):
        cmp.add_argument(side, help="a results folder (optimize, simulate), a scenario (bundled name or TOML: its "
                                    "rigid design simulated) or a speed file (.json, simulated on --scenario)")
    cmp.add_argument("-o", "--out", type=Path, default=Path("compare"), help="output folder (default: compare)")
    cmp.add_argument("--scenario", default=None,
                     help=f"the scenario a speed file is simulated on (default {DEFAULT_SCENARIO})")
    cmp.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="override a key of the scenarios simulated (repeatable)")
    cmp.add_argument("--quiet", "-q", action="store_true", help="no table on the terminal")
    scen = sub.add_parser("scenario", help="write a template or show a scenario")
    ssub = scen.add_subparsers(dest="action", metavar="ACTION", required=True)
    new = ssub.add_parser("new", help="write a commented scenario file to edit")
    new.add_argument("path", type=Path)
    new.add_argument("--force", action="store_true", help="overwrite an existing file")
    show = ssub.add_parser("show", help="print the scenario as it will be run")
    show.add_argument("scenario", nargs="?", default=None)
    show.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    return ap


def interrupted(out: Path, staging: Path | None) -> str:
    """What an interrupted job left in `out`: its run when the commit had finished (the manifest
    names this run's staging folder), else the previous run, untouched."""
    from .io import RunMismatch, read_manifest, staging_run_id

    try:
        manifest = read_manifest(out) if out.is_dir() else None
    except RunMismatch:
        manifest = None
    if staging is not None and manifest is not None and manifest.get("run_id") == staging_run_id(staging):
        return f"this run had finished writing; {out} holds it"
    held = f"the previous run (run {manifest.get('run_id')})" if manifest else "the previous run, if any"
    return f"nothing of this run was written; {out} holds {held}"


def check_writable(folder: Path, what: str) -> None:
    """InputError unless `folder` can be written or created: its nearest existing ancestor must be a
    folder this process may write into. Checked before any solve (a folder is not created here)."""
    existing = folder.absolute()
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise InputError(f"{what}: {existing} is a file, so no folder can be made under it")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise InputError(f"{what}: {existing} is not writable by this user")


def _prepare(args: argparse.Namespace):
    """Check the input and return the job to run (a callable giving its exit code). Every bad value
    raises here, before anything is solved."""
    from .io import MANIFEST_NAME, NotRegularFile, check_regular, output_folder, refuse_if_busy

    if args.command == "scenario":
        return _prepare_scenario(args)
    if args.command == "compare":
        return _prepare_compare(args)

    out: Path = args.out
    refuse_if_busy(out)  # a folder another run writes: refused before anything else is read
    scenario = load_scenario(args.scenario, args.set)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out} is a file, not a folder")
    check_writable(out, f"--out {out}")
    import matplotlib

    matplotlib.use("Agg")  # files only; the library itself never picks a backend
    from . import jobs

    for name in (*jobs.OUTPUT_NAMES, *SWEEP_FILES, MANIFEST_NAME):  # each replaced by a regular file
        try:
            check_regular(out / name)
        except NotRegularFile as err:
            raise InputError(f"--out: {err}") from None

    if args.command == "sweep":
        return _prepare_sweep(args, scenario, out)
    if args.command == "simulate":
        speed = jobs.read_speed(args.speed) if args.speed is not None else None
        scenario.check_speed(speed, "--speed")
        warn_other_press(args.speed, scenario)
        job = lambda folder: jobs.simulate_job(scenario, folder, speed,  # noqa: E731
                                               str(args.speed) if args.speed else "rigid design",
                                               progress=not args.quiet)
    elif args.command == "design":
        job = lambda folder: jobs.design_job(scenario, folder)  # noqa: E731
    elif args.command == "impacts":
        job = lambda folder: jobs.impacts_job(scenario, folder)  # noqa: E731
    elif args.command == "rate":
        if scenario.problem.drive is None:
            raise InputError(f"rate: scenario {scenario.name!r} has no [drive] table: the stroke rate is limited by "
                             "the drive's ratings (pressocp scenario new shows one)")
        from .stroke_rate import RateSearch

        try:
            search = RateSearch(tolerance_spm=args.tolerance_spm, max_trials=args.max_trials,
                                hold_limits=not args.unconstrained_only)
        except ValueError as err:
            raise InputError(f"rate: {err}") from None
        job = lambda folder: jobs.rate_job(scenario, folder, search, progress=not args.quiet)  # noqa: E731
    else:
        job = lambda folder: jobs.optimize_job(scenario, folder, progress=not args.quiet)  # noqa: E731

    def run() -> int:
        folder = None
        try:
            with output_folder(out) as folder:  # the job writes into a staging folder, committed at the end
                report = job(folder)
        except KeyboardInterrupt:
            raise KeyboardInterrupt(interrupted(out, folder)) from None
        if not args.quiet:
            print(report.text)
            print(f"  wrote {', '.join(p.name for p in report.files)} to {out}/")
        if not report.ok:
            from .summaries import flag_reason

            print(f"pressocp {report.job}: results written but flagged: {flag_reason(report.summary)}",
                  file=sys.stderr)
        return report.exit_code
    return run


def _prepare_scenario(args: argparse.Namespace):
    """`pressocp scenario new|show`: check the input and return the job."""
    from .io import NotRegularFile, atomic_write, check_regular

    if args.action == "new":
        if args.path.exists() and not args.force:
            raise InputError(f"{args.path} exists; pass --force to overwrite it")
        check_writable(args.path.parent, f"scenario new {args.path}")
        try:
            check_regular(args.path)
        except NotRegularFile as err:
            raise InputError(f"scenario new: {err}") from None

        def write() -> int:
            atomic_write(args.path, template(str(args.path)))
            print(f"wrote {args.path}: edit it, then run pressocp optimize {args.path}")
            return 0
        return write
    text = load_scenario(args.scenario, args.set).to_toml()
    return lambda: print(text, end="") or 0


def _prepare_compare(args: argparse.Namespace):
    """Check both sides of ``compare`` and its output folder; return the job that writes the
    comparison (compare.csv, compare.png, motor.png with drives on both sides, report.txt)."""
    import matplotlib

    matplotlib.use("Agg")
    from .compare import COMPARE_FILES, CompareError, prepare, run_compare
    from .io import NotRegularFile, check_regular, output_folder

    out: Path = args.out
    if out.exists() and not out.is_dir():
        raise InputError(f"-o {out} is a file, not a folder")
    check_writable(out, f"-o {out}")
    for name in COMPARE_FILES:
        try:
            check_regular(out / name)
        except NotRegularFile as err:
            raise InputError(f"-o: {err}") from None
    overrides = parse_set(args.set)
    scenario = load_scenario(args.scenario, args.set)
    try:
        make_a = prepare(args.A, "A", scenario, overrides)
        make_b = prepare(args.B, "B", scenario, overrides)
    except CompareError as err:
        raise InputError(str(err)) from None

    def run() -> int:
        with output_folder(out) as folder:
            _, text, files = run_compare(make_a, make_b, folder)
        if not args.quiet:
            print(text)
            print(f"  wrote {', '.join(p.name for p in files)} to {out}/")
        return 0
    return run


def parse_vary(items: list[str], path: bool) -> dict | list:
    """``--vary`` strings to `pressocp.sweep`'s ``vary``: a grid (dict of lists) or, with `path`, a
    list of points (the lists zipped)."""
    import numpy as np

    lists = {}
    for item in items:
        key, sep, raw = item.partition("=")
        key = key.strip()
        if not sep or not key or not raw.strip():
            raise InputError(f"--vary {item!r}: expected KEY=START:STOP:N or KEY=V1,V2,...")
        if ":" in raw:
            parts = raw.split(":")
            try:
                start, stop, n = float(parts[0]), float(parts[1]), int(parts[2])
            except (ValueError, IndexError):
                raise InputError(f"--vary {item!r}: START:STOP:N needs two numbers and a count, e.g. "
                                 f"{key}=5e-5:3e-4:6") from None
            if len(parts) != 3 or not 1 <= n <= 10_000:
                raise InputError(f"--vary {item!r}: N must be in [1, 10000] and come third")
            values = [float(v) for v in np.linspace(start, stop, n)]
        else:
            values = [parse_set([f"{key}={v}"])[key] for v in raw.split(",")]
        if key in lists:
            raise InputError(f"--vary {key} given twice")
        lists[key] = values
    if not path:
        return lists
    lengths = {len(v) for v in lists.values()}
    if len(lengths) != 1:
        raise InputError(f"--path: every --vary list must have the same length, got {sorted(lengths)}")
    return [dict(zip(lists, combo)) for combo in zip(*lists.values())]


def _prepare_sweep(args: argparse.Namespace, scenario, out: Path):
    """Check a sweep's input (every point) and return the job that runs it."""
    from . import jobs, plots
    from .io import atomic_write, output_folder, run_id, write_manifest
    from .sweeps import Continuation, points_of, sweep
    from .workers import process_pool

    vary = parse_vary(args.vary, args.path)
    points, _ = points_of(vary)
    continuation: bool | Continuation = True
    if args.segment is not None and args.along is None:
        raise InputError(f"--segment {args.segment} sets the segments of --along KEY, which is not given")
    if args.along is not None:
        if args.path or args.task != "optimize":
            raise InputError(f"--along continues a grid of optima; this is {'a --path' if args.path else 'a grid'} "
                             f"of --task {args.task}")
        try:
            continuation = (Continuation(args.along) if args.segment is None
                            else Continuation(args.along, args.segment))
            continuation.segments(points)
        except ValueError as err:
            raise InputError(f"--along/--segment: {err}") from None
    speed = jobs.read_speed(args.speed) if args.speed is not None else None
    if speed is not None and args.task != "simulate":
        raise InputError(f"--speed is the speed a simulate sweep evaluates; --task is {args.task}")
    for p in points:
        scenario.with_overrides(p).check_speed(speed, "--speed")
    warn_other_press(args.speed, scenario)
    if args.workers is not None and not 1 <= args.workers <= 256:
        raise InputError(f"--workers must be in [1, 256], got {args.workers}")
    csv = out / "sweep.csv"
    if csv.exists() and not args.resume:
        raise InputError(f"{csv} exists: pass --resume to continue that sweep, or another --out")
    keys = list(points[0])

    def run() -> int:
        try:
            with output_folder(out, transaction=False):  # a resumed sweep continues its sweep.csv
                return sweep_job()
        except KeyboardInterrupt:
            raise KeyboardInterrupt(f"{csv} holds the points finished so far; --resume continues the sweep") from None

    def sweep_job() -> int:
        pool = None if args.workers is None else process_pool(args.workers)
        try:
            table = sweep(scenario, vary, args.task, speed, pool, progress=not args.quiet, csv=csv,
                          continuation=continuation)
        finally:
            if pool is not None:
                pool.shutdown(cancel_futures=True)
        try:
            plots.save(plots.plot_sweep(table, keys, f"{scenario.name}: {args.task} sweep"), out / "sweep.png")
            written = "sweep.csv, sweep.png, report.txt"
        except ValueError as err:  # no point to draw: the figure is not claimed
            (out / "sweep.png").unlink(missing_ok=True)
            written = f"sweep.csv, report.txt (no sweep.png: {err})"
        failed = int((~table["ok"].astype(bool)).sum())
        text = f"{scenario.name}: {args.task} at {len(table)} points, {failed} not ok"
        atomic_write(out / "report.txt", text + "\n\n" + table.drop(columns=["speed"], errors="ignore")
                     .to_string(index=False) + "\n")
        write_manifest(out, run_id(), [n for n in SWEEP_FILES if (out / n).is_file()])
        if not args.quiet:
            cols = [c for c in [*keys, "ok", "peak_torque_N_m", "initial_peak_torque_N_m", "rigid_peak_torque_N_m",
                                "peak_slider_normal_force_N", "wall_time_s", "error"] if c in table]
            print(text)
            print(table[cols].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
            print(f"  wrote {written} to {out}/")
        return 0 if failed == 0 else 1
    return run


#: The files a sweep writes into its folder: its table (resumed from), figure and report.
SWEEP_FILES = ("sweep.csv", "sweep.png", "report.txt")
#: Subcommands; a command line that starts with none of them runs ``optimize``.
COMMANDS = ("optimize", "simulate", "design", "impacts", "sweep", "scenario", "compare", "rate")


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit code (0, 1, 2 or 130)."""
    from .checks import PlausibilityWarning
    from .io import NotRegularFile, OutputBusy
    from .scenario import ScenarioError

    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or (argv[0] not in COMMANDS and argv[0] not in ("-h", "--help")):
        argv = ["optimize", *argv]  # the main job
    args = _parser().parse_args(argv)
    try:
        with warnings.catch_warnings(record=True) as suspects:  # values that look like unit slips
            warnings.simplefilter("error" if getattr(args, "strict", False) else "always", PlausibilityWarning)
            job = _prepare(args)
    except (InputError, ScenarioError, ValueError, PlausibilityWarning) as err:  # names the key, value and range
        print(f"pressocp: error: {err}", file=sys.stderr)
        return 2
    for w in suspects:
        if not issubclass(w.category, PlausibilityWarning):
            warnings.showwarning(w.message, w.category, w.filename, w.lineno)
    for message in dict.fromkeys(str(w.message) for w in suspects if issubclass(w.category, PlausibilityWarning)):
        print(f"pressocp: warning: {message} (--strict makes this an error)", file=sys.stderr)
    try:
        return job()
    except (OutputBusy, NotRegularFile) as err:  # the folder taken, or a file of it made a folder meanwhile
        print(f"pressocp: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as err:
        print(f"pressocp: interrupted{f': {err}' if str(err) else ''}", file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
