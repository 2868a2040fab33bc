"""`python -m benchmarks`: runs each benchmark as its own process, records every run, rewrites its own
table in benchmarks/README.md (and nothing else there), and reports failures without stopping."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import benchmarks.__main__ as runner

ROOT = Path(__file__).resolve().parents[1]


def test_every_benchmark_script_exists():
    for job in runner.JOBS:
        assert (ROOT / "benchmarks" / job.script).is_file(), job.script


def test_runs_are_recorded_and_the_table_rewritten(tmp_path, monkeypatch, capsys):
    results = tmp_path / "results"
    results.mkdir()
    readme = tmp_path / "README.md"
    readme.write_text("# Benchmarks\n\nA hand-written table.\n")
    (tmp_path / "ok.py").write_text("from pathlib import Path\n"
                                    "(Path(__file__).parent / 'results' / 'x.json').write_text('{}')\n")
    (tmp_path / "bad.py").write_text("raise SystemExit(3)\n")
    (results / "same.json").write_text("[1]")
    (results / "resumed.csv").write_text("a point of an earlier run\n")
    (tmp_path / "arch.py").write_text("from pathlib import Path\n"
                                      "(Path(__file__).parent / 'results' / 'a.json').write_text('{}')\n")
    (tmp_path / "same.py").write_text("from pathlib import Path\n"
                                      "(Path(__file__).parent / 'results' / 'same.json').write_text('[1]')\n")
    monkeypatch.setattr(runner, "calibrate", lambda: 0.5)  # the real one starts CasADi in a process per job
    for name, value in (("HERE", tmp_path), ("RESULTS", results), ("README", readme), ("RUNS", results / "runs.json"),
                        ("JOBS", (runner.Job("ok", "ok.py", (), 0.1, "writes x.json", fresh=("resumed.csv",)),
                                  runner.Job("bad", "bad.py", ("--flag",), 0.1, "fails"),
                                  runner.Job("same", "same.py", (), 0.1, "rewrites a file unchanged"),
                                  runner.Job("arch", "arch.py", (), 0.1, "archived", archive=True)))):
        monkeypatch.setattr(runner, name, value)
    assert runner.main([]) == 1  # a failure is reported, after every job ran
    runs = json.loads((results / "runs.json").read_text())
    assert runs["ok"]["exit_status"] == 0 and runs["ok"]["files"] == ["x.json"]
    assert runs["same"]["exit_status"] == 0 and runs["same"]["files"] == []  # rewritten, unchanged
    assert runs["bad"]["exit_status"] == 3 and runs["bad"]["command"] == "bad.py --flag"
    assert {"date", "machine", "cpus", "wall_time_s"} <= set(runs["ok"]) and runs["ok"]["calibration_s"] == 0.5
    assert not (results / "resumed.csv").exists() and "arch" not in runs and not (results / "a.json").exists()
    suite = runs[runner.SUITE]  # the whole suite's run, the archive left out
    assert suite["jobs"] == 3 and suite["failed"] == ["bad"] and suite["budget_min"] == pytest.approx(0.3)
    text = readme.read_text()
    assert "Last run of the whole suite: " in text and "failed or over budget: bad." in text
    assert "| arch (archive) | `arch.py` | not run by this command yet" in text
    assert text.startswith("# Benchmarks\n\nA hand-written table.\n")
    assert text.count(runner.BEGIN) == 1 and "**failed (3)**" in text and "`x.json`" in text
    assert text.count(runner.goal_status.BEGIN) == 1 and "| #28 |" in text  # the goals, from tmp_path's results
    assert (results / "logs" / "ok.log").exists()
    total = sum(runs[k]["wall_time_s"] for k in ("ok", "bad", "same")) / 60  # the archived job is left out
    assert f"Suite: the latest runs of 3 of the 3 benchmarks add up to {total:.0f} min (budgets 0.3 min; run " in text
    assert runner.main(["--only", "ok"]) == 0  # rewritten in place, the failed run still listed
    again = readme.read_text()
    assert again.count(runner.BEGIN) == 1 and "**failed (3)**" in again
    runs = json.loads((results / "runs.json").read_text())
    assert runs[runner.SUITE] == suite  # a part of the suite is not a run of it
    assert runner.main(["--archive"]) == 0 and (results / "a.json").exists()
    runs = json.loads((results / "runs.json").read_text())
    assert runs["arch"]["exit_status"] == 0 and runs[runner.SUITE] == suite
    capsys.readouterr()
    assert runner.main(["--list"]) == 0  # each job's latest run, and what they add up to
    listed = capsys.readouterr().out
    assert "not run yet" not in listed and listed.count("last ") == 3
    assert "3 benchmarks on 2 cores: the latest runs of 3 of the 3 benchmarks add up to" in listed
    runs["bad"]["note"] = "stopped by hand"
    assert "**failed (3)**: stopped by hand |" in runner.table(runs)


def test_a_job_over_its_budget_is_stopped_and_recorded(tmp_path, monkeypatch):
    """A job that runs past budget_factor x its budget is killed (with its process group) and recorded
    as over budget; the table says so, and the command exits 1."""
    results = tmp_path / "results"
    results.mkdir()
    (tmp_path / "README.md").write_text("# Benchmarks\n")
    finished = tmp_path / "finished"
    (tmp_path / "slow.py").write_text(f"import pathlib, time\ntime.sleep(60)\npathlib.Path({str(finished)!r}).touch()\n")
    monkeypatch.setattr(runner, "calibrate", lambda: None)  # a failed calibration is recorded as None
    for name, value in (("HERE", tmp_path), ("RESULTS", results), ("README", tmp_path / "README.md"),
                        ("RUNS", results / "runs.json"), ("JOBS", (runner.Job("slow", "slow.py", (), 0.01, "sleeps"),))):
        monkeypatch.setattr(runner, name, value)
    assert runner.main(["--budget-factor", "2"]) == 1  # 1.2 s allowed
    run = json.loads((results / "runs.json").read_text())["slow"]
    assert run["over_budget"] and run["exit_status"] == runner.OVER_BUDGET and not finished.exists()
    assert "**over budget**" in (tmp_path / "README.md").read_text()
    assert "stopped after" in (results / "logs" / "slow.log").read_text()


def test_sigterm_stops_the_running_job_with_the_command(tmp_path):
    """`kill PID` on the runner stops its job too: the job runs in its own session, so without the
    handler it would run on, orphaned, and nothing would record it."""
    results = tmp_path / "results"
    results.mkdir()
    (tmp_path / "README.md").write_text("# Benchmarks\n")
    started, finished = tmp_path / "started", tmp_path / "finished"
    (tmp_path / "slow.py").write_text(f"import os, pathlib, time\npathlib.Path({str(started)!r}).write_text(str(os.getpid()))\n"
                                      f"time.sleep(60)\npathlib.Path({str(finished)!r}).touch()\n")
    script = f"""
import sys
sys.path.insert(0, {str(ROOT)!r})
from pathlib import Path
import benchmarks.__main__ as runner
here = Path({str(tmp_path)!r})
runner.calibrate = lambda: None
runner.HERE, runner.RESULTS, runner.README = here, here / "results", here / "README.md"
runner.RUNS = here / "results" / "runs.json"
runner.JOBS = (runner.Job("slow", "slow.py", (), 5, "sleeps"),)
runner.stop_on_sigterm()
sys.exit(runner.main([]))
"""
    proc = subprocess.Popen([sys.executable, "-c", script], cwd=ROOT)
    deadline = time.monotonic() + 60
    while not started.exists() or not started.read_text():
        assert time.monotonic() < deadline and proc.poll() is None
        time.sleep(0.1)
    job = int(started.read_text())
    proc.terminate()
    assert proc.wait(timeout=30) == 128 + signal.SIGTERM
    deadline = time.monotonic() + 10
    while True:  # the job's process group was killed and the runner reaped it: the job is gone
        try:
            os.kill(job, 0)
        except ProcessLookupError:
            break
        assert time.monotonic() < deadline, "the job runs on after its runner was stopped"
        time.sleep(0.1)
    assert not finished.exists()


def test_the_calibration_runs():
    """The machine's calibration workload runs in a fresh process and takes a positive time."""
    assert runner.calibrate() > 0.0


#: Run in one fresh process: imports what every benchmark script imports (CasADi, the package,
#: matplotlib), then forks a child per job that runs the job's script as ``python SCRIPT ARGS --help``
#: would (`runpy`, ``__main__``, the script's folder first on sys.path), its output to files. Prints
#: each job's exit status and output as JSON: one start-up instead of one per job (4 s each).
PARSE_ALL = """
import json, os, runpy, sys, tempfile
import matplotlib.pyplot, pressocp, pressocp.plots  # what each child would import again
jobs, out = json.loads(sys.argv[1]), {}
for name, argv in jobs.items():
    with tempfile.TemporaryFile() as so, tempfile.TemporaryFile() as se:
        sys.stdout.flush(); sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            code = 1
            try:
                os.dup2(so.fileno(), 1); os.dup2(se.fileno(), 2)
                sys.argv, sys.path[0] = [argv[0], *argv[1:], "--help"], os.path.dirname(argv[0])
                runpy.run_path(argv[0], run_name="__main__")
                code = 0
            except SystemExit as stop:
                code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
            except BaseException:
                import traceback; traceback.print_exc()
            finally:
                sys.stdout.flush(); sys.stderr.flush()
                os._exit(code)
        status = os.waitpid(pid, 0)[1]
        so.seek(0); se.seek(0)
        out[name] = {"returncode": os.waitstatus_to_exitcode(status), "stdout": so.read().decode(errors="replace"),
                     "stderr": se.read().decode(errors="replace")}
sys.stdout.write(json.dumps(out))
"""


@pytest.fixture(scope="module")
def parsed():
    """Each job's ``SCRIPT ARGS --help`` (`PARSE_ALL`): name -> exit status, stdout, stderr."""
    jobs = {job.name: job.command()[1:] for job in runner.JOBS}
    done = subprocess.run([sys.executable, "-c", PARSE_ALL, json.dumps(jobs)], capture_output=True, text=True,
                          timeout=600, cwd=ROOT, env={**os.environ, "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout)


@pytest.mark.parametrize("job", runner.JOBS, ids=lambda job: job.name)
def test_every_benchmark_command_parses(job, parsed):
    """Each job's script imports and accepts the job's arguments (``--help`` after them: argparse checks
    what comes before it, then exits), so a renamed function or option fails here, not hours into
    ``python -m benchmarks``."""
    done = parsed[job.name]
    assert done["returncode"] == 0, done["stderr"][-2000:]
    assert "usage:" in done["stdout"]


def test_a_broken_command_fails_the_parse_check(tmp_path):
    """The one-process check fails a job whose script raises on import or refuses an argument's value, as a
    process of its own would, and the next job still runs."""
    (tmp_path / "broken.py").write_text("import no_such_module_here\n")
    (tmp_path / "strict.py").write_text("import argparse\nap = argparse.ArgumentParser()\n"
                                        "ap.add_argument('--cases', type=int)\nap.parse_args()\n")
    (tmp_path / "fine.py").write_text("import argparse\nargparse.ArgumentParser().parse_args()\n")
    jobs = {"broken": [str(tmp_path / "broken.py")], "strict": [str(tmp_path / "strict.py"), "--cases", "many"],
            "fine": [str(tmp_path / "fine.py")]}
    done = subprocess.run([sys.executable, "-c", PARSE_ALL, json.dumps(jobs)], capture_output=True, text=True,
                          timeout=120, env={**os.environ, "MPLBACKEND": "Agg"})
    out = json.loads(done.stdout)
    assert out["broken"]["returncode"] != 0 and "no_such_module_here" in out["broken"]["stderr"]
    assert out["strict"]["returncode"] == 2 and "--cases" in out["strict"]["stderr"]
    assert out["fine"]["returncode"] == 0 and "usage:" in out["fine"]["stdout"]
