"""Writing result files: atomically (temporary file in the same folder, then rename), so a run never
leaves a half-written file, and JSON with numpy values.

An output folder holds one complete run (`output_folder`). A run writes its files into a staging
folder inside ``--out`` and only then commits them: the staging folder is renamed to `COMMIT_NAME`
(one atomic step: from here the run counts as written), its files are moved in, the previous run's
files it does not replace are removed, and its `MANIFEST_NAME` (every file with its SHA-256 and the
run id) is moved in last. A process killed during those moves leaves `COMMIT_NAME` behind, and the
next run or reader finishes them (`recover`): the folder is then the complete new run. A run
interrupted before its commit leaves the previous run untouched. Readers (`check_folder`) refuse a
folder whose files do not match its manifest."""

from __future__ import annotations

import hashlib
import json
import os
import platform
import shutil
import sys
import tempfile
import time
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from .interrupt import interrupt_deferred


#: Lock file of an output folder while a run writes into it.
LOCK_NAME = ".pressocp.lock"
#: The file a job writes last among its own (its report): the run's files, its status, its peaks.
SUMMARY_NAME = "summary.json"
#: The file a run's commit places last: every file of the run with its SHA-256 and the run id.
MANIFEST_NAME = "manifest.json"
#: The file beside the lock that names the run holding it (process, host, start, command).
OWNER_NAME = ".pressocp.owner"
#: A run's staging folder inside the output folder, renamed to `COMMIT_NAME` when it commits.
STAGING_PREFIX = ".pressocp-run-"
#: A run being committed (its files being moved into the folder); finished by `recover`.
COMMIT_NAME = ".pressocp-commit"
#: Seconds a reader waits for a run that is committing (its moves take milliseconds).
COMMIT_WAIT_S = 10.0


class OutputBusy(ValueError):
    """Another run is writing into the output folder."""


class RunMismatch(ValueError):
    """A folder's files do not match its manifest: changed after the run, or parts of two runs."""


def run_id() -> str:
    """A new run's id: its start time and a random suffix ("20261125T160102-1a2b3c4d")."""
    return f"{time.strftime('%Y%m%dT%H%M%S')}-{uuid.uuid4().hex[:8]}"


def acquire(out: Path, timeout: float = 0.0):
    """`out`'s lock (`LOCK_NAME`, a `filelock.FileLock`), acquired; `OutputBusy`, naming the holder,
    when another process holds it after `timeout` seconds."""
    from filelock import FileLock, Timeout

    lock = FileLock(str(out / LOCK_NAME))
    try:
        lock.acquire(timeout=timeout)
    except Timeout:
        raise OutputBusy(f"{out} is being written by another pressocp run{lock_holder(out)} (lock file "
                         f"{out / LOCK_NAME}): wait for it to end, or pass another --out") from None
    return lock


def refuse_if_busy(out: Path) -> None:
    """`OutputBusy`, naming the holder, when another run holds the folder `out` now; nothing when it
    is free or has no lock file (nothing is created). A job checks this before it reads its input,
    so that a second run into a busy folder is refused at once (`output_folder` takes the lock for
    the run itself)."""
    if (out / LOCK_NAME).is_file():
        acquire(out).release()


@contextmanager
def hold(out: Path, timeout: float = 0.0) -> Iterator[None]:
    """Hold the output folder `out`'s lock (a `filelock` lock file, `LOCK_NAME`, released when the
    holder ends or dies) and name the holder in `OWNER_NAME`. Raises `OutputBusy`, naming the holder,
    when another process holds it after `timeout` seconds."""
    lock = acquire(out, timeout)
    try:
        atomic_write(out / OWNER_NAME, json.dumps({"pid": os.getpid(), "host": platform.node(),
                                                   "started": time.strftime("%Y-%m-%d %H:%M:%S"),
                                                   "command": " ".join(sys.argv)}) + "\n")
        yield
    finally:
        (out / OWNER_NAME).unlink(missing_ok=True)
        lock.release()


@contextmanager
def output_folder(out: str | Path, transaction: bool = True) -> Iterator[Path]:
    """The output folder `out` (created), held by this run: a second run into it is refused
    (`OutputBusy`, `hold`).

    With `transaction` (every job but a sweep) this yields a fresh staging folder inside `out` to
    write into; when the block ends normally, its files are committed (`commit`) as one run that
    replaces the previous one, and when it raises (an error, Ctrl-C) the staging folder is removed
    and the previous run stays as it was. Staging folders of killed runs are removed on entry.
    Without `transaction` (a sweep, which resumes from its own partial sweep.csv) this yields `out`
    itself; the caller writes its manifest (`write_manifest`) when done."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    with hold(out):
        recover(out, locked=True)
        for stale in out.glob(STAGING_PREFIX + "*"):
            shutil.rmtree(stale, ignore_errors=True)
        if not transaction:
            yield out
            return
        staging = out / f"{STAGING_PREFIX}{run_id()}"
        staging.mkdir()
        try:
            yield staging
            try:
                commit(staging, out)
            except NotRegularFile as err:  # raised before anything moved: keep the run's files
                kept = out / staging.name.lstrip(".")
                os.replace(staging, kept)
                raise NotRegularFile(f"{err}; this run's files are in {kept}") from None
        finally:
            shutil.rmtree(staging, ignore_errors=True)


def staging_run_id(staging: Path) -> str:
    """The run id of a staging folder (`output_folder`'s)."""
    return staging.name.removeprefix(STAGING_PREFIX)


def lock_holder(out: Path) -> str:
    """", process 1234 on host, started 2026-11-25 15:20:00: pressocp optimize ..." from the folder's
    `OWNER_NAME`, or "" when it cannot be read."""
    try:
        o = json.loads((out / OWNER_NAME).read_text())
        return f", process {o['pid']} on {o['host']}, started {o['started']}: {o['command']}"
    except (OSError, ValueError, KeyError, TypeError):
        return ""


def sha256(path: str | Path) -> str:
    """The SHA-256 of a file's bytes, as hex."""
    with open(path, "rb") as f:
        return hashlib.file_digest(f, "sha256").hexdigest()


def manifest_of(folder: Path, run: str, names: list[str] | None = None) -> dict:
    """The manifest of the run whose files are `names` in `folder` (default: every regular file in it
    but the manifest)."""
    if names is None:
        names = sorted(p.name for p in folder.iterdir() if p.is_file() and not p.name.startswith(".pressocp"))
    files = {n: sha256(folder / n) for n in sorted(set(names)) if n != MANIFEST_NAME}
    return {"run_id": run, "written": time.strftime("%Y-%m-%d %H:%M:%S"), "files": files}


def write_manifest(folder: Path, run: str, names: list[str]) -> Path:
    """Write `folder`'s manifest for a run written in place (a sweep): `names` with their hashes."""
    return write_json(folder / MANIFEST_NAME, manifest_of(folder, run, names))


def read_manifest(folder: Path) -> dict | None:
    """`folder`'s manifest, or None when it has none. Raises `RunMismatch` when it cannot be read."""
    path = folder / MANIFEST_NAME
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as err:
        raise RunMismatch(f"{path} cannot be read ({err}): the folder holds no checkable run") from None
    if not (isinstance(data, dict) and isinstance(data.get("files"), dict)
            and all(isinstance(k, str) and isinstance(v, str) for k, v in data["files"].items())):
        raise RunMismatch(f"{path} is not a pressocp manifest (expected run_id and files)")
    return data


def previous_files(out: Path) -> list[str]:
    """The files of the run `out` holds: its manifest's, else (a folder written before manifests)
    those its summary lists; plain names only, never a path out of the folder."""
    try:
        manifest = read_manifest(out)
    except RunMismatch:
        manifest = None
    if manifest is not None:
        names = list(manifest["files"]) + [MANIFEST_NAME]
    else:
        try:
            names = json.loads((out / SUMMARY_NAME).read_text()).get("files", [])
        except (OSError, ValueError, AttributeError):
            return []
        names = [*names, SUMMARY_NAME] if isinstance(names, list) else []
    return [n for n in dict.fromkeys(names) if isinstance(n, str) and Path(n).name == n and n not in ("", ".", "..")]


def commit(staging: Path, out: Path) -> None:
    """Commit the run in `staging` into `out` (whose lock the caller holds): write its manifest, check
    that no file it replaces is a folder or device (else raise before moving anything), rename it to
    `COMMIT_NAME` and finish the moves (`roll_forward`). Ctrl-C waits for the end of the commit."""
    manifest = manifest_of(staging, staging_run_id(staging))
    write_json(staging / MANIFEST_NAME, manifest)
    for name in [*manifest["files"], MANIFEST_NAME]:
        try:
            check_regular(out / name)
        except NotRegularFile as err:
            raise NotRegularFile(f"{err}; the run's files were not placed, the folder keeps its previous run") from None
    with interrupt_deferred():
        shutil.rmtree(out / COMMIT_NAME, ignore_errors=True)  # recover() ran: an empty leftover
        os.replace(staging, out / COMMIT_NAME)
        roll_forward(out)


def roll_forward(out: Path) -> None:
    """Finish the commit in ``out/COMMIT_NAME``: move its files in (a symbolic link in `out` is written
    through), remove the previous run's files it does not replace, move its manifest in last, remove
    the commit folder. Each step can be repeated, so a commit killed at any point is finished by
    running this again."""
    pending = out / COMMIT_NAME
    new = pending / MANIFEST_NAME
    if new.exists():
        files = json.loads(new.read_text(encoding="utf-8"))["files"]
        previous = previous_files(out)  # before the moves: a new summary.json replaces an old one
        for name in files:
            if (pending / name).exists():
                place(pending / name, out / name)
        for name in previous:
            if name not in files and name != MANIFEST_NAME and (out / name).is_file():
                (out / name).unlink()
        place(new, out / MANIFEST_NAME)
    shutil.rmtree(pending, ignore_errors=True)


def place(src: Path, dst: Path) -> None:
    """Move `src` onto `dst` in one rename; a link at `dst` is written through (its target replaced)."""
    if dst.is_symlink():
        with atomic_path(dst) as tmp:
            shutil.copyfile(src, tmp)
        src.unlink()
    else:
        os.replace(src, dst)


def recover(out: Path, locked: bool = False) -> None:
    """Finish a commit that a killed run left in `out` (`roll_forward`), holding the folder's lock
    (taken here unless `locked`; a run that is committing is waited for, `COMMIT_WAIT_S`)."""
    if not (out / COMMIT_NAME).exists():
        return
    if locked:
        roll_forward(out)
        return
    with hold(out, timeout=COMMIT_WAIT_S):
        roll_forward(out)


def check_folder(folder: str | Path) -> dict | None:
    """The manifest of the run `folder` holds, after checking that every file it lists is there with
    its hash (a commit a killed run left is finished first, `recover`). None for a folder without a
    manifest (files written by hand or by an older version). Raises `RunMismatch` naming the files
    that differ."""
    folder = Path(folder)
    recover(folder)
    manifest = read_manifest(folder)
    if manifest is not None:
        verify_manifest(folder, manifest)
    return manifest


def verify_manifest(folder: Path, manifest: dict) -> None:
    """Raise `RunMismatch`, naming them, unless every file `manifest` lists is in `folder` with its hash."""
    missing = [n for n in manifest["files"] if not (folder / n).is_file()]
    changed = [n for n, h in manifest["files"].items() if n not in missing and sha256(folder / n) != h]
    if missing or changed:
        what = "; ".join(s for s in (f"missing {', '.join(missing)}" if missing else "",
                                     f"changed {', '.join(changed)}" if changed else "") if s)
        raise RunMismatch(f"{folder} does not hold the run its {MANIFEST_NAME} lists (run {manifest.get('run_id')}): "
                          f"{what}. The files were changed after the run or come from two runs; run the job again")


def check_run_file(path: str | Path) -> None:
    """Before reading a file of an output folder: `check_folder` of its folder when the file is one
    its manifest lists (a file the manifest does not list, or a folder without one, is read as is;
    a commit a killed run left is finished first)."""
    path = Path(path)
    recover(path.parent)
    manifest = read_manifest(path.parent)
    if manifest is not None and path.name in manifest["files"]:
        verify_manifest(path.parent, manifest)


def file_mode() -> int:
    """Permissions of a new file under the process's umask (mkstemp's own are owner-only)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@contextmanager
def atomic_path(path: str | Path) -> Iterator[str]:
    """A temporary file name beside `path` to write to; on success it is renamed onto `path` (with the
    umask's permissions), on failure removed. Creates the folder. A symbolic link is written through
    (the file it points to is replaced, the link stays); a path that is neither a regular file nor
    missing (a device, a folder, a pipe) raises `NotRegularFile` before anything is written."""
    path = Path(os.path.realpath(path))
    check_regular(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, file_mode())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


class NotRegularFile(OSError):
    """A write to a path that exists and is not a regular file (a device, a folder, a pipe)."""


def check_regular(path: str | Path) -> None:
    """Raise `NotRegularFile` when `path` (its link followed) exists and is not a regular file."""
    target = Path(os.path.realpath(path))
    if target.exists() and not target.is_file():
        kind = "a folder" if target.is_dir() else "a device, pipe or socket"
        raise NotRegularFile(f"{path} is {kind}{f' ({target})' if str(target) != str(path) else ''}, not a regular "
                             "file: refusing to replace it")


def atomic_write(path: str | Path, text: str) -> Path:
    """Write `text` to `path` through a temporary file and an atomic rename (`atomic_path`)."""
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    return Path(path)


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON-serialisable")


def write_json(path: str | Path, data: Any) -> Path:
    """`atomic_write` of `data` as indented JSON (numpy arrays and scalars as plain values)."""
    return atomic_write(path, json.dumps(data, indent=2, default=_plain) + "\n")


def versions() -> dict[str, str]:
    """Versions of pressocp, CasADi, numpy and Python."""
    out = {"python": platform.python_version()}
    for pkg in ("pressocp", "casadi", "numpy"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "unknown"
    return out
