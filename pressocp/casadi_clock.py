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
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import casadi as ca
import numpy as np

#: The C library's symbol that CasADi's statistics call, and the one put in its place.
CLOCK, STAND_IN = "clock", "pthread_self"
#: The relocation types that fill a function's slot, by machine: JUMP_SLOT and GLOB_DAT.
SLOT_TYPES = {"EM_X86_64": (7, 6), "EM_AARCH64": (1026, 1025)}
#: An ELF64 symbol and a relocation with addend, little-endian.
ELF64_SYM = np.dtype([("st_name", "<u4"), ("st_info", "u1"), ("st_other", "u1"), ("st_shndx", "<u2"),
                      ("st_value", "<u8"), ("st_size", "<u8")])
ELF64_RELA = np.dtype([("r_offset", "<u8"), ("r_info", "<u8"), ("r_addend", "<i8")])
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


@lru_cache(maxsize=None)
def clock_slots(path: Path) -> tuple[int, ...]:
    """The offsets (from the load address) of the slots through which the 64-bit little-endian
    shared library `path` calls ``clock``: its relocations of `SLOT_TYPES` whose symbol is named so.
    The symbol and relocation tables are read as arrays (about 24 000 relocations in libcasadi: a few
    milliseconds, where reading them entry by entry took 0.2 s of every import)."""
    try:
        from elftools.elf.elffile import ELFFile
    except ImportError:
        return ()
    with open(path, "rb") as f:
        elf = ELFFile(f)
        kinds = SLOT_TYPES.get(elf["e_machine"])
        loads = [s["p_vaddr"] for s in elf.iter_segments() if s["p_type"] == "PT_LOAD"]
        dynsym = elf.get_section_by_name(".dynsym")
        if (kinds is None or elf.elfclass != 64 or not elf.little_endian or elf["e_type"] != "ET_DYN"
                or not loads or min(loads) != 0 or dynsym is None):
            return ()
        strings = elf.get_section(dynsym["sh_link"]).data()
        name = CLOCK.encode() + b"\0"
        starts, at = [], strings.find(name)
        while at >= 0:
            starts.append(at)
            at = strings.find(name, at + 1)
        symbols = np.flatnonzero(np.isin(np.frombuffer(dynsym.data(), ELF64_SYM)["st_name"], starts))
        index = elf.get_section_index(".dynsym")
        slots: list[int] = []
        for section in elf.iter_sections():
            if section["sh_type"] == "SHT_RELA" and section["sh_link"] == index:
                rel = np.frombuffer(section.data(), ELF64_RELA)
                hit = np.isin(rel["r_info"] >> 32, symbols) & np.isin(rel["r_info"] & 0xFFFFFFFF, kinds)
                slots += [int(o) for o in rel["r_offset"][hit]]
    return tuple(slots)


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


@dataclass(frozen=True)
class ClockSlots:
    """libcasadi's slots for ``clock`` in this process (addresses), its mapping (load address, end,
    regions as (start, end, permissions)), and the C library."""

    addresses: tuple[int, ...]
    base: int
    end: int
    regions: list[tuple[int, int, str]]
    libc: ctypes.CDLL

    @classmethod
    def find(cls) -> "ClockSlots | None":
        """The slots, or None off Linux, without the C library, or when libcasadi or its slots are not
        found."""
        if not sys.platform.startswith("linux"):
            return None
        mapped, libc = mapped_libcasadi(), c_library()
        if mapped is None or libc is None:
            return None
        path, base, end, regions = mapped
        offsets = clock_slots(path)
        return cls(tuple(base + s for s in offsets), base, end, regions, libc) if offsets else None


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
        Whether libcasadi's slots were found and hold what was asked (False off Linux, without
        pyelftools, or when a slot holds something this module did not expect; nothing is changed
        then).
    """
    found = ClockSlots.find()
    if found is None:
        return False
    clock, stand_in = symbol_address(found.libc, CLOCK), symbol_address(found.libc, STAND_IN)
    if clock is None or stand_in is None:
        return False
    want = clock if measured else stand_in
    plan = []
    for slot in found.addresses:
        region = next(((s, e, p) for s, e, p in found.regions if s <= slot < e), None)
        if region is None:
            return False
        held = ctypes.c_void_p.from_address(slot).value or 0
        if held not in (clock, stand_in) and not found.base <= held < found.end:
            return False  # neither the linker's value nor ours
        plan.append((slot, held, "w" in region[2]))
    for slot, held, writable in plan:
        if held != want:
            _write(found.libc, slot, want, writable)
    return True


def casadi_clock_measured() -> bool | None:
    """True when CasADi's statistics read the process clock in this process, False when they read
    ``pthread_self`` (`set_casadi_clock`), None when libcasadi's slot cannot be read here."""
    found = ClockSlots.find()
    if found is None:
        return None
    held = {ctypes.c_void_p.from_address(slot).value for slot in found.addresses}
    return held != {symbol_address(found.libc, STAND_IN)}
