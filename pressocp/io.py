"""Writing result files: atomically (temporary file in the same folder, then rename), so a run never
leaves a half-written file, and JSON with numpy values."""

from __future__ import annotations

import json
import os
import platform
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np


#: Lock file of an output folder while a run writes into it.
LOCK_NAME = ".pressocp.lock"
#: The file a run writes last, listing the run's files: present means the folder holds a complete run.
SUMMARY_NAME = "summary.json"
#: The file beside the lock that names the run holding it (process, host, start, command).
OWNER_NAME = ".pressocp.owner"


class OutputBusy(ValueError):
    """Another run is writing into the output folder."""


@contextmanager
def output_folder(out: str | Path, clear: bool = True) -> Iterator[Path]:
    """The output folder `out` (created), held by this run: a second run into it while this one
    writes is refused (`OutputBusy`; a `filelock` lock file, `LOCK_NAME`, released when the run ends
    or dies). With `clear`, the previous run's files, listed in its `SUMMARY_NAME`, are removed
    first, that summary last: an interrupted run then leaves no summary of an older run beside its
    own files. Other files in the folder are left alone."""
    from filelock import FileLock, Timeout

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    lock = FileLock(str(out / LOCK_NAME))
    try:
        lock.acquire(timeout=0)
    except Timeout:
        raise OutputBusy(f"{out} is being written by another pressocp run{lock_holder(out)} (lock file "
                         f"{out / LOCK_NAME}): wait for it to end, or pass another --out") from None
    try:
        atomic_write(out / OWNER_NAME, json.dumps({"pid": os.getpid(), "host": platform.node(),
                                                   "started": time.strftime("%Y-%m-%d %H:%M:%S"),
                                                   "command": " ".join(sys.argv)}) + "\n")
        if clear:
            clear_previous_run(out)
        yield out
    finally:
        (out / OWNER_NAME).unlink(missing_ok=True)
        lock.release()


def lock_holder(out: Path) -> str:
    """", process 1234 on host, started 2026-11-25 15:20:00: pressocp optimize ..." from the folder's
    `OWNER_NAME`, or "" when it cannot be read."""
    try:
        o = json.loads((out / OWNER_NAME).read_text())
        return f", process {o['pid']} on {o['host']}, started {o['started']}: {o['command']}"
    except (OSError, ValueError, KeyError, TypeError):
        return ""


def clear_previous_run(out: Path) -> list[str]:
    """Remove the files the folder's `SUMMARY_NAME` lists (plain names in `out` only), then the
    summary. Returns the names removed (none when there is no readable summary)."""
    summary = out / SUMMARY_NAME
    try:
        names = json.loads(summary.read_text()).get("files", [])
    except (OSError, ValueError, AttributeError):
        return []
    removed = []
    for name in [n for n in names if isinstance(n, str) and n != SUMMARY_NAME] + [SUMMARY_NAME]:
        path = out / name
        if Path(name).name == name and path.is_file():
            path.unlink()
            removed.append(name)
    return removed


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
