"""A fuzz campaign of the package's front doors: generated presses, problems, scenario files,
scenario dicts and command lines, as a hostile or careless user would write them.

    python benchmarks/bench_fuzz.py [--cases N] [--seed S]

Each case ends in one of:

* ``accepted``: built, and (API and dict cases) its kinematic design and rigid response are finite;
* ``refused, named``: a ValueError or TypeError (the command line: exit 2) whose message names a
  field, key or file the case set;
* ``refused, unnamed``: refused with a message that names none of them;
* ``internal error``: any other exception, or a traceback on the command line;
* ``non-finite``: accepted, with a NaN or inf in its design or response;
* ``exit 1 on bad input``: a command line refused with exit 1 (the code of a solve that did not
  converge) instead of 2;
* ``refused after 2 s``: (the "process" family) refused, but more than 2 s after the process
  started.

The "process" family runs each case as its own ``python -m pressocp`` process, as a user's shell
does: generated ``--set`` values and scenario files, and bad ``--out`` and ``--speed`` arguments to
``optimize`` and ``simulate`` (which would start solving if they were not refused first); its time
is the process's whole wall time, start-up included.

The unit slips of issue #30's list are run one by one: each must be refused or warned
(`pressocp.checks.PlausibilityWarning`). Writes results/fuzz.json and results/fuzz.png.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import random
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import pressocp as po
from pressocp.checks import PlausibilityWarning
from pressocp.cli import main as cli
from pressocp.report import stamp

OUT = Path(__file__).parent / "results"
PRESS = {"crank_radius": 0.05, "rod_length": 0.25, "crank_inertia": 0.5, "crank_mass": 20.0, "crank_com": 0.01,
         "rod_mass": 3.14, "rod_youngs_modulus": 2.1e11, "rod_area_moment": 2.13e-7, "rod_damping_ratio": 0.02,
         "slider_mass": 150.0, "gravity": 9.81}
BEARING = {"clearance": 1e-4, "journal_radius": 0.04, "stiffness": 1e10, "damping": 1e3, "tangential_damping": 1e3}
PROBLEM = {"period": 0.8, "ram_speed": -0.1, "omega_max": 20.0, "max_pin_force": 1e4}
SPECIAL = [0.0, -0.0, math.nan, math.inf, -math.inf, True, "0.1", "x", None, [1.0], "", 1e308, -1e-308]
OUTCOMES = ("accepted", "refused, named", "refused, unnamed", "internal error", "non-finite", "exit 1 on bad input",
            "refused after 2 s")
#: A refusal of a command line must come within this many seconds of the process's start (issue #30).
REFUSAL_LIMIT_S = 2.0
#: A "process" case still running after this many seconds has passed every check and is solving: it
#: is stopped and counted as accepted.
SOLVING_S = 6.0
#: Issue #30's unit slips: (what, API call). Each must raise or warn.
SLIPS = {
    "rod_mass in g": lambda: po.PressParams(rod_mass=3140.0),
    "crank_com in mm": lambda: po.PressParams(crank_com=25.0),
    "gravity in mm/s^2": lambda: po.PressParams(gravity=9810.0),
    "Young's modulus in GPa": lambda: po.PressParams(rod_youngs_modulus=210.0),
    "Young's modulus in MPa": lambda: po.PressParams(rod_youngs_modulus=210000.0),
    "rod_area_moment in mm^4": lambda: po.PressParams(rod_area_moment=213.0),
    "crank_inertia in kg mm^2": lambda: po.PressParams(crank_inertia=5e5),
    "process_force.h_top in mm": lambda: po.PressParams(process_force=po.ProcessForce(force=1e4, h_top=12.7,
                                                                                      h_bottom=0.0)),
    "process force in mN": lambda: po.PressParams(process_force=po.ProcessForce(force=1e9, h_top=0.05,
                                                                                h_bottom=0.0)),
    "omega_max in rpm": lambda: po.SpeedProblem(po.PressParams(), period=0.8, omega_max=400.0),
    "clearance 0.1 um": lambda: po.Bearing(clearance=1e-7),
    "contact stiffness off its Hertz value": lambda: po.Bearing(stiffness=6e8),
    "slider_mass in g": lambda: po.PressParams(slider_mass=150000.0),
}
GOOD_TOML = """name = "fuzz"
[press]
crank_radius = 0.05
rod_length = 0.25
slider_mass = 150.0
[press.wrist_pin]
clearance = 1e-4
[problem]
stroke_rate_spm = 75
ram_speed = -0.1
window = [0.7, 0.3]
"""


def value(rng: random.Random, default: float):
    """Near `default` (x 0.5 .. 2), or off by orders of magnitude of either sign, or a special value."""
    u = rng.random()
    if u < 0.25:
        return rng.choice(SPECIAL)
    if u < 0.55:
        return default * rng.uniform(0.5, 2.0)
    return default * 10.0 ** rng.uniform(-5, 5) * (-1 if rng.random() < 0.2 else 1)


def some(rng: random.Random, fields: dict) -> dict:
    return {k: value(rng, v) for k, v in fields.items() if rng.random() < 0.3}


#: A scenario key and the problem field it sets, which the problem's own messages name.
ALIASES = {"period_s": "period=", "stroke_rate_spm": "period="}


def names(err: BaseException, given: list[str]) -> bool:
    text = str(err)
    return any(g in text or g.split(".")[-1] in text or ALIASES.get(g.split(".")[-1], "\0") in text for g in given)


def finite_design(problem: po.SpeedProblem) -> bool:
    design = po.design_speed(problem)
    t = np.linspace(0.0, problem.period, 301)
    r = po.rigid_response(problem.press, design.speed, t)
    return all(np.all(np.isfinite(getattr(r, k))) for k in ("torque", "slider_normal_force", "crank_pin_force",
                                                            "wrist_pin_force"))


def api_case(rng: random.Random) -> tuple[str, str]:
    press, pin, prob = some(rng, PRESS), some(rng, BEARING), some(rng, PROBLEM)
    given = [*press, *(f"wrist_pin.{k}" for k in pin), *prob]
    try:
        problem = po.SpeedProblem(po.PressParams(**press, wrist_pin=po.Bearing(**pin)), **prob)
        return ("accepted" if finite_design(problem) else "non-finite"), ""
    except (ValueError, TypeError) as err:
        return ("refused, named" if names(err, given) or not given else "refused, unnamed"), str(err)[:200]
    except Exception as err:  # noqa: BLE001 - the point of the campaign
        return "internal error", f"{type(err).__name__}: {str(err)[:200]}"


def dict_case(rng: random.Random) -> tuple[str, str]:
    base = po.Scenario.load("press75").to_dict()
    given = []
    for _ in range(rng.randint(1, 3)):
        table = rng.choice(["press", "problem", "solver", "model"])
        if not isinstance(base.get(table), dict) or not base[table]:
            continue
        key = rng.choice(list(base[table]))
        old = base[table][key]
        base[table][key] = value(rng, old) if isinstance(old, (int, float)) and not isinstance(old, bool) \
            else rng.choice(SPECIAL + ["abc", {}, [0.1, 0.2, 0.3]])
        given.append(f"{table}.{key}")
    try:
        sc = po.Scenario.from_dict(base, source="fuzz")
        return ("accepted" if finite_design(sc.problem) else "non-finite"), ""
    except (ValueError, TypeError) as err:
        return ("refused, named" if names(err, given) else "refused, unnamed"), str(err)[:200]
    except Exception as err:  # noqa: BLE001
        return "internal error", f"{type(err).__name__}: {str(err)[:200]}"


def toml_file(rng: random.Random, folder: Path) -> tuple[Path, str]:
    """A scenario file with one line mutated (a value, a key, the line dropped) or random bytes; its
    path and the key of the mutated line."""
    lines = GOOD_TOML.splitlines()
    i = rng.choice([k for k, ln in enumerate(lines) if "=" in ln and not ln.startswith("name")])
    key = lines[i].split("=")[0].strip()
    token = rng.choice(["", "nan", "inf", "-1", "1e400", '"x"', "[", "true", "0", "{}", "1e-30", "75.0.0", "= 1"])
    mutation = rng.choice(["value", "key", "drop", "bytes"])
    if mutation == "value":
        lines[i] = f"{key} = {token}"
    elif mutation == "key":
        lines[i] = f"{key}x = 1"
    elif mutation == "drop":
        lines.pop(i)
    path = folder / f"case{rng.randrange(10**9)}.toml"
    if mutation == "bytes":
        path.write_bytes(bytes(rng.randrange(256) for _ in range(rng.randint(1, 200))))
    else:
        path.write_text("\n".join(lines) + "\n")
    return path, key


def toml_case(rng: random.Random, folder: Path) -> tuple[str, str]:
    path, key = toml_file(rng, folder)
    try:
        sc = po.Scenario.load(str(path))
        return ("accepted" if finite_design(sc.problem) else "non-finite"), ""
    except (ValueError, TypeError) as err:
        return ("refused, named" if path.name in str(err) or names(err, [key]) else "refused, unnamed"), \
            str(err)[:200]
    except Exception as err:  # noqa: BLE001
        return "internal error", f"{type(err).__name__}: {str(err)[:200]}"


def cli_case(rng: random.Random, folder: Path) -> tuple[str, str, float]:
    key = rng.choice([f"press.{k}" for k in PRESS] + [f"press.wrist_pin.{k}" for k in BEARING]
                     + ["problem.stroke_rate_spm", "problem.period_s", "problem.ram_speed", "problem.window",
                        "problem.n_harmonics", "problem.objective", "solver.elements", "solver.verify_rtol",
                        "solver.jit", "model.rod", "model.clearance", "press.nothing"])
    token = rng.choice(["nan", "inf", "-1", "0", "1e9", '"x"', "[1,2]", "true", "1e-12", "x"])
    argv = ["design", "--set", f"{key}={token}", "--out", str(folder / "out"), "-q"]
    if rng.random() < 0.3:
        argv += ["--strict"]
    err_text = io.StringIO()
    t0 = time.perf_counter()
    try:
        with contextlib.redirect_stderr(err_text), contextlib.redirect_stdout(io.StringIO()):
            code = cli(argv)
    except SystemExit as exit_:  # argparse
        code = exit_.code
    except Exception as err:  # noqa: BLE001
        return "internal error", f"{type(err).__name__}: {str(err)[:200]}", time.perf_counter() - t0
    seconds = time.perf_counter() - t0
    text = err_text.getvalue()
    if "Traceback" in text or code not in (0, 1, 2):
        return "internal error", text[-300:], seconds
    return classify(code, text, [key]) + (seconds,)


def classify(code: int, text: str, given: list[str]) -> tuple[str, str]:
    """A command line's outcome from its exit code and stderr: exit 0 (and 1 without an error message:
    ran, did not converge) is accepted; exit 2 is a refusal, named when the message names one of
    `given`; exit 1 with an error message is a refusal with the wrong code."""
    if "Traceback" in text or code not in (0, 1, 2):
        return "internal error", text[-300:]
    if code == 0 or (code == 1 and "error:" not in text):
        return "accepted", ""
    if code == 1:
        return "exit 1 on bad input", text.strip()[:200]
    named = any(g in text or g.split(".")[-1] in text or ALIASES.get(g.split(".")[-1], "\0") in text for g in given)
    return ("refused, named" if named else "refused, unnamed"), text.strip()[:200]


def process_case(rng: random.Random, folder: Path) -> tuple[str, str, float]:
    """One generated bad command line run as ``python -m pressocp``; (outcome, message, wall s)."""
    import subprocess
    import sys

    kind = rng.choice(["set", "file", "out", "speed"])
    if kind == "set":
        key = rng.choice([f"press.{k}" for k in PRESS] + ["problem.stroke_rate_spm", "problem.ram_speed",
                                                          "problem.window", "solver.verify_rtol", "solver.elements"])
        token = rng.choice(["nan", "inf", "-1", "0", "1e9", '"x"', "true", "x"])
        argv, given = [rng.choice(["optimize", "simulate", "design"]), "--set", f"{key}={token}"], [key]
    elif kind == "file":
        path, key = toml_file(rng, folder)
        argv, given = ["optimize", str(path)], [path.name, key]
    elif kind == "out":
        blocker = folder / f"afile{rng.randrange(10**6)}"
        blocker.write_text("a file\n")
        argv, given = ["optimize", "press60", "--out", str(blocker / "out")], ["--out"]
    else:
        n, omega = rng.choice([(20, 8.0), (15, -1.0), (3, 7.85)])
        speed = folder / f"speed{rng.randrange(10**6)}.json"
        speed.write_text(json.dumps(po.FourierSpeed(rng.choice([0.8, 1.3]), [omega * 0.9] + [0.0] * (n - 1),
                                                    [0.0] * n).to_dict() | {"a0": omega}))
        argv, given = ["simulate", "press75", "--speed", str(speed)], ["--speed", speed.name]
    argv += ["--out", str(folder / "out"), "-q"] if "--out" not in argv else ["-q"]
    t0 = time.perf_counter()
    try:  # a case still running after SOLVING_S passed every check and is solving: accepted
        done = subprocess.run([sys.executable, "-m", "pressocp", *argv], capture_output=True, text=True,
                              timeout=SOLVING_S, cwd=folder)
    except subprocess.TimeoutExpired:
        return "accepted", "", time.perf_counter() - t0
    seconds = time.perf_counter() - t0
    outcome, message = classify(done.returncode, done.stderr, given)
    if outcome.startswith("refused") and seconds > REFUSAL_LIMIT_S:
        outcome = "refused after 2 s"
    return outcome, message or " ".join(argv[:4]), seconds


def slips() -> dict:
    out = {}
    for what, make in SLIPS.items():
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always", PlausibilityWarning)
            try:
                make()
                caught = [str(w.message) for w in seen if issubclass(w.category, PlausibilityWarning)]
                out[what] = {"outcome": "warned" if caught else "accepted silently", "message": " ".join(caught)[:200]}
            except (ValueError, TypeError) as err:
                out[what] = {"outcome": "refused", "message": str(err)[:200]}
    return out


def plot(data: dict) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    families = list(data["families"])
    fig, ax = plt.subplots(figsize=(8, 3.8))
    left = np.zeros(len(families))
    for k, outcome in enumerate(OUTCOMES):
        n = np.array([data["families"][f]["counts"].get(outcome, 0) for f in families])
        ax.barh(families, n, left=left, color=f"C{[2, 0, 1, 3, 4, 5, 6][k]}", label=outcome)
        left += n
    ax.set_xlabel("cases")
    slipped = sum(v["outcome"] == "accepted silently" for v in data["unit_slips"].values())
    ax.set_title(f"Fuzz campaign, {data['cases']} cases ({data['date'][:10]}); unit slips: "
                 f"{len(data['unit_slips']) - slipped} of {len(data['unit_slips'])} refused or warned", fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    path = OUT / "fuzz.png"
    fig.savefig(path, dpi=130)
    return path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=150, help="cases per family (API, dict, TOML, command line)")
    ap.add_argument("--processes", type=int, default=60, help="cases of the process family (one process each)")
    ap.add_argument("--seed", type=int, default=30)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    families: dict[str, dict] = {}
    t_start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # plausibility warnings are counted in the slips table
        folder = Path(tmp)
        runs = {"API": lambda: api_case(rng), "dict": lambda: dict_case(rng), "TOML": lambda: toml_case(rng, folder),
                "command line": lambda: cli_case(rng, folder), "process": lambda: process_case(rng, folder)}
        for family, run in runs.items():
            counts: dict[str, int] = {}
            examples: dict[str, list[str]] = {}
            slowest = 0.0
            for _ in range(args.processes if family == "process" else args.cases):
                outcome, message, *rest = run()
                counts[outcome] = counts.get(outcome, 0) + 1
                if outcome != "accepted" and len(examples.setdefault(outcome, [])) < 5:
                    examples[outcome].append(message)
                if rest and outcome != "accepted":
                    slowest = max(slowest, rest[0])
            families[family] = {"counts": counts, "examples": examples,
                                **({"slowest_refusal_s": slowest} if family in ("command line", "process") else {})}
            print(family, counts, flush=True)
    data = {**stamp(), "cases": sum(sum(f["counts"].values()) for f in families.values()), "seed": args.seed,
            "wall_time_s": time.perf_counter() - t_start, "families": families, "unit_slips": slips()}
    OUT.mkdir(exist_ok=True)
    (OUT / "fuzz.json").write_text(json.dumps(data, indent=1, default=str) + "\n")
    for what, v in data["unit_slips"].items():
        print(f"{what}: {v['outcome']}")
    print(plot(data))


if __name__ == "__main__":
    main()
