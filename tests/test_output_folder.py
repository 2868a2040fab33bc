"""An output folder holds one complete run (`pressocp.io.output_folder`): a run interrupted before its
commit leaves the previous run, a run killed during its commit is finished by the next reader, and
readers refuse a folder whose files do not match its manifest. The kills are real (a child process
ends itself with ``os._exit`` at the k-th file move); the check is a hash of every file, computed here."""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys

import pytest

from pressocp.io import (COMMIT_NAME, MANIFEST_NAME, STAGING_PREFIX, NotRegularFile, RunMismatch, check_folder,
                         check_run_file, output_folder)

#: A child that writes a run of `files` (name -> text) into `out`, killing itself at the k-th move of
#: the commit (k < 0: never). Moves are `pressocp.io.place` calls.
CHILD = """
import json, os, sys
import pressocp.io as io
out, files, k = sys.argv[1], json.loads(sys.argv[2]), int(sys.argv[3])
real, n = io.place, [0]
def place(src, dst):
    if n[0] == k:
        os._exit(9)
    n[0] += 1
    real(src, dst)
io.place = place
with io.output_folder(out) as folder:
    for name, text in files.items():
        (folder / name).write_text(text)
"""

OLD = {"summary.json": '{"run": "old"}', "result.json": '{"x": 1}', "old_only.png": "old figure"}
NEW = {"summary.json": '{"run": "new"}', "result.json": '{"x": 2}', "new_only.png": "new figure"}


def write_run(out, files, kill_at=-1):
    return subprocess.run([sys.executable, "-c", CHILD, str(out), json.dumps(files), str(kill_at)]).returncode


def contents(out):
    """The folder's visible files and their text, hashed by this test (not by the code under test)."""
    return {p.name: p.read_text() for p in out.iterdir()
            if p.is_file() and not p.name.startswith(".") and p.name != MANIFEST_NAME}


# 3 files + the manifest: 4 moves; 4 = not killed. The kills between the first and the last move: slow
# (3-7 s each, a process killed); by default the first move and none
@pytest.mark.parametrize("kill_at", [0, *(pytest.param(k, marks=pytest.mark.slow) for k in (1, 2, 3)), 4])
def test_a_run_killed_during_its_commit_is_finished_by_the_next_reader(tmp_path, kill_at):
    out = tmp_path / "out"
    assert write_run(out, OLD) == 0
    assert contents(out) == OLD
    code = write_run(out, NEW, kill_at)
    assert code == (9 if kill_at < 4 else 0)
    assert (out / COMMIT_NAME).exists() == (kill_at < 4)  # the commit had begun: the run counts as written
    manifest = check_folder(out)  # finishes the commit
    assert contents(out) == NEW and not (out / COMMIT_NAME).exists()
    assert {n: hashlib.sha256(t.encode()).hexdigest() for n, t in NEW.items()} == manifest["files"]


def test_a_run_killed_before_its_commit_leaves_the_previous_run(tmp_path):
    out = tmp_path / "out"
    assert write_run(out, OLD) == 0
    before = check_folder(out)
    child = subprocess.Popen([sys.executable, "-c", "import sys, time\nimport pressocp.io as io\n"
                              "with io.output_folder(sys.argv[1]) as f:\n    (f / 'result.json').write_text('half')\n"
                              "    print('writing', flush=True)\n    time.sleep(60)\n", str(out)],
                             stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "writing"
    child.kill()
    child.wait()
    assert list(out.glob(STAGING_PREFIX + "*"))  # its staging folder is left
    assert check_folder(out) == before and contents(out) == OLD
    with output_folder(out) as folder:  # the next run removes it
        (folder / "summary.json").write_text("{}")
    assert not list(out.glob(STAGING_PREFIX + "*")) and contents(out) == {"summary.json": "{}"}


def test_an_exception_or_ctrl_c_inside_the_run_leaves_the_previous_run(tmp_path):
    out = tmp_path / "out"
    assert write_run(out, OLD) == 0
    for error in (RuntimeError("solver died"), KeyboardInterrupt()):
        with pytest.raises(type(error)):
            with output_folder(out) as folder:
                (folder / "result.json").write_text("half")
                raise error
        assert contents(out) == OLD and not list(out.glob(".pressocp-run*"))
        check_folder(out)


def test_readers_refuse_a_folder_that_does_not_match_its_manifest(tmp_path):
    from pressocp import OcpResult
    from pressocp.jobs import read_speed

    out = tmp_path / "out"
    assert write_run(out, {**NEW, "speed.json": "{}"}) == 0
    check_run_file(out / "result.json")
    (out / "summary.json").write_text('{"run": "edited"}')
    with pytest.raises(RunMismatch, match=r"changed summary.json"):
        check_folder(out)
    with pytest.raises(RunMismatch, match="does not hold the run its manifest.json lists"):
        OcpResult.from_json(out / "result.json")
    with pytest.raises(ValueError, match="^--speed: .*changed summary.json"):
        read_speed(out / "speed.json")
    (out / "summary.json").write_text('{"run": "new"}')
    (out / "new_only.png").unlink()
    with pytest.raises(RunMismatch, match="missing new_only.png"):
        check_folder(out)
    (out / "loose.json").write_text("{}")  # a file the manifest does not list is read as is
    check_run_file(out / "loose.json")
    (out / MANIFEST_NAME).write_text("not json")
    with pytest.raises(RunMismatch, match="cannot be read"):
        check_run_file(out / "result.json")


def test_a_folder_in_place_of_a_file_is_refused_before_anything_moves(tmp_path):
    out = tmp_path / "out"
    assert write_run(out, OLD) == 0
    (out / "new_only.png").mkdir()
    with pytest.raises(NotRegularFile, match="this run's files are in"):
        with output_folder(out) as folder:
            for name, text in NEW.items():
                (folder / name).write_text(text)
    assert contents(out) == OLD and check_folder(out)
    kept = [p for p in out.iterdir() if p.name.startswith("pressocp-run-")]
    assert len(kept) == 1 and (kept[0] / "result.json").read_text() == NEW["result.json"]


def test_the_command_line_refuses_an_out_whose_file_is_a_folder_before_solving(tmp_path, capsys):
    from pressocp.cli import main

    out = tmp_path / "out"
    (out / "results.csv").mkdir(parents=True)
    assert main(["design", "--out", str(out), "-q"]) == 2
    assert "--out: " in capsys.readouterr().err and os.listdir(out) == ["results.csv"]
