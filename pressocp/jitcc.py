"""A caching C compiler for CasADi's JIT, run as a script (it imports nothing of pressocp):

    python jitcc.py CACHE_DIR COMPILER ARG...      (CACHE_DIR "-": no cache)

It stands in for the compiler and the linker in CasADi's shell importer
(`pressocp.compile_cache.jit_options`). When the command compiles one C source (``-c SRC -o OBJ``),
the object file is looked up in CACHE_DIR under the SHA-256 of the compiler's identity, the flags and
the source text; a hit is copied to OBJ and the compiler is not run. When it links one object file
into a library (``OBJ -o LIB``, no ``-c``), the library is looked up the same way under the SHA-256 of
the compiler, the flags and the object code: a cached function then costs one start of this script
per step and no compiler or linker run (the link took 0.1-0.25 s of each function's 0.3-0.4 s on a
2-core machine). Any other command (several inputs, a source it cannot read) runs the compiler as it
is. The wall time of every compile it does run is appended to the file named by
``$PRESSOCP_COMPILE_LOG``, the calling process's record of its compile time (a link is not timed).
The exit code of every command it runs to its end, a cache hit included, is appended to the file named
by ``$PRESSOCP_COMPILE_STATUS``: a failed command whose code is missing there never reached this
script (`pressocp.interrupt.compiling`).

An entry is one file: a header line with the SHA-256 of the object code, then the object code. An
entry whose object code does not match its header (truncated, corrupt) is deleted and rebuilt,
never used. Entries are written to a temporary file in CACHE_DIR and renamed into place, so two
processes compiling the same source at once each write a whole entry and either one is kept; a
process that misses an entry another one is compiling waits for that compile and takes its entry
(`entry_lock`).
"""

from __future__ import annotations

import os
import sys
import time

try:  # CPython's C module: `signal` wraps it in enums, whose import cost a hit 8 of its ~56 ms
    import _signal as signal
except ImportError:
    import signal
try:  # CPython's built-in SHA-256 (3.12: _sha2; 3.11: _sha256): hashlib loads OpenSSL, 7 of a hit's 38 ms,
    from _sha2 import sha256  # while the built-in one hashes a 600 kB source in 3 ms
except ImportError:
    try:
        from _sha256 import sha256
    except ImportError:
        from hashlib import sha256

# subprocess, shutil and tempfile are imported where they are used: a cache hit needs none of them, and
# importing them took 30 of the 50 ms this script ran for a hit (its interpreter starts in 20).

MAGIC = b"pressocp-jitcc 1 "


def compiler_identity(compiler: str) -> str:
    """The compiler's resolved path, size and modification time: a new compiler gives new keys."""
    path = compiler
    if not os.path.isabs(compiler):  # CasADi is given an absolute path: shutil's import took 25 ms
        import shutil

        path = shutil.which(compiler) or compiler
    try:
        st = os.stat(path)
        return f"{os.path.realpath(path)}:{st.st_size}:{st.st_mtime_ns}"
    except OSError:
        return path


def cache_key(compiler: str, args: list[str], source: str, obj: str) -> str | None:
    """SHA-256 of the compiler, the arguments (the input and output paths left out) and the input's
    content (a C source, or the object file a link reads); None when the input cannot be read."""
    try:
        with open(source, "rb") as f:
            text = f.read()
    except OSError:
        return None
    h = sha256()
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
            sha256(payload).hexdigest():
        return payload
    try:
        os.remove(path)
    except OSError:
        pass
    return None


def write_entry(path: str, payload: bytes) -> None:
    """Write a cache entry atomically (a temporary file in the same folder, then a rename)."""
    import tempfile

    folder = os.path.dirname(path)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=".o")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(MAGIC + sha256(payload).hexdigest().encode() + b"\n" + payload)
        os.replace(tmp, path)
    except OSError:
        try:
            os.remove(tmp)
        except OSError:
            pass


def call(command: list[str]) -> int:
    """Run `command`; returns its exit code."""
    import subprocess

    return subprocess.call(command)


def timed_call(command: list[str]) -> int:
    """Run `command`; its wall time is appended to the file named by ``$PRESSOCP_COMPILE_LOG`` (when
    set), which the calling process reads as its compile time. Returns the exit code."""
    t0 = time.perf_counter()
    code = call(command)
    append_line("PRESSOCP_COMPILE_LOG", f"{time.perf_counter() - t0:.6f}")
    return code


def append_line(variable: str, line: str) -> None:
    """Append `line` to the file named by the environment variable `variable` (when set); a file that
    cannot be written is left alone (the caller's record only)."""
    log = os.environ.get(variable)
    if log:
        try:
            with open(log, "a") as f:
                f.write(line + "\n")
        except OSError:
            pass


def compile_cached(cache: str, compiler: str, args: list[str]) -> int:
    """Run ``compiler args`` through the cache; returns the exit code. A compile or a link the cache
    answers is not run and logs no time; a link that runs is not timed (it is not a compile)."""
    if "-o" not in args or args.index("-o") + 1 >= len(args):
        return call([compiler, *args])
    out = args[args.index("-o") + 1]
    if "-c" in args:  # a compile: the object file is cached under its source
        inputs, suffix, run = [a for a in args if a.endswith((".c", ".cpp", ".cc"))], ".o", timed_call
    else:  # a link: the library is cached under its object file
        inputs, suffix, run = [a for a in args if a.endswith(".o")], ".so", call
    if cache == "-":  # no cache (pressocp.compile_cache.NO_CACHE)
        return run([compiler, *args])
    key = cache_key(compiler, args, inputs[0], out) if len(inputs) == 1 else None
    if key is None:
        return run([compiler, *args])
    entry = os.path.join(cache, key[:2], key + suffix)
    if copied(entry, out, suffix):
        return 0
    lock = entry_lock(entry)
    try:
        if lock is not None and copied(entry, out, suffix):  # compiled by the process that held the lock
            return 0
        code = run([compiler, *args])
        if code == 0:
            try:
                os.makedirs(os.path.dirname(entry), exist_ok=True)
                with open(out, "rb") as f:
                    write_entry(entry, f.read())
            except OSError:  # an unwritable cache only costs the next compile
                pass
    finally:
        if lock is not None:
            release(lock, entry)
    return code


def copied(entry: str, out: str, suffix: str) -> bool:
    """Whether the cache entry `entry` was found whole and written to `out` (a library made executable)."""
    payload = read_entry(entry)
    if payload is None:
        return False
    with open(out, "wb") as f:
        f.write(payload)
    if suffix == ".so":
        os.chmod(out, 0o755)
    return True


def entry_lock(entry: str) -> int | None:
    """An exclusive lock on `entry`'s lock file (``ENTRY.lock``, POSIX ``flock``), taken when the entry
    is missing, before compiling it: a second process that misses the same entry meanwhile waits here,
    then finds the entry instead of compiling the same source again (the compile ahead of the 75 spm
    seed and a candidate chain reaching the same point function). The descriptor, or None where there
    is no ``flock`` or the lock file cannot be made: the lock only saves work, since entries are
    written whole and renamed into place (`write_entry`). ``fcntl`` is the standard library's: this
    script runs with ``-S``, without site-packages. A process that dies holding the lock releases it."""
    try:
        import fcntl
    except ImportError:  # not POSIX
        return None
    try:
        os.makedirs(os.path.dirname(entry), exist_ok=True)
        fd = os.open(entry + ".lock", os.O_RDWR | os.O_CREAT, 0o666)
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
    except OSError:
        os.close(fd)
        return None
    return fd


def release(fd: int, entry: str) -> None:
    """Remove `entry`'s lock file, then release the lock (`entry_lock`). A process that opened the
    file before its removal then holds a lock on the removed file, and one arriving later a lock of its
    own on a new file: both find the entry written, or, after a failed compile, both compile, which is
    harmless (`write_entry`)."""
    try:
        os.remove(entry + ".lock")
    except OSError:
        pass
    os.close(fd)


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


def record_status(code: int) -> None:
    """Append `code`, this command's exit code, to the file named by ``$PRESSOCP_COMPILE_STATUS``
    (when set)."""
    append_line("PRESSOCP_COMPILE_STATUS", str(code))


def main(argv: list[str]) -> int:
    """The command line (see the module's docstring); its exit code, recorded (`record_status`) also
    when the compiler could not be run."""
    code = 2
    try:
        if len(argv) < 2:
            print("usage: python jitcc.py CACHE_DIR COMPILER ARG...", file=sys.stderr)
            return code
        code = 1  # until the compiler's own code is known: an exception below is a failure
        code = compile_cached(argv[0], argv[1], argv[2:])
        return code
    finally:
        record_status(code)


if __name__ == "__main__":
    record_interrupts()
    sys.exit(main(sys.argv[1:]))
