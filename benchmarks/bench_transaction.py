"""An output folder is one complete run: Ctrl-C (SIGINT) and SIGKILL at random moments of
``pressocp optimize`` into a used ``--out``, and two runs at once on one folder.

    python benchmarks/bench_transaction.py [--trials N] [--scenario press60] [--seed S]

A first run fills the folder. Each trial then starts the same command into it, waits a random time
(uniform over 1.1 x the first run's wall time, so some runs finish before the signal) and sends
SIGINT or SIGKILL (alternately): SIGINT to the process group, as Ctrl-C in a terminal; SIGKILL to
the process alone, whose worker processes must then end too (a run waits at most 120 s for them,
and counts them as outliving it otherwise). Afterwards the folder is read as a user's script would, with this
file's own check (not the package's): the manifest's every file present with its SHA-256, and no
other visible file but a marker the user left. Outcomes:

* ``old run``: the run there before the trial, complete (the signal came before the commit);
* ``new run``: the trial's run, complete (it had committed);
* ``commit pending``: a killed commit left ``.pressocp-commit``; ``pressocp.io.check_folder``
  finishes it, and the folder is then checked again (it must be the new run);
* ``mixed``: anything else (files of two runs, a missing or changed file): a failure.

The concurrent case starts two runs at once: one must be refused (exit 2, a message naming the
holder) within 2 s, the other must finish. Writes results/transaction.json and results/transaction.png. A Ctrl-C must end a run with exit 130
(0 when it came after the run's end; -2 during Python's own start-up) and no worker's traceback;
``--sigint-window`` aims the Ctrl-C trials at one part of the run.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pressocp.report import stamp
from status import figure_note  # a sibling script: this folder is the script's path

OUT = Path(__file__).parent / "results"
OUTCOMES = ("old run", "new run", "commit pending", "mixed")
MARKER = "notes.txt"


def command(scenario: str, out: Path) -> list[str]:
    return [sys.executable, "-m", "pressocp", "optimize", scenario, "--out", str(out), "--quiet"]


def folder_state(out: Path) -> tuple[str | None, str]:
    """(run id, "complete" or what is wrong), from the manifest and hashes computed here."""
    if (out / ".pressocp-commit").exists():
        return None, "commit pending"
    try:
        manifest = json.loads((out / "manifest.json").read_text())
    except (OSError, ValueError) as err:
        return None, f"no readable manifest ({err})"
    files = manifest["files"]
    bad = [n for n, h in files.items()
           if not (out / n).is_file() or hashlib.sha256((out / n).read_bytes()).hexdigest() != h]
    extra = [p.name for p in out.iterdir()
             if not p.name.startswith(".") and p.name not in files and p.name not in ("manifest.json", MARKER)]
    if bad or extra:
        return manifest.get("run_id"), f"differs: {bad} not as listed, {extra} not listed"
    if json.loads((out / "summary.json").read_text()).get("job") != "optimize":
        return manifest.get("run_id"), "summary.json is not an optimize run's"
    return manifest["run_id"], "complete"


def trial(scenario: str, out: Path, delay: float, sig: signal.Signals, before: str) -> dict:
    """One run into `out`, `sig` after `delay` s; the folder's state afterwards."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(command(scenario, out), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        proc.wait(timeout=delay)
    except subprocess.TimeoutExpired:
        if sig == signal.SIGINT:
            os.killpg(proc.pid, sig)  # as Ctrl-C in a terminal: the process and its workers
        else:
            proc.send_signal(sig)  # as kill -9 or the OOM killer: the process alone; its workers must follow
    try:
        _, err = proc.communicate(timeout=120)
        orphans = False
    except subprocess.TimeoutExpired:  # the stderr pipe held open by workers that outlived the run
        orphans = True
        os.killpg(proc.pid, signal.SIGKILL)
        _, err = proc.communicate()
    row = {"signal": sig.name, "delay_s": delay, "exit": proc.returncode, "run_s": time.perf_counter() - t0,
           "message": err.strip().splitlines()[-1] if err.strip() else "", "workers_outlived_run": orphans}
    run, state = folder_state(out)
    if state == "commit pending":
        from pressocp.io import check_folder

        check_folder(out)  # finishes the commit a kill interrupted
        run, state = folder_state(out)
        row["outcome"] = "commit pending" if state == "complete" and run != before else "mixed"
    elif state == "complete":
        row["outcome"] = "old run" if run == before else "new run"
    else:
        row["outcome"] = "mixed"
    # a Ctrl-C during the interpreter's start-up ends in Python's own KeyboardInterrupt traceback (exit
    # -2), before the package can catch it; any other traceback is a failure
    startup = proc.returncode == -signal.SIGINT and err.strip().endswith("KeyboardInterrupt")
    worker = "concurrent/futures/process.py" in err and "KeyboardInterrupt" in err
    row.update(state=state, run_id=run, traceback="Traceback" in err and not startup and not worker,
               startup_interrupt=startup, worker_tracebacks=worker)
    if row["traceback"] or proc.returncode not in (0, 130, -signal.SIGINT):
        row["stderr_tail"] = err[-4000:]  # where it failed, for the record
    return row


def holds(out: Path, pid: int) -> bool:
    """Whether the folder's owner file names process `pid`."""
    try:
        return json.loads((out / ".pressocp.owner").read_text())["pid"] == pid
    except (OSError, ValueError, KeyError):
        return False


def concurrent(scenario: str, out: Path) -> dict:
    """Two runs started together on `out`: one refused (exit 2, naming the holder), one finishing."""
    t0 = time.perf_counter()
    first = subprocess.Popen(command(scenario, out), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    while not holds(out, first.pid) and first.poll() is None and time.perf_counter() - t0 < 60:
        time.sleep(0.05)  # until the first holds the folder (an owner file a killed run left names another)
    t1 = time.perf_counter()
    second = subprocess.run(command(scenario, out), capture_output=True, text=True, timeout=120)
    refused_s = time.perf_counter() - t1
    _, err_first = first.communicate(timeout=600)
    run, state = folder_state(out)
    return {"first_exit": first.returncode, "first_message": err_first.strip()[-300:],
            "second_exit": second.returncode, "second_refused_after_s": refused_s,
            "second_message": second.stderr.strip(), "names_holder": f"process {first.pid} " in second.stderr,
            "first_run_s": time.perf_counter() - t0, "folder_afterwards": state,
            "ok": second.returncode == 2 and f"process {first.pid} " in second.stderr and refused_s < 2.0
            and first.returncode == 0 and state == "complete"}


def plot(data: dict) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 3.2))
    colors = {"old run": "C0", "new run": "C2", "commit pending": "C1", "mixed": "C3"}
    for k, sig in enumerate(("SIGINT", "SIGKILL")):
        for outcome, color in colors.items():
            d = [r["delay_s"] for r in data["trials"] if r["signal"] == sig and r["outcome"] == outcome]
            ax.scatter(d, [k] * len(d), color=color, s=40, label=outcome if k == 0 or not d else None,
                       marker="o" if sig == "SIGINT" else "x")
    ax.axvline(data["reference_run_s"], color="k", lw=0.8, ls="--")
    ax.text(data["reference_run_s"], 1.35, " a whole run", fontsize=7, va="center")
    ax.set_yticks([0, 1], ["SIGINT", "SIGKILL"])
    ax.set_ylim(-0.6, 1.6)
    ax.set_xlabel("signal sent after, s")
    counts = {o: sum(r["outcome"] == o for r in data["trials"]) for o in OUTCOMES}
    ax.set_title(f"pressocp optimize {data['scenario']} into a used --out, {len(data['trials'])} trials "
                 f"({data['date'][:10]}): " + ", ".join(f"{o} {n}" for o, n in counts.items()), fontsize=8)
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    ax.legend(uniq.values(), uniq.keys(), fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.tight_layout()
    figure_note(fig, data)
    path = OUT / "transaction.png"
    fig.savefig(path, dpi=130)
    return path


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=20, help="signals sent, SIGINT and SIGKILL alternately")
    ap.add_argument("--scenario", default="press60")
    ap.add_argument("--seed", type=int, default=30)
    ap.add_argument("--sigint-window", type=float, nargs=2, metavar=("FROM_S", "TO_S"),
                    help="SIGINT only, sent between these times (e.g. 2 6: press60's compiles and links); "
                         "writes results/transaction_sigint.json, no figure")
    args = ap.parse_args()
    # a process a shell starts in the background (``cmd &``) ignores SIGINT, and so would the runs
    # started here: SIGINT is given its terminal default back, which the runs inherit
    signal.signal(signal.SIGINT, signal.default_int_handler)
    rng = random.Random(args.seed)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        out.mkdir()
        (out / MARKER).write_text("the user's own file: every run must leave it\n")
        t0 = time.perf_counter()
        first = subprocess.run(command(args.scenario, out), capture_output=True, text=True)
        reference = time.perf_counter() - t0
        run, state = folder_state(out)
        if first.returncode != 0 or state != "complete":
            raise SystemExit(f"the first run failed (exit {first.returncode}, folder {state}): {first.stderr[-2000:]}")
        print(f"first run {reference:.1f} s, {run}", flush=True)
        trials = []
        for i in range(args.trials):
            sig = signal.SIGINT if args.sigint_window else (signal.SIGINT, signal.SIGKILL)[i % 2]
            lo, hi = args.sigint_window or (0.0, 1.1 * reference)
            row = trial(args.scenario, out, rng.uniform(lo, hi), sig, run)
            trials.append(row)
            run = row["run_id"] or run
            print(f"{i + 1:2d} {sig.name:7s} after {row['delay_s']:5.1f} s: exit {row['exit']}, {row['outcome']}"
                  f" ({row['message'][:100]})", flush=True)
            if not (out / MARKER).exists():
                raise SystemExit("the user's own file was removed")
        both = concurrent(args.scenario, out)
        print(f"concurrent: second exit {both['second_exit']} after {both['second_refused_after_s']:.2f} s, "
              f"names holder {both['names_holder']}; folder {both['folder_afterwards']}", flush=True)
        leftovers = sorted(p.name for p in out.iterdir() if p.name.startswith(".pressocp-run"))
    data = {**stamp(), "scenario": args.scenario, "seed": args.seed, "reference_run_s": reference,
            "trials": trials, "outcomes": {o: sum(r["outcome"] == o for r in trials) for o in OUTCOMES},
            "exit_codes": {str(c): sum(r["exit"] == c for r in trials) for c in sorted({r["exit"] for r in trials})},
            "tracebacks": sum(r["traceback"] for r in trials), "staging_left_at_end": leftovers,
            "concurrent": both, "median_run_s": float(np.median([r["run_s"] for r in trials])),
            "sigint_window_s": args.sigint_window,
            "workers_outlived_run": sum(r["workers_outlived_run"] for r in trials),
            "startup_interrupts": sum(r["startup_interrupt"] for r in trials),
            "worker_tracebacks": sum(r["worker_tracebacks"] for r in trials),
            # a Ctrl-C ends a run with 130, or 0 when it came after the run's end, or -2 in Python's start-up
            "ctrl_c_other_exits": sum(r["signal"] == "SIGINT" and r["exit"] not in (130, 0, -signal.SIGINT)
                                      for r in trials)}
    OUT.mkdir(exist_ok=True)
    name = "transaction_sigint.json" if args.sigint_window else "transaction.json"
    (OUT / name).write_text(json.dumps(data, indent=1) + "\n")
    if not args.sigint_window:
        print(plot(data))
    failed = (data["outcomes"]["mixed"] or data["tracebacks"] or not both["ok"] or data["workers_outlived_run"]
              or data["ctrl_c_other_exits"] or data["worker_tracebacks"])
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
