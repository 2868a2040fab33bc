"""`pressocp.buffers`: evaluating a CasADi Function into numpy arrays gives a plain call's numbers."""

import casadi as ca
import numpy as np
import pytest

from pressocp.buffers import call, evaluate


def function() -> ca.Function:
    x, y, s = ca.SX.sym("x", 2, 3), ca.SX.sym("y", 3), ca.SX.sym("s")
    return ca.Function("f", [x, y, s], [ca.mtimes(x, y) * s, ca.sin(x).T, ca.sumsqr(x) + s],
                       ["x", "y", "s"], ["xy", "sin_t", "total"], {"default_in": [0.0, 1.0, 2.0]})


def test_outputs_are_a_plain_calls_in_their_shapes():
    f, rng = function(), np.random.default_rng(3)
    x, y = rng.normal(size=(2, 3)), rng.normal(size=3)
    plain = [np.asarray(v) for v in f(x, y, 0.5)]
    for got, want in zip(evaluate(f, x, y, 0.5), plain):
        assert got.shape == want.shape
        np.testing.assert_array_equal(got, want)


def test_inputs_by_name_take_their_defaults():
    f = function()
    x = np.arange(6.0).reshape(2, 3)
    got = call(f, x=x)
    want = f.call({"x": x})
    for k in f.name_out():
        np.testing.assert_array_equal(got[k], np.asarray(want[k]))
    assert got["total"].item() == pytest.approx(np.sum(x**2) + 2.0)


def test_an_integrators_statistics_and_failure_come_through():
    x = ca.SX.sym("x")
    F = ca.integrator("F", "cvodes", {"x": x, "ode": -50 * x}, 0.0, np.linspace(0.1, 1.0, 10), {"max_num_steps": 5})
    stats = {}
    with pytest.raises(RuntimeError, match="CV_TOO_MUCH_WORK"):
        call(F, stats=stats, x0=1.0)
    assert "tcur" in stats  # what a plain call's failure leaves in f.stats(), for the error's time
    G = ca.integrator("G", "cvodes", {"x": x, "ode": -x}, 0.0, np.linspace(0.1, 1.0, 10), {"reltol": 1e-10, "abstol": 1e-12})
    stats = {}
    xf = call(G, stats=stats, x0=1.0)["xf"]
    np.testing.assert_allclose(xf.ravel(), np.exp(-np.linspace(0.1, 1.0, 10)), rtol=1e-8)
    assert stats["nsteps"] > 10


@pytest.mark.parametrize("args, match", [((np.zeros(5), np.zeros(3), 1.0), "input 'x' needs 6"),
                                         ((np.zeros(6), np.zeros(3)), "takes 3 inputs")])
def test_a_wrong_argument_is_named(args, match):
    with pytest.raises(ValueError, match=match):
        evaluate(function(), *args)


def test_an_unknown_input_name_is_named():
    with pytest.raises(ValueError, match="has no input z; its inputs: x, y, s"):
        call(function(), z=1.0)
