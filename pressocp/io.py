"""Writing result files: atomically (temporary file in the same folder, then rename), so a run never
leaves a half-written file, and JSON with numpy values."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np


def file_mode() -> int:
    """Permissions of a new file under the process's umask (mkstemp's own are owner-only)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


@contextmanager
def atomic_path(path: str | Path) -> Iterator[str]:
    """A temporary file name beside `path` to write to; on success it is renamed onto `path` (with the
    umask's permissions), on failure removed. Creates the folder."""
    path = Path(path)
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
