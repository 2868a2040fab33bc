"""CasADi's process clock (`pressocp.casadi_clock`): off once `pressocp` is imported, back on
request, and neither changes a number CasADi computes, only its process-time statistics."""

from __future__ import annotations

import ctypes
import sys

import casadi as ca
import numpy as np
import pytest

import pressocp  # noqa: F401  (importing it turns the clock off)
from pressocp import casadi_clock

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="libcasadi's ELF slot: Linux only")


def oscillator() -> ca.Function:
    """IDAS on a lightly damped oscillator over 1 s: thousands of residual evaluations."""
    x = ca.SX.sym("x", 2)
    ode = ca.vertcat(x[1], -1e4 * x[0] - 0.1 * x[1])
    return ca.integrator("osc", "idas", {"x": x, "ode": ode}, 0.0, np.linspace(0.0, 1.0, 11)[1:], {"reltol": 1e-9})


def run(F: ca.Function) -> tuple[np.ndarray, dict]:
    out = np.array(F(x0=[1.0, 0.0])["xf"])
    return out, F.stats()


def test_libcasadi_calls_clock_through_one_slot():
    mapped = casadi_clock.mapped_libcasadi()
    assert mapped is not None and mapped[0].name.startswith("libcasadi.so")
    assert len(casadi_clock.clock_slots(mapped[0])) == 1


def test_the_clock_is_off_after_import_and_toggles_without_changing_the_answer():
    assert casadi_clock.casadi_clock_measured() is False
    F = oscillator()
    quiet, quiet_stats = run(F)
    assert quiet_stats["t_proc_daeF"] == 0.0 and quiet_stats["t_wall_daeF"] > 0.0
    assert quiet_stats["n_call_daeF"] > 1000
    try:
        assert casadi_clock.set_casadi_clock(True)
        assert casadi_clock.casadi_clock_measured() is True
        measured, stats = run(F)
        assert stats["t_proc_daeF"] > 0.0
    finally:
        assert casadi_clock.set_casadi_clock(False)
    assert casadi_clock.casadi_clock_measured() is False
    assert np.array_equal(quiet, measured)  # the same bits
    assert stats["n_call_daeF"] == quiet_stats["n_call_daeF"]


def test_nothing_is_written_where_libcasadi_is_not_found(monkeypatch):
    monkeypatch.setattr(casadi_clock, "mapped_libcasadi", lambda: None)
    assert casadi_clock.set_casadi_clock(True) is False
    assert casadi_clock.casadi_clock_measured() is None
    monkeypatch.undo()
    assert casadi_clock.casadi_clock_measured() is False  # unchanged


def test_an_unexpected_slot_value_is_left_alone(monkeypatch):
    """A slot that holds neither the C library's clock, nor the stand-in, nor libcasadi's own PLT
    code is not the dynamic linker's: nothing is written."""
    mapped = casadi_clock.mapped_libcasadi()
    libc = casadi_clock.c_library()
    real = casadi_clock.symbol_address

    def elsewhere(lib, name):  # as if the C library's clock and the stand-in lived elsewhere
        return real(lib, name) + 64 if name in (casadi_clock.CLOCK, casadi_clock.STAND_IN) else real(lib, name)

    monkeypatch.setattr(casadi_clock, "symbol_address", elsewhere)
    assert casadi_clock.set_casadi_clock(True) is False
    monkeypatch.undo()
    slot = mapped[1] + casadi_clock.clock_slots(mapped[0])[0]
    assert ctypes.c_void_p.from_address(slot).value == casadi_clock.symbol_address(libc, casadi_clock.STAND_IN)
