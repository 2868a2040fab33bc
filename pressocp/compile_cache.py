"""Compiled model functions: the CasADi JIT options, with an on-disk cache of object files.

CasADi compiles a function and each derivative it builds of it through the system C compiler. The
compiler command here is `pressocp.jitcc`, which keys every object file by the SHA-256 of the
compiler, the flags and the generated C source, so a second process (a sweep's worker, a notebook
re-run, the CLI after the Python call) that generates the same code compiles nothing: only CasADi's
code generation and the link remain (tenths of a second). A corrupt entry is rebuilt, never used.

The cache folder is ``$PRESSOCP_CACHE_DIR`` when set (``off``: no cache), else
``$XDG_CACHE_HOME/pressocp/jit`` (default ``~/.cache/pressocp/jit``). `set_cache_dir` sets the
variable, so worker processes started afterwards use the same folder.
"""

from __future__ import annotations

import atexit
import hashlib
import os
import shlex
import shutil
import sys
import tempfile
import warnings
from collections.abc import Sequence
from functools import lru_cache
from pathlib import Path

#: Environment variable naming the cache folder ("off" disables the cache).
CACHE_ENV = "PRESSOCP_CACHE_DIR"
#: Environment variable that tells `pressocp.jitcc` which file to create when a SIGINT stops it. The
#: caller cannot see that SIGINT: CasADi runs the compiler through ``system()``, which ignores SIGINT
#: in its caller, so a Ctrl-C during a compile would otherwise be lost (`compile_interrupted`).
INTERRUPT_ENV = "PRESSOCP_COMPILE_INTERRUPTED"
#: Shell prefix of the compile and link commands (CasADi runs them through ``/bin/sh -c``). The shell
#: records a SIGINT in the flag file (`INTERRUPT_ENV`) and exits 130 once its command has ended; the
#: command (`pressocp.jitcc`) starts with SIGINT ignored, until its own handler is in place. Python takes
#: tens of milliseconds to get there, and a cached compile is mostly that start-up: without the shell's
#: record a Ctrl-C there ended the compile unrecorded ("Linking failed", exit 1) with a traceback of the
#: compiler's interpreter. A Ctrl-C in that start-up lets that one compile finish first.
RECORD_INTERRUPT = (f"trap ': > \"${INTERRUPT_ENV}\"; exit 130' INT; run() ( trap '' INT; exec \"$@\" ); run "
                    if os.name == "posix" else "")
#: Environment variable naming the file to which `pressocp.jitcc` appends the seconds of every compile
#: it runs (a cache hit runs none), so a caller can report its compile time (`compile_seconds`).
COMPILE_LOG_ENV = "PRESSOCP_COMPILE_LOG"
#: Environment variable naming the file to which `pressocp.jitcc` appends the exit code of every
#: command it runs to its end (`compile_statuses`): a failed compile whose code is missing was killed
#: before it ran, which the shell's trap (`RECORD_INTERRUPT`) cannot record in the shell's own first
#: milliseconds. Measured: 1 of 20 Ctrl-C's at random moments of press60's compiles and links
#: (`transaction_sigint`, 2026-11-29) ended as "Linking failed", exit 1.
COMPILE_STATUS_ENV = "PRESSOCP_COMPILE_STATUS"
#: `pressocp.jitcc`'s cache folder argument for "no cache" (every source compiled, and timed).
NO_CACHE = "-"
#: Optimisation flags of the compiled functions (-O3 was no faster and compiled 3 x longer).
FLAGS = ("-O1",)
#: Optimisation flags of the functions an NLP evaluates, and their derivatives (`function_options`'s
#: ``flags``: the rigid stage's loads, the ram's kinematics, the collocation point function). GCC
#: spends most of an -O1 compile of these long straight-line functions in register allocation; -Og
#: skips part of it: the collocation point function's Hessian (548 kB of C) compiled in 9.5 against
#: 13.2 s and evaluates as fast (23.1 against 23.6 us a point), and the 75 spm seed's cold call
#: compiled for 17.5 against 25.2 s, with the same answer to the last digit. The integrators keep
#: `FLAGS`: the flexible rod's right-hand side ran about 15 % slower at -Og
#: (docs/decisions/2026-12-02-og-for-nlp-functions.md).
NLP_FLAGS = ("-Og",)
#: Directions per derivative sweep of an NLP whose functions are compiled (the oracle's
#: ``max_num_dir``; CasADi's default 64 put all 9 Hessian colours of the collocation point function
#: into one large function that took ~35 s to compile; 3 compile in ~5 s and evaluate as fast).
JIT_DIRECTIONS = 3
#: CasADi's common-subexpression elimination on the derivatives of every compiled function: the
#: collocation point function's Hessian sweep (three forward directions of its adjoint, press75)
#: falls from 30 428 to 22 939 operations, its values the same to the bit. On the function itself as
#: well it would fall to 15 677 (-O1 compile 7.3 -> 2.8 s), but the adjoint then sums its terms in
#: another order: the last bits move and so does IPOPT's path (docs/decisions/2026-12-01-cse.md).
DERIVATIVE_CSE = True


@lru_cache(maxsize=1)
def c_compiler() -> str | None:
    """The system C compiler (``cc``, else ``gcc``), or None when neither is on the PATH."""
    return shutil.which("cc") or shutil.which("gcc")


def compiler_available() -> bool:
    """Whether a C compiler is on the PATH."""
    return c_compiler() is not None


def check_jit(setting: bool | str) -> None:
    """A transcription's ``jit`` setting: True, False or "auto" (ValueError otherwise)."""
    if setting not in (True, False, "auto"):
        raise ValueError(f"jit must be True, False or 'auto', got {setting!r}")


def use_jit(setting: bool | str, what: str) -> bool:
    """Whether to compile: `setting` True or False, or "auto" (when a C compiler is found; a warning
    names `what` runs on CasADi's virtual machine when none is)."""
    check_jit(setting)
    if setting == "auto":
        if not compiler_available():
            warnings.warn(f"no C compiler (cc) found: {what} runs on CasADi's virtual machine, several times "
                          "slower; install one (e.g. gcc) to compile", RuntimeWarning, stacklevel=3)
            return False
        return True
    return bool(setting)


#: Optimisation flags of the derivatives of an integrator's right-hand side (`function_options` with
#: ``derivatives="quick"``): the rigid rod's Jacobian compiled in 2.7 s at -O0 and 8.4 s at -O1, the
#: 8-element rod reduced to 2 modes in 7 s and 55 s, for an integration 0-10 % slower with IDAS
#: (docs/decisions/2026-11-26-compiled-integrator.md).
QUICK_FLAGS = ("-O0",)


def function_options(jit: bool, derivatives: str = "same", flags: tuple[str, ...] = FLAGS) -> dict:
    """Options of a CasADi Function compiled with its derivatives (`jit_options`) at `flags`
    (`NLP_FLAGS` for the functions of an NLP), or none. ``derivatives="quick"`` compiles the
    derivatives at `QUICK_FLAGS`. Each derivative CasADi builds merges its common subexpressions first
    (`DERIVATIVE_CSE`); the function itself does not."""
    if not jit:
        return {}
    base = jit_options()
    opts = {**base, "jit_options": {**base["jit_options"], "flags": list(flags)}}
    der = {**opts, "cse": DERIVATIVE_CSE}
    if derivatives == "quick":
        return {**opts, "der_options": {**der, "jit_options": {**opts["jit_options"], "flags": list(QUICK_FLAGS)}}}
    return {**opts, "der_options": der}


def oracle_options(jit: bool) -> dict:
    """nlpsol options for an NLP whose functions are compiled: at most `JIT_DIRECTIONS` directions per
    derivative sweep."""
    return {"oracle_options": {"max_num_dir": JIT_DIRECTIONS}} if jit else {}


def cache_dir() -> Path | None:
    """The object-file cache folder, or None when the cache is off (``PRESSOCP_CACHE_DIR=off``)."""
    value = os.environ.get(CACHE_ENV)
    if value is not None:
        return None if value.strip().lower() in ("", "off", "0", "false", "no") else Path(value).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "pressocp" / "jit"


def set_cache_dir(path: str | os.PathLike | None) -> None:
    """Use `path` as the cache folder (None: no cache), here and in processes started afterwards."""
    os.environ[CACHE_ENV] = "off" if path is None else os.fspath(path)


def process_file(kind: str) -> Path:
    """A file of this process's compiles in the system's temporary folder, named by `kind` and the
    process id: what its compile commands leave for it (`interrupt_flag`, `compile_log`,
    `compile_status_log`)."""
    return Path(tempfile.gettempdir()) / f"pressocp-compile-{kind}-{os.getpid()}"


def interrupt_flag() -> Path:
    """This process's flag file for a compile stopped by SIGINT (`INTERRUPT_ENV`)."""
    return process_file("interrupted")


def compile_interrupted() -> bool:
    """Whether a compile of this process was stopped by SIGINT since the last call (the flag file
    `pressocp.jitcc` leaves is removed)."""
    flag = interrupt_flag()
    if not flag.exists():
        return False
    try:
        flag.unlink()
    except OSError:
        pass
    return True


def compile_log() -> Path:
    """This process's log of compile times (`COMPILE_LOG_ENV`)."""
    return process_file("seconds")


def compile_seconds() -> float:
    """Seconds the C compiler has run for this process's JIT functions so far (object files taken
    from the cache cost none): the difference between two calls is the compile time between them."""
    try:
        text = compile_log().read_text()
    except OSError:
        return 0.0
    return float(sum(float(x) for x in text.split() if x.replace(".", "", 1).isdigit()))


def compile_status_log() -> Path:
    """This process's log of its compile commands' exit codes (`COMPILE_STATUS_ENV`)."""
    return process_file("status")


def compile_statuses() -> list[int]:
    """The exit codes of this process's compile and link commands so far, in order (a command killed
    before `pressocp.jitcc` ran to its end has none), from the file its commands write to: the one
    ``$PRESSOCP_COMPILE_STATUS`` names (a worker started before it set its own inherits its
    parent's), else `compile_status_log`."""
    try:
        text = Path(os.environ.get(COMPILE_STATUS_ENV) or compile_status_log()).read_text()
    except OSError:
        return []
    return [int(x) for x in text.split() if x.lstrip("-").isdigit()]


@lru_cache(maxsize=1)
def _remove_log_at_exit() -> None:
    atexit.register(lambda: [f.unlink(missing_ok=True) for f in (compile_log(), compile_status_log())])


def prepared_record(*parts: str) -> Path | None:
    """The file that records in the cache folder that the functions `parts` describe were compiled into
    it (named by the SHA-256 of `parts`, CasADi's version, `FLAGS` and `NLP_FLAGS`); None when the
    cache is off. It lets a caller skip compiling ahead what the cache holds; a record whose object files were removed
    since costs only the compile it was meant to save, in the solve that then compiles."""
    folder = cache_dir()
    if folder is None:
        return None
    import casadi as ca

    key = hashlib.sha256("\n".join((ca.__version__, *FLAGS, *NLP_FLAGS, *parts)).encode()).hexdigest()
    return folder / "prepared" / key


def write_prepared_record(record: Path | None) -> None:
    """Create `record` (`prepared_record`), if it is not None and the folder is writable."""
    if record is None:
        return
    try:
        record.parent.mkdir(parents=True, exist_ok=True)
        record.touch()
    except OSError:  # an unwritable cache folder: the next call prepares again
        pass


def jit_options() -> dict:
    """CasADi Function options that compile the function with the system C compiler at `FLAGS`,
    through the object-file cache (`cache_dir`) unless it is off; the generated sources go to the
    system's temporary folder. Raises RuntimeError when there is no C compiler."""
    cc = c_compiler()
    if cc is None:
        raise RuntimeError("no C compiler (cc or gcc) on the PATH: install one, or compile nothing (jit=False)")
    folder = cache_dir()
    if folder is not None:
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:  # an unwritable cache folder: compile without it
            folder = None
    script = Path(__file__).with_name("jitcc.py")  # a link runs as it is, but a SIGINT during it is recorded too
    compiler = linker = RECORD_INTERRUPT + " ".join(shlex.quote(str(a)) for a in (
        sys.executable, "-I", "-S", script, NO_CACHE if folder is None else folder, cc))
    os.environ[INTERRUPT_ENV] = str(interrupt_flag())  # for the compiler's process (`compile_interrupted`)
    os.environ[COMPILE_LOG_ENV] = str(compile_log())  # and where it logs its time (`compile_seconds`)
    os.environ[COMPILE_STATUS_ENV] = str(compile_status_log())  # and its exit codes (`compile_statuses`)
    _remove_log_at_exit()
    return {"jit": True, "compiler": "shell",
            "jit_options": {"compiler": compiler, "linker": linker, "flags": list(FLAGS), "verbose": False,
                            "directory": os.path.join(tempfile.gettempdir(), "")}}


def compile_library(sources: Sequence[tuple[Path, Sequence[str]]], library: Path,
                    link_flags: Sequence[str] = ()) -> None:
    """Compile C `sources` (each with its own flags after `FLAGS`) into the shared `library` through
    the object-file cache, as CasADi's JIT compiles (`pressocp.jitcc`: a second process with the same
    sources and flags compiles nothing; the compiles' time goes to `compile_seconds`), and link them
    with `link_flags`. Raises RuntimeError (with the compiler's output) when a step fails or there is
    no C compiler; a Ctrl-C stops the compiler and raises KeyboardInterrupt."""
    import subprocess

    jit_options()  # the compiler's environment: its time log and status file
    cc, folder = c_compiler(), cache_dir()
    command = [sys.executable, "-I", "-S", str(Path(__file__).with_name("jitcc.py")),
               NO_CACHE if folder is None else str(folder), str(cc)]
    objects = [source.with_suffix(".o") for source, _ in sources]
    steps = [(f"compiling {source.name}", [*FLAGS, *flags, "-fPIC", "-c", str(source), "-o", str(obj)])
             for (source, flags), obj in zip(sources, objects)]
    steps.append((f"linking {library.name}", [*map(str, objects), "-o", str(library), "-shared", *link_flags]))
    for what, args in steps:
        done = subprocess.run([*command, *args], capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{what} failed (exit {done.returncode}): {(done.stderr or done.stdout).strip()[-2000:]}")
