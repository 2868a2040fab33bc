"""Command line: ``pressocp`` (or ``python -m pressocp``).

    pressocp                                   the main job: optimise the 75 spm scenario, write out/
    pressocp optimize [SCENARIO] --out DIR     minimum peak torque (or the scenario's objective)
    pressocp simulate [SCENARIO] [--speed F]   a speed (default: the rigid design) on the model
    pressocp design [SCENARIO]                 rigid speed design (seconds)
    pressocp impacts [SCENARIO]                constant and designed speed: impacts in the clearances
    pressocp scenario new PATH                 a commented scenario file to edit
    pressocp scenario show [SCENARIO]          the scenario as it will be run (bundled: press75, ...)

SCENARIO is a TOML file or a bundled scenario's name (default press75). Any key can be overridden:
``--set problem.stroke_rate_spm=60 --set press.wrist_pin.clearance=5e-5``.

Exit codes: 0 success; 1 solved but not converged or not verified (results written and flagged);
2 bad input (one message, nothing solved); 130 interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path

#: The scenario every command runs by default.
DEFAULT_SCENARIO = "press75"


class InputError(ValueError):
    """Bad command-line input: reported in one line, exit code 2."""


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
    "objective": "peak_torque, peak_slider_normal_force, peak_pin_force, rms_torque or peak_power",
    "n_harmonics": "Fourier harmonics of the crank speed", "rod": "rigid or flexible",
    "n_elements": "beam elements of the flexible rod", "transcription": "auto, collocation, shooting-idas or "
    "shooting-cvodes", "jit": "\"auto\", true or false: compile collocation with the C compiler",
    "verify_rtol": "tolerance of the verifying re-simulation",
}
#: Optional keys the template shows commented out, after the line of the key named first.
TEMPLATE_OPTIONAL = {
    "objective": ["# ram_speed_tol = 0.001               # m/s (default 1 % of |ram_speed|)",
                  "# max_pin_force = 8000.0              # N, cap on the crank-pin and wrist-pin forces",
                  "# omega_min = 0.5                     # rad/s (default 5 % of the mean crank speed)",
                  "# omega_max = 40.0                    # rad/s, motor speed limit at the crank",
                  "# alpha_max = 2000.0                  # rad/s^2, motor acceleration limit at the crank"],
    "journal_radius": ["# stiffness = 6.2e11                   # N/m^1.5 (default: Hertz, steel on steel)",
                       "# damping = 3.0                       # s/m, Hunt-Crossley hysteresis (default 3.0: e = 0.9 at 0.05 m/s)"],
}


def template(path: str) -> str:
    """A scenario file with every table, each key commented with its unit, optional keys commented
    out."""
    from .scenario import Scenario

    lines = []
    for line in Scenario.bundled(DEFAULT_SCENARIO).to_toml().splitlines():
        key = line.split("=")[0].strip()
        if "=" in line and key in TEMPLATE_NOTES:
            line = f"{line:<40s} # {TEMPLATE_NOTES[key]}"
        lines.append(line)
        if "=" in line and key in TEMPLATE_OPTIONAL and "[press.wrist_pin]" not in lines:
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
    sub.add_parser("optimize", parents=[common], help="optimal crank speed, verified (minutes)")
    sim = sub.add_parser("simulate", parents=[common], help="a speed on the scenario's model")
    sim.add_argument("--speed", type=Path, default=None,
                     help="speed.json or result.json from optimize (default: the rigid design)")
    sub.add_parser("design", parents=[common], help="rigid speed design (seconds)")
    sub.add_parser("impacts", parents=[common], help="impacts of constant and designed speed")
    scen = sub.add_parser("scenario", help="write a template or show a scenario")
    ssub = scen.add_subparsers(dest="action", metavar="ACTION", required=True)
    new = ssub.add_parser("new", help="write a commented scenario file to edit")
    new.add_argument("path", type=Path)
    new.add_argument("--force", action="store_true", help="overwrite an existing file")
    show = ssub.add_parser("show", help="print the scenario as it will be run")
    show.add_argument("scenario", nargs="?", default=None)
    show.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    return ap


def _prepare(args: argparse.Namespace):
    """Check the input and return the job to run (a callable giving its exit code). Every bad value
    raises here, before anything is solved."""
    from .io import atomic_write

    if args.command == "scenario":
        if args.action == "new":
            if args.path.exists() and not args.force:
                raise InputError(f"{args.path} exists; pass --force to overwrite it")

            def write() -> int:
                atomic_write(args.path, template(str(args.path)))
                print(f"wrote {args.path}: edit it, then run pressocp optimize {args.path}")
                return 0
            return write
        text = load_scenario(args.scenario, args.set).to_toml()
        return lambda: print(text, end="") or 0

    scenario = load_scenario(args.scenario, args.set)
    out: Path = args.out
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out} is a file, not a folder")
    import matplotlib

    matplotlib.use("Agg")  # files only; the library itself never picks a backend
    from . import jobs

    if args.command == "simulate":
        speed = jobs.read_speed(args.speed) if args.speed is not None else None
        jobs.check_speed(speed, scenario.problem)
        job = lambda: jobs.simulate_job(scenario, out, speed, str(args.speed) if args.speed else "rigid design")  # noqa: E731
    elif args.command == "design":
        job = lambda: jobs.design_job(scenario, out)  # noqa: E731
    elif args.command == "impacts":
        job = lambda: jobs.impacts_job(scenario, out)  # noqa: E731
    else:
        job = lambda: jobs.optimize_job(scenario, out, progress=not args.quiet)  # noqa: E731

    def run() -> int:
        report = job()
        if not args.quiet:
            print(report.text)
            print(f"  wrote {', '.join(p.name for p in report.files)} to {out}/")
        if not report.ok:
            print(f"pressocp {report.job}: results written but flagged: "
                  f"{report.summary.get('status', report.summary.get('periodic'))}", file=sys.stderr)
        return report.exit_code
    return run


#: Subcommands; a command line that starts with none of them runs ``optimize``.
COMMANDS = ("optimize", "simulate", "design", "impacts", "scenario")


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit code (0, 1, 2 or 130)."""
    from .scenario import ScenarioError

    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or (argv[0] not in COMMANDS and argv[0] not in ("-h", "--help")):
        argv = ["optimize", *argv]  # the main job
    args = _parser().parse_args(argv)
    try:
        job = _prepare(args)
    except (InputError, ScenarioError, ValueError) as err:  # names the key, the value and the range
        print(f"pressocp: error: {err}", file=sys.stderr)
        return 2
    try:
        return job()
    except KeyboardInterrupt:
        print("pressocp: interrupted (files written so far are complete; the rest were not written)",
              file=sys.stderr)
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
