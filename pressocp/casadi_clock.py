"""CasADi's process clock, read twice in every call of an integrator's inner functions, made free.

Every call an integrator or NLP solver makes to one of its inner functions (CasADi's
``OracleFunction::calc_function``: the DAE residual, its Jacobian, the NLP's functions) times itself
for CasADi's statistics, whether or not anything asks for them (casadi issue #2703, "record_time
not observed in oracle"): two reads of the wall clock and two of the process CPU clock
(``std::clock()``). On Linux the process CPU clock is a system call that sums the times of every
thread of the process; on the package's 2-core VM it costs about 0.8 µs, and an IDAS cycle of the
seed clearance model (about 75 000 residual evaluations) spent a third of its time in it (perf,
2026-12-01). The wall clock is read through the vDSO, without a system call.

When `pressocp` is imported it points libcasadi's one reference to ``clock`` (its PLT slot) at
``pthread_self``, which takes no argument, makes no system call, and returns the same value on every
call in a thread. CasADi's process-time statistics (``t_proc_*`` in ``stats()``, the t_proc column of
``print_time``) then read 0; its wall-time statistics, and every number it computes, are unchanged.
Nothing else in libcasadi calls ``clock``. `set_casadi_clock(True)` puts the clock back. See
``docs/decisions/2026-12-01-casadi-process-clock.md``.

The slot is found in libcasadi's ELF relocations (pyelftools) and written only when it holds what
the dynamic linker puts there (libc's ``clock``, or libcasadi's own PLT code before the first call);
on any other platform or layout nothing is changed and the functions return False.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import sys
from pathlib import Path

import casadi as ca

#: The C library's symbol that CasADi's statistics call, and the one put in its place.
CLOCK, STAND_IN = "clock", "pthread_self"
#: The relocation types that fill a function's slot (x86-64, AArch64).
SLOT_TYPES = ("R_X86_64_JUMP_SLOT", "R_X86_64_GLOB_DAT", "R_AARCH64_JUMP_SLOT", "R_AARCH64_GLOB_DAT")
PAGE = 4096
PROT_READ, PROT_WRITE = 1, 2


def mapped_libcasadi() -> tuple[Path, int, int, list[tuple[int, int, str]]] | None:
    """The libcasadi this process loaded: its path, its load address (the start of its mapping at
    file offset 0), the end of its last mapping, and its mappings (start, end, permissions); None
    when it is not mapped (or no ``/proc/self/maps``)."""
    try:
        lines = Path("/proc/self/maps").read_text().splitlines()
    except OSError:
        return None
    package = Path(ca.__file__).resolve().parent
    maps: dict[Path, list[tuple[int, int, str, int]]] = {}
    for line in lines:
        parts = line.split(maxsplit=5)
        if len(parts) < 6:
            continue
        path = Path(parts[5].strip())
        if path.parent != package or not path.name.startswith("libcasadi.so"):
            continue
        start, end = (int(x, 16) for x in parts[0].split("-"))
        maps.setdefault(path, []).append((start, end, parts[1], int(parts[2], 16)))
    if len(maps) != 1:
        return None
    path, regions = next(iter(maps.items()))
    base = [s for s, _, _, offset in regions if offset == 0]
    if not base:
        return None
    return path, min(base), max(e for _, e, _, _ in regions), [(s, e, p) for s, e, p, _ in regions]


def clock_slots(path: Path) -> list[int]:
    """The offsets (from the load address) of the slots through which `path` calls ``clock``."""
    try:
        from elftools.elf.elffile import ELFFile
        from elftools.elf.relocation import RelocationSection
        from elftools.elf.enums import ENUM_RELOC_TYPE_x64, ENUM_RELOC_TYPE_AARCH64
    except ImportError:
        return []
    types = {v: k for k, v in {**ENUM_RELOC_TYPE_x64, **ENUM_RELOC_TYPE_AARCH64}.items()}
    slots = []
    with open(path, "rb") as f:
        elf = ELFFile(f)
        first_load = min((s["p_vaddr"] for s in elf.iter_segments() if s["p_type"] == "PT_LOAD"), default=None)
        if first_load != 0 or elf["e_type"] != "ET_DYN":
            return []
        for section in elf.iter_sections():
            if not isinstance(section, RelocationSection):
                continue
            symbols = elf.get_section(section["sh_link"])
            for rel in section.iter_relocations():
                kind = types.get(rel["r_info_type"]) if elf["e_machine"] in ("EM_X86_64", "EM_AARCH64") else None
                if kind in SLOT_TYPES and rel["r_info_sym"] and symbols.get_symbol(rel["r_info_sym"]).name == CLOCK:
                    slots.append(int(rel["r_offset"]))
    return slots


def c_library() -> ctypes.CDLL | None:
    """The C library (``libc.so.6``), or None when it cannot be found."""
    name = ctypes.util.find_library("c")
    try:
        return ctypes.CDLL(name) if name else None
    except OSError:
        return None


def symbol_address(lib: ctypes.CDLL, name: str) -> int | None:
    """The address of the function `name` in `lib`, or None when `lib` has none."""
    try:
        return ctypes.cast(getattr(lib, name), ctypes.c_void_p).value
    except AttributeError:
        return None


def _write(libc: ctypes.CDLL, slot: int, value: int, writable: bool) -> None:
    """Write the pointer `value` at `slot`, making its page writable for the write when it is not."""
    page = slot - slot % PAGE
    mprotect = libc.mprotect
    mprotect.argtypes = (ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int)
    if not writable and mprotect(page, PAGE, PROT_READ | PROT_WRITE) != 0:
        raise OSError(f"mprotect of the page at {page:#x} failed")
    ctypes.c_void_p.from_address(slot).value = value
    if not writable:
        mprotect(page, PAGE, PROT_READ)


def set_casadi_clock(measured: bool = False) -> bool:
    """Whether CasADi's statistics read the process CPU clock in this process.

    Parameters
    ----------
    measured : bool
        False (what importing `pressocp` sets): CasADi's ``clock`` is ``pthread_self``, its
        process-time statistics read 0, its calls cost no system call. True: the C library's
        ``clock`` again.

    Returns
    -------
    bool
        Whether libcasadi's slot was found and holds what was asked (False off Linux, without
        pyelftools, or when the slot holds something this module did not expect; nothing is
        changed then).
    """
    if not sys.platform.startswith("linux"):
        return False
    mapped, libc = mapped_libcasadi(), c_library()
    if mapped is None or libc is None:
        return False
    path, base, end, regions = mapped
    clock, stand_in = symbol_address(libc, CLOCK), symbol_address(libc, STAND_IN)
    slots = clock_slots(path)
    if clock is None or stand_in is None or not slots:
        return False
    want = clock if measured else stand_in
    for offset in slots:
        slot = base + offset
        region = next(((s, e, p) for s, e, p in regions if s <= slot < e), None)
        if region is None:
            return False
        held = ctypes.c_void_p.from_address(slot).value or 0
        if held not in (clock, stand_in) and not base <= held < end:  # not the linker's, not ours
            return False
        if held != want:
            _write(libc, slot, want, "w" in region[2])
    return True


def casadi_clock_measured() -> bool | None:
    """True when CasADi's statistics read the process clock in this process, False when they read
    ``pthread_self`` (`set_casadi_clock`), None when libcasadi's slot cannot be read here."""
    mapped, libc = mapped_libcasadi(), c_library()
    if not sys.platform.startswith("linux") or mapped is None or libc is None:
        return None
    path, base, _, _ = mapped
    slots = clock_slots(path)
    if not slots:
        return None
    held = {ctypes.c_void_p.from_address(base + s).value for s in slots}
    return held != {symbol_address(libc, STAND_IN)}
