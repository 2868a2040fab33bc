"""Solver settings a user passes are refused before any solve when IPOPT, CasADi or the package would
refuse or mishandle them later: an IPOPT option name or value, a verification or integration tolerance
too loose to mean anything."""

import pytest

import pressocp as po
from pressocp.ocp.rigid_stage import Rigid
from pressocp.simulate import Integrator

PRESS60 = po.Scenario.load("press60")


@pytest.fixture
def no_solve(monkeypatch):
    """Any stage solve or design fails the test: the check must come first."""
    def solved(*args, **kwargs):
        raise AssertionError("a solve ran before the bad option was refused")

    monkeypatch.setattr(Rigid, "solve", solved)
    monkeypatch.setattr(po.Collocation, "solve", solved)
    monkeypatch.setattr("pressocp.ocp.optimize.design_speed", solved)


@pytest.mark.parametrize("transcription, strategy, match", [
    (po.Collocation(ipopt={"ipopt.max_itr": 5}), None, r"Collocation\.ipopt: IPOPT refuses ipopt\.max_itr = 5: No such "
                                                       r"IPOPT option: max_itr"),
    (po.Collocation(ipopt={"ipopt.tol": -1.0}), None, r"Collocation\.ipopt: IPOPT refuses ipopt\.tol = -1\.0: .*"
                                                      r"0 < \(1e-08\) <= \+inf"),
    (po.Collocation(ipopt={"ipopt.mu_strategy": "adaptiv"}), None, r"valid settings: monotone, adaptive"),
    (po.Collocation(ipopt={"ipopt.max_iter": "five"}), None, r"ipopt\.max_iter = 'five'.*type mismatch"),
    (po.Collocation(ipopt={"ipopt.linear_solver": "ma27"}), None, r"ipopt\.linear_solver = 'ma27': Invalid_Option "
                                                                  r"\('mumps' comes with CasADi; .*'ipopt\.hsllib'"),
    # the user's value of an option the package also sets (QUIET) is the one tried
    (po.Collocation(ipopt={"ipopt.print_level": 99}), None, r"ipopt\.print_level = 99: .*0 <= \(5\) <= 12"),
    (None, po.Strategy(rigid=Rigid(ipopt={"print_time": "yes"})), r"Strategy\.rigid\.ipopt: CasADi's nlpsol refuses "
                                                                  r"\['print_time'\]: .*cannot be cast to OT_BOOL"),
    (None, po.Strategy(rigid=Rigid(ipopt={"max_iter": 5})), r"Strategy\.rigid\.ipopt: CasADi's nlpsol refuses "
                                                            r"\['max_iter'\].*did you mean 'ipopt\.max_iter'\?"),
    (None, po.Strategy(rigid=Rigid(ipopt={"print_tim": False})), r"did you mean 'print_time'\?"),
    (po.Collocation(ipopt={1: 2}), None, r"Collocation\.ipopt must be a dict of nlpsol options with string keys"),
])
def test_an_option_ipopt_or_casadi_refuses_fails_before_any_solve(no_solve, transcription, strategy, match):
    with pytest.raises(ValueError, match=match):
        po.optimize_speed(PRESS60.problem, PRESS60.build_model(), transcription, strategy or po.Strategy(),
                          progress=False)


def test_options_ipopt_takes_pass_the_check():
    from pressocp.ipopt_options import check_nlpsol_options

    check_nlpsol_options("Collocation.ipopt", {"ipopt.max_iter": 0, "ipopt.mu_strategy": "adaptive",
                                               "ipopt.linear_solver": "mumps", "expand": False})


@pytest.mark.parametrize("value", [1e-4, 1.0, 50.0, 1e-15, 0.0])
def test_a_verification_tolerance_outside_its_range_is_refused(value):
    with pytest.raises(ValueError, match=rf"verify_rtol must be in \[1e-14, 1e-05\], got {value!r}"):
        po.Strategy(verify_rtol=value)


@pytest.mark.parametrize("value", [1e-2, 0.5, 5.0])
def test_an_integration_tolerance_of_a_percent_or_more_is_refused(value):
    with pytest.raises(ValueError, match=rf"rtol must be in \(0, 0\.01\), got {value!r}"):
        Integrator(rtol=value)


def test_ipopt_options_are_tried_together_and_the_culprit_is_named():
    """Options that only work together (a linear solver and its library) are tried as a set; when the
    set fails, the key whose removal makes it pass is named."""
    from pressocp import ipopt_options

    calls = []

    def refusal(options):  # stands in for IPOPT: 'b' works only with 'a', 'c' never
        calls.append(dict(options))
        ok = "ipopt.c" not in options and ("ipopt.b" not in options or "ipopt.a" in options)
        return None if ok else ("Invalid_Option", "")

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(ipopt_options, "ipopt_refusal", refusal)
        ipopt_options.check_nlpsol_options("X.ipopt", {"ipopt.a": 1, "ipopt.b": 2})
        assert calls == [{"ipopt.a": 1, "ipopt.b": 2}]
        with pytest.raises(ValueError, match=r"X\.ipopt: IPOPT refuses ipopt\.c = 3: Invalid_Option"):
            ipopt_options.check_nlpsol_options("X.ipopt", {"ipopt.a": 1, "ipopt.b": 2, "ipopt.c": 3})
