"""Every IPOPT option set of the package, in one place (the stages' transcriptions add their own
``ipopt`` overrides on top, and `pressocp.compile_cache.oracle_options` the derivative settings), and
the check of a user's overrides before any solve (`check_nlpsol_options`)."""

from __future__ import annotations

import difflib
import io
import re
import threading
from collections.abc import Iterator
from contextlib import contextmanager, redirect_stdout
from typing import Any

import casadi as ca

#: No output from IPOPT or CasADi.
QUIET = {"ipopt.print_level": 0, "ipopt.sb": "yes", "print_time": False}
#: Options of every IPOPT call of the optimiser (quiet, MUMPS).
IPOPT_BASE = {**QUIET, "ipopt.max_iter": 300, "ipopt.tol": 1e-8, "ipopt.linear_solver": "mumps"}
#: Rigid transcription: exact Hessian, adaptive barrier (with the monotone one the 15-harmonic
#: default case stalled at 300 iterations). Its free mode (``adaptive_mu_globalization =
#: never-monotone-mode``) took press60's rigid stage from 142 to 72 iterations, but stopped at other
#: points of the flat min-max optimum, which re-simulated up to 0.8 % higher on the clearance model
#: (60 spm, 0.2 mm): not taken (docs/measurements.md, "Speed of the default calls"). Its KKT-error
#: globalization (``adaptive_mu_globalization = kkt-error``) halved press60's iterations (214 -> 88)
#: but stopped at its 300-iteration limit on press75 at 60 spm with a 0.05 mm wrist-pin clearance,
#: where the filter took 101: not taken (docs/decisions/2026-11-26-rigid-globalization.md).
IPOPT_RIGID = {**IPOPT_BASE, "ipopt.mu_strategy": "adaptive"}
#: On top of `IPOPT_RIGID`, the rigid stage's first solve: IPOPT stops at its acceptable level (overall
#: error 1e-4 for 3 iterations). The min-max optimum is flat and degenerate: press60's iterates reach
#: the objective to 4e-6 by iteration 48 and spend 77 more closing the dual (125 in all). Where that
#: answer stands (verified on the clearance model, `Strategy.run`), the relaxed re-solve starts from it
#: with its multipliers; everywhere else it is first continued to `IPOPT_RIGID`'s tolerance (a chain
#: started from the acceptable iterate itself did not converge on large_press, NR at margin 0.02;
#: docs/decisions/2026-11-28-rigid-acceptable.md).
IPOPT_RIGID_ACCEPTABLE = {"ipopt.acceptable_tol": 1e-4, "ipopt.acceptable_iter": 3}
#: Transcriptions with states, warm-started at a good point: a limited-memory Hessian (an exact one
#: would need adjoint sensitivities through the integrators, which fail on contact in IDAS; collocation
#: asks for the exact one), a small initial barrier parameter and
#: bound push keep IPOPT from pushing every inequality into the interior first. The monotone barrier
#: strategy is asked for: with a limited-memory Hessian IPOPT defaults to the adaptive one, which
#: ignores mu_init (mu rose to 0.25 on the 75 spm case and the second step left the smooth region).
IPOPT_WARM = {**IPOPT_BASE, "ipopt.hessian_approximation": "limited-memory", "ipopt.mu_strategy": "monotone", "ipopt.tol": 1e-6, "ipopt.acceptable_tol": 1e-4,
              "ipopt.acceptable_iter": 5, "ipopt.max_iter": 200, "ipopt.mu_init": 1e-4, "ipopt.bound_push": 1e-6,
              "ipopt.bound_frac": 1e-6}

#: IPOPT options of a primal-dual warm start (`solve_nlp` with multipliers): IPOPT starts at the given
#: point and multipliers, with a small barrier parameter, and pushes the bounds only slightly, so a
#: re-solve from an optimum with slightly changed bounds stays at that optimum.
IPOPT_WARM_START = {"ipopt.warm_start_init_point": "yes", "ipopt.mu_init": 1e-7, "ipopt.warm_start_bound_push": 1e-9,
                    "ipopt.warm_start_bound_frac": 1e-9, "ipopt.warm_start_slack_bound_push": 1e-9,
                    "ipopt.warm_start_slack_bound_frac": 1e-9, "ipopt.warm_start_mult_bound_push": 1e-9}

#: IPOPT options of a primal-dual warm start from a coarser grid's solution carried to a finer one
#: (`pressocp.ocp.prolong`): `IPOPT_WARM_START` with the collocation NLP's own initial barrier
#: parameter. The carried states do not meet the finer grid's collocation equations (scaled
#: infeasibility 0.3-0.8 on the 75 spm seed with 0.02 mm clearances), and at mu = 1e-7 IPOPT went
#: through restoration phases: two refined stages took 130 and 195 iterations at 1e-7, 81 and 101 at
#: 1e-5, 184 at 1e-3, and 200 (not converged) and 110 from the re-simulated response without
#: multipliers (docs/decisions/2026-11-29-refined-multipliers.md).
IPOPT_CARRIED_START = {**IPOPT_WARM_START, "ipopt.mu_init": 1e-5}

#: IPOPT options of the collocation NLP on top of `IPOPT_WARM`: the exact Hessian, zero initial
#: constraint multipliers instead of IPOPT's least-squares estimate (an extra linear solve that
#: changed nothing), no MUMPS scaling (its automatic choice made every linear solve dearer) and an
#: initial barrier parameter of 1e-5: at 1e-4 IPOPT spent about 50 iterations on the first barrier
#: problem alone (75 spm seed: target 88 and polish 82 iterations at 1e-4, 60 and 38 at 1e-5, the
#: verified optimum 145.16 and 145.14 N m; the adaptive strategy took 161).
IPOPT_COLLOCATION = {"ipopt.hessian_approximation": "exact", "ipopt.constr_mult_init_max": 0.0,
                     "ipopt.mumps_scaling": 0, "ipopt.mu_init": 1e-5}

#: What `Collocation.rescaled` adds: MUMPS's automatic scaling of the KKT matrix (twice the cost per
#: linear solve), and IPOPT's acceptable level at 1e-3. forming40 (60 kN over the window, 23.9 kN
#: counterbalance, 750 elements): without the scaling the target stage stopped at 200 iterations with
#: its dual infeasibility at 1e3-1e7 and restoration phases every few iterations; with it the same
#: start converged in 75 iterations. From another start (20.1 kN, margin 0.1) the scaled solve reached
#: its primal feasibility to 1e-12 by iteration 200 with steps of 1e-7, its dual infeasibility stuck
#: at 1.23e-4, just above the default acceptable level (1e-4), until its 300-iteration limit
#: (docs/measurements.md, 2026-11-27). The answer is re-simulated and verified either way.
IPOPT_RESCALED = {"ipopt.mumps_scaling": 77, "ipopt.acceptable_tol": 1e-3}

#: IPOPT options of a tracking re-solve (`resolve_tracking`): IPOPT starts at the given primal-dual point
#: with a barrier parameter near the one it ended at and no push into the interior, so that its
#: iterates follow the same local optimum instead of restarting the barrier (which can leave it for
#: another local optimum): the primal-dual warm start with a smaller barrier parameter.
IPOPT_TRACKING = {**IPOPT_BASE, **IPOPT_WARM_START, "ipopt.mu_init": 1e-9, "ipopt.mu_strategy": "monotone",
                  "ipopt.max_iter": 200}

#: The kinematic speed design (`pressocp.design.design_speed`): a small, smooth NLP solved tightly.
IPOPT_DESIGN = {**QUIET, "ipopt.max_iter": 500, "ipopt.tol": 1e-10}


#: Option sets `check_nlpsol_options` has accepted in this process (by their repr).
ACCEPTED: set[str] = set()
#: IPOPT options the check does not try: a probe would create or truncate the user's file.
NOT_TRIED = ("ipopt.output_file",)
#: Serialises the checks: `captured_stdout` redirects the whole process's ``sys.stdout``.
CAPTURE_LOCK = threading.Lock()


def check_nlpsol_options(name: str, options: Any) -> None:
    """Refuse, before any solve, extra nlpsol options (a transcription's ``ipopt``) that IPOPT or
    CasADi would refuse only when a stage builds its solver, minutes into a call.

    The options are set on a one-variable problem, as the stages set them (on top of `QUIET`), and
    IPOPT solves it: a name IPOPT or CasADi's nlpsol does not know, a value of the wrong type, out of
    IPOPT's range or not among its settings, or a linear solver IPOPT cannot load raises. The ``ipopt.*``
    keys are tried together (``linear_solver`` with ``hsllib``); when they fail, the key whose
    removal makes them pass is named, with IPOPT's explanation (its range or valid settings), which
    the check captures from what IPOPT prints. A set accepted once is not tried again.

    Parameters
    ----------
    name : str
        The field, for the message (e.g. ``"Collocation.ipopt"``).
    options : dict
        nlpsol options, string keys (``"ipopt.max_iter"``: IPOPT's; others: CasADi's nlpsol's).

    Raises
    ------
    ValueError
        Naming `name`, the key and its value, and why.
    """
    if not isinstance(options, dict) or not all(isinstance(k, str) for k in options):
        raise ValueError(f"{name} must be a dict of nlpsol options with string keys, e.g. "
                         f"{{'ipopt.max_iter': 50}}, got {options!r}")
    key = repr(sorted(options.items(), key=lambda kv: kv[0]))
    if not options or key in ACCEPTED:
        return
    tried = {k: v for k, v in options.items() if k.startswith("ipopt.") and k not in NOT_TRIED}
    rest = {k: v for k, v in options.items() if not k.startswith("ipopt.")}
    with CAPTURE_LOCK:
        refused = ipopt_refusal({**rest, **tried})  # one probe when all is well
        if refused is not None:
            if rest:
                alone = ipopt_refusal(tried) if tried else None
                if alone is None:  # IPOPT takes its own options: CasADi's are refused
                    raise ValueError(nlpsol_message(name, rest, refused[0]))
                refused = alone
            culprit = next((k for k in tried if ipopt_refusal({j: w for j, w in tried.items() if j != k}) is None), None)
            if culprit is None:
                raise ValueError(f"{name}: IPOPT refuses the options {tried}: {refused[0]}"
                                 f"{ipopt_explanation(refused[1], '')}")
            reason, printed = ipopt_refusal({culprit: tried[culprit]}) or refused
            raise ValueError(f"{name}: IPOPT refuses {culprit} = {tried[culprit]!r}: {reason}"
                             f"{ipopt_explanation(printed, culprit)}")
    ACCEPTED.add(key)


def ipopt_refusal(options: dict) -> tuple[str, str] | None:
    """Why IPOPT or CasADi refuses `options` on a one-variable problem (set on top of `QUIET`, then
    solved), and what they printed meanwhile; None when IPOPT ran with them (whatever its return
    status, except ``Invalid_Option``: an iteration limit of 0 is an option like another)."""
    x = ca.SX.sym("x")
    with captured_stdout() as printed:
        try:
            solver = ca.nlpsol("option_check", "ipopt", {"x": x, "f": (x - 1.0) ** 2}, {**QUIET, **options})
            solver(x0=0.0)
            status = str(solver.stats()["return_status"])
        except RuntimeError as err:
            status = casadi_reason(err)
        else:
            if status != "Invalid_Option":
                return None
    return status, printed[0]


def nlpsol_message(name: str, rest: dict, reason: str) -> str:
    """The message for nlpsol options (`rest`, no ``ipopt.`` prefix) CasADi refuses with `reason`: an
    unknown one that is IPOPT's is pointed to its prefix, else to the nearest nlpsol option."""
    hint = ""
    unknown = re.search(r"Unknown option: (\S+)", reason)
    if unknown:
        bad = unknown.group(1)
        if "." not in bad and bad in rest and ipopt_refusal({f"ipopt.{bad}": rest[bad]}) is None:
            hint = f"; IPOPT's own options take the prefix 'ipopt.': did you mean 'ipopt.{bad}'?"
        else:
            close = difflib.get_close_matches(bad, NLPSOL_OPTIONS, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
    return f"{name}: CasADi's nlpsol refuses {sorted(rest)}: {reason}{hint}"


#: Options of CasADi's nlpsol that users set (for the suggestion of a misspelt one).
NLPSOL_OPTIONS = ("print_time", "expand", "error_on_fail", "verbose", "verbose_init", "record_time",
                  "calc_lam_p", "calc_lam_x", "calc_f", "calc_g", "bound_consistency", "warn_initial_bounds",
                  "iteration_callback_step", "iteration_callback_ignore_errors", "max_io", "jit", "compiler",
                  "jit_options", "print_in", "print_out", "regularity_check", "common_options")


def casadi_reason(err: RuntimeError) -> str:
    """The reason in a CasADi error: the text after its last source location (``file.cpp:123:``), on
    one line, without CasADi's list of similar option names."""
    text = str(err).split("Did you mean")[0]
    parts = re.split(r"\S+\.(?:cpp|hpp):\d+:", text)
    return " ".join(parts[-1].split()) or " ".join(text.split())


def ipopt_explanation(printed: str, key: str) -> str:
    """What IPOPT printed about a refused option (the refused setting, the allowed range or the valid
    settings), as a parenthesis for a message; for a linear solver, where the others come from."""
    lines = printed.splitlines()
    why = [line.strip() for line in lines if line.startswith("Setting:") or " <= " in line]
    if "Valid Settings:" in lines:
        names = [line.split()[0] for line in lines[lines.index("Valid Settings:") + 1 :]
                 if line.startswith("\t") and line.split()]
        why.append("valid settings: " + ", ".join(names))
    if key == "ipopt.linear_solver":
        why.append("'mumps' comes with CasADi; HSL's solvers need their library, named by 'ipopt.hsllib'")
    return f" ({'; '.join(why)})" if why else ""


@contextmanager
def captured_stdout() -> Iterator[list[str]]:
    """Within the block, what is printed through Python's ``sys.stdout`` (where CasADi passes IPOPT's
    messages) goes to a buffer; the list the block gets holds that text after it. It redirects the
    whole process's ``sys.stdout``: callers hold `CAPTURE_LOCK`."""
    text: list[str] = [""]
    buffer = io.StringIO()
    try:
        with redirect_stdout(buffer):
            yield text
    finally:
        text[0] = buffer.getvalue()
