"""A caching C compiler for CasADi's JIT, run as a script (it imports nothing of pressocp):

    python jitcc.py CACHE_DIR COMPILER ARG...      (CACHE_DIR "-": no cache)

It stands in for the compiler in CasADi's shell importer (`pressocp.compile_cache.jit_options`).
When the command compiles one C source (``-c SRC -o OBJ``), the object file is looked up in
CACHE_DIR under the SHA-256 of the compiler's identity, the flags and the source text; a hit is
copied to OBJ and the compiler is not run. Any other command (a link, or a source it cannot read)
runs the compiler as it is. The wall time of every compile it does run is appended to the file named
by ``$PRESSOCP_COMPILE_LOG``, the calling process's record of its compile time.

An entry is one file: a header line with the SHA-256 of the object code, then the object code. An
entry whose object code does not match its header (truncated, corrupt) is deleted and rebuilt,
never used. Entries are written to a temporary file in CACHE_DIR and renamed into place, so two
processes compiling the same source at once each write a whole entry and either one is kept.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

MAGIC = b"pressocp-jitcc 1 "


def compiler_identity(compiler: str) -> str:
    """The compiler's resolved path, size and modification time: a new compiler gives new keys."""
    path = shutil.which(compiler) or compiler
    try:
        st = os.stat(path)
        return f"{os.path.realpath(path)}:{st.st_size}:{st.st_mtime_ns}"
    except OSError:
        return path


def cache_key(compiler: str, args: list[str], source: str, obj: str) -> str | None:
    """SHA-256 of the compiler, the arguments (the source and object paths left out) and the source
    text; None when the source cannot be read."""
    try:
        with open(source, "rb") as f:
            text = f.read()
    except OSError:
        return None
    h = hashlib.sha256()
    h.update(compiler_identity(compiler).encode())
    for a in args:
        h.update(b"\0" + (b"<src>" if a == source else b"<obj>" if a == obj else a.encode()))
    h.update(b"\0" + text)
    return h.hexdigest()


def read_entry(path: str) -> bytes | None:
    """The object code of a cache entry, or None when it is missing or does not match its header (a
    corrupt entry is deleted)."""
    try:
        with open(path, "rb") as f:
            header, payload = f.readline(), f.read()
    except OSError:
        return None
    if header.startswith(MAGIC) and header[len(MAGIC) :].strip().decode(errors="replace") == \
            hashlib.sha256(payload).hexdigest():
        return payload
    try:
        os.remove(path)
    except OSError:
        pass
    return None


def write_entry(path: str, payload: bytes) -> None:
    """Write a cache entry atomically (a temporary file in the same folder, then a rename)."""
    folder = os.path.dirname(path)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=".o")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(MAGIC + hashlib.sha256(payload).hexdigest().encode() + b"\n" + payload)
        os.replace(tmp, path)
    except OSError:
        try:
            os.remove(tmp)
        except OSError:
            pass


def timed_call(command: list[str]) -> int:
    """Run `command`; its wall time is appended to the file named by ``$PRESSOCP_COMPILE_LOG`` (when
    set), which the calling process reads as its compile time. Returns the exit code."""
    t0 = time.perf_counter()
    code = subprocess.call(command)
    log = os.environ.get("PRESSOCP_COMPILE_LOG")
    if log:
        try:
            with open(log, "a") as f:
                f.write(f"{time.perf_counter() - t0:.6f}\n")
        except OSError:
            pass
    return code


def compile_cached(cache: str, compiler: str, args: list[str]) -> int:
    """Run ``compiler args`` through the cache; returns the exit code. A compile the cache answers is
    not run and logs no time; a link is not timed (it is not a compile)."""
    run = lambda: subprocess.call([compiler, *args])  # noqa: E731
    if "-c" not in args or "-o" not in args or args.index("-o") + 1 >= len(args):
        return run()
    if cache == "-":  # no cache (pressocp.compile_cache.NO_CACHE)
        return timed_call([compiler, *args])
    obj = args[args.index("-o") + 1]
    sources = [a for a in args if a.endswith((".c", ".cpp", ".cc"))]
    key = cache_key(compiler, args, sources[0], obj) if len(sources) == 1 else None
    if key is None:
        return timed_call([compiler, *args])
    entry = os.path.join(cache, key[:2], key + ".o")
    payload = read_entry(entry)
    if payload is not None:
        with open(obj, "wb") as f:
            f.write(payload)
        return 0
    code = timed_call([compiler, *args])
    if code == 0:
        try:
            os.makedirs(os.path.dirname(entry), exist_ok=True)
            with open(obj, "rb") as f:
                write_entry(entry, f.read())
        except OSError:  # an unwritable cache only costs the next compile
            pass
    return code


def record_interrupts() -> None:
    """On SIGINT, create the file named by ``$PRESSOCP_COMPILE_INTERRUPTED`` (when set) and exit 130:
    the process that ran this compile through ``system()`` ignores SIGINT meanwhile, and checks that
    file instead (`pressocp.compile_cache.compile_interrupted`)."""
    flag = os.environ.get("PRESSOCP_COMPILE_INTERRUPTED")
    if not flag:
        return

    def stop(signum, frame):
        try:
            with open(flag, "w"):
                pass
        finally:
            os._exit(130)

    signal.signal(signal.SIGINT, stop)


if __name__ == "__main__":
    record_interrupts()
    if len(sys.argv) < 3:
        sys.exit("usage: python jitcc.py CACHE_DIR COMPILER ARG...")
    sys.exit(compile_cached(sys.argv[1], sys.argv[2], sys.argv[3:]))
