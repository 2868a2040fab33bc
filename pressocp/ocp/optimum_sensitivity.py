"""Sensitivity of an optimal design to press parameters: dJ*/dp and d(coefficients)/dp from the
NLP's parametric sensitivity.

    s = po.optimum_sensitivities(result, ("slider_mass", "wrist_pin.clearance"))
    s.table                     # dJ*/dp, normalised, how far the active set holds
    s.coefficients              # d(Fourier coefficients)/dp

The stage that produced the answer (the rigid press, or collocation on the clearance or flexible
model) is solved once more, from the answer, with the parameters as the NLP's p (the model built
with them as symbols); the implicit function theorem on its KKT system (`pressocp.ocp.kkt`) then gives
the derivatives for every parameter at the cost of one linear solve. The re-solve starts at the
optimum, so it takes few iterations; its objective is reported next to the result's.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from .. import checks as chk
from ..model import ModelSpec, build_model
from ..objectives import get as get_objective
from ..params import check_parameter
from ..problem import SpeedProblem
from ..speed import FourierSpeed
from .kkt import KktSensitivity, kkt_sensitivity
from .nlp import ParametricPoint
from .ocp_result import OcpResult
from .stage import StageResult, Transcription, WarmStart, standing_stage, transcription_from

if TYPE_CHECKING:
    import pandas as pd

#: Parameters that move the working window (its heights are fractions of the stroke) or the ideal
#: press's kinematics: a derivative of the optimum holding the problem fixed does not exist for them.
KINEMATIC = ("crank_radius", "rod_length")
#: A predicted active-set change within this relative step of p makes d(coefficients)/dp one-sided.
ONE_SIDED = 1e-6
#: ``derivative`` and ``derivative_check`` agree when they differ by at most this share of the larger
#: one, or when both are below `NEGLIGIBLE` in normalised terms (p / J* dJ*/dp).
AGREE_RTOL = 0.05
#: A normalised derivative below this is zero for the agreement test.
NEGLIGIBLE = 1e-6


def derivatives_agree(derivative: float, check: float, scale: float) -> bool:
    """Whether dJ*/dp by the envelope theorem and by the optimum's own derivative agree: within
    `AGREE_RTOL` of the larger, or both under `NEGLIGIBLE` x `scale` (``scale`` = J*/|p|, the
    objective's unit per unit of p). When they do not, the KKT solve is not sound at this optimum
    (dependent or degenerate active constraints), and neither number is to be trusted."""
    big = max(abs(derivative), abs(check))
    return bool(abs(derivative - check) <= AGREE_RTOL * big or big <= NEGLIGIBLE * abs(scale))


class SensitivityError(RuntimeError):
    """The re-solve at the answer did not converge, so the KKT system is not at a solution."""


@dataclass
class OptimumSensitivities:
    """Derivatives of an optimal design with respect to press parameters.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per parameter: ``parameter_value`` (SI), ``objective`` (J*, the objective's unit),
        ``derivative`` (dJ*/dp, envelope theorem), ``derivative_check`` (the same from the optimum's
        own derivative; the two agree when the KKT solve is sound), ``trustworthy``
        (`derivatives_agree`: False means neither is to be trusted, and a warning says so; re-solve
        or sweep that parameter instead), ``normalised`` (p / J* dJ*/dp),
        ``step_up`` and ``step_down`` (relative steps dp/p to the first predicted change of the active
        set, weakly active constraints aside) with ``change_up`` and ``change_down`` (the constraint
        group that changes), ``weakly_active`` (inequalities at their bound with a multiplier near
        zero: they may enter or leave at once; a min-max optimum has many in its epigraph),
        ``kkt_residual`` and ``kkt_regularisation`` (`KktSensitivity`: a regularised, singular KKT
        matrix means dependent active constraints, whose multipliers are one of a set) and
        ``coefficients_one_sided`` (weakly active constraints, or an active-set change within
        `ONE_SIDED` relative: d(coefficients)/dp holds for one direction of p only). dJ*/dp is
        two-sided all the same when the multipliers are unique (a nonsingular KKT matrix,
        ``kkt.residual`` small): it is the Lagrangian's partial derivative, which does not depend on
        which of the weakly active constraints hold.
    coefficients : pandas.DataFrame
        d(Fourier coefficient)/dp, rad/s per unit of p: rows ``a1..an, b1..bn``, a column per parameter.
        A min-max optimum can be flat in some coefficient directions (many designs share the peak), and
        then re-solves at p +- dp land anywhere on the flat set: trust this only where
        ``coefficients_one_sided`` is False.
    stage : str
        The stage whose NLP was differentiated ("rigid", "no_reversal", "target", "flexible" or "polish_k").
    objective : float
        J* of the re-solve (its unit).
    result_objective : float
        J* as the result's stage reported it.
    active, weakly_active : dict
        Active and weakly active inequality constraints per group (e.g. the epigraph's samples).
    resolve_time, kkt_time : float
        s: the re-solve at the answer (model build, NLP, IPOPT) and the sensitivity (derivatives,
        KKT factorisation and solve).
    kkt : KktSensitivity
    speed : FourierSpeed
        The re-solved optimum.
    problem : SpeedProblem
        The problem of the differentiated stage (with the no-reversal bound when that stage answered).
    transcription : Transcription
        The stage's transcription, with its settings.
    model : ModelSpec
        The stage's model level.
    point : ParametricPoint
        The stage's NLP at the re-solved optimum (its solver, solution and multipliers):
        `pressocp.ocp.kkt.resolve_tracking` follows that optimum to other parameter values.
    to_objective : float
        dJ = to_objective d(NLP objective): the NLP minimises a scaled objective.
    """

    table: pd.DataFrame
    coefficients: pd.DataFrame
    stage: str
    objective: float
    result_objective: float
    active: dict
    weakly_active: dict
    resolve_time: float
    kkt_time: float
    kkt: KktSensitivity
    speed: FourierSpeed
    problem: SpeedProblem
    transcription: Transcription
    model: ModelSpec
    point: ParametricPoint | None = None
    to_objective: float = 1.0

    def derivative(self, parameter: str) -> float:
        """dJ*/dp of one parameter."""
        row = self.table[self.table["parameter"] == parameter]
        if row.empty:
            raise KeyError(f"no row for {parameter!r}; parameters: {', '.join(self.table['parameter'])}")
        return float(row["derivative"].iloc[0])


def answer_stage(result: OcpResult) -> StageResult:
    """The stage that produced the result's answer (`standing_stage`)."""
    if not result.success:
        raise ValueError(f"the result did not converge ({result.status}): an optimum is needed")
    return standing_stage(result.stages)


def per_group(mask: np.ndarray, groups: list) -> dict[str, int]:
    """Number of True entries of `mask` per constraint group name (groups without one left out)."""
    out: dict[str, int] = {}
    for name, i0, size in groups:
        k = int(mask[i0 : i0 + size].sum())
        if k:
            out[name] = out.get(name, 0) + k
    return out


def differentiated_nlp(result: OcpResult, stage: StageResult, names: tuple[str, ...]
                       ) -> tuple[Transcription, SpeedProblem, ModelSpec]:
    """The transcription, problem and model whose NLP is re-solved and differentiated at the answer.

    The answer's own stage NLP with IPOPT's default options; the ideal press's stages keep their
    rod-tension bounds and take no bearing parameters; a transcription that gives no parametric point
    (multiple shooting) is refused before any solve.
    """
    problem = result.problem
    if not stage.settings:
        raise ValueError(f"the answer's stage {stage.name!r} records no transcription settings (a result saved "
                         "before they were recorded): optimise again")
    transcription = replace(transcription_from(stage.settings), ipopt={})  # the stage's NLP, default IPOPT options
    if not transcription.has_states:  # the ideal press's stages: rigid, no_reversal, relaxed
        bearings = [n for n in names if "." in n]
        if bearings:
            raise ValueError(f"the answer is the ideal press's optimum (verified on the clearance model), which "
                             f"does not depend on {', '.join(bearings)}: differentiate a clearance-model optimum "
                             "(optimize_speed(..., strategy='all')) or sweep it")
        problem = problem.replace(min_tension=stage.details.get("min_tension_N"),
                                  max_tension=stage.details.get("max_tension_N"))
        spec = result.model
    elif transcription.gives_parametric_point:
        spec = result.model if stage.model == result.model.describe() else ModelSpec("rigid", result.model.clearance, mechanism=result.model.mechanism)
    else:
        raise ValueError(f"the answer comes from {type(transcription).__name__} (stage {stage.name!r}); optimum "
                         "sensitivities need a Rigid or Collocation answer: optimise with the default transcription")
    return transcription, problem, spec


def optimum_sensitivities(result: OcpResult, parameters: Sequence[str], progress: bool = False
                          ) -> OptimumSensitivities:
    """dJ*/dp and d(coefficients)/dp of an optimal design for press parameters p.

    Parameters
    ----------
    result : OcpResult
        A converged optimum (`optimize_speed`; also one reloaded from JSON).
    parameters : sequence of str
        Dotted names in `pressocp.params.NUMERIC_PARAMETERS`, but not the kinematic ones (`KINEMATIC`);
        a bearing's parameters only when the answer comes from a model with clearance.
    progress : bool
        A tqdm bar over the re-solve's iterations.

    Returns
    -------
    OptimumSensitivities

    Raises
    ------
    ValueError
        An unknown, kinematic or (for a rigid-press answer) bearing parameter, an unconverged result,
        or an answer from multiple shooting (checked before any solve).
    SensitivityError
        The re-solve at the answer did not converge.
    """
    chk.instance("result", result, OcpResult)
    names = checked_names(parameters)
    stage = answer_stage(result)
    t0 = time.perf_counter()
    transcription, problem, spec = differentiated_nlp(result, stage, names)
    model = build_model(problem.press, spec.rod, spec.clearance, spec.n_elements, problem.n_harmonics, names,
                        n_modes=spec.n_modes, mechanism=spec.mechanism)
    again = transcription.solve(problem, model, WarmStart(result.speed), "sensitivity", progress)
    if not again.success or again.point is None:
        raise SensitivityError(f"the re-solve at the answer did not converge ({again.status}); "
                               "the optimum's derivatives need a converged NLP")
    resolve_time = time.perf_counter() - t0
    t1 = time.perf_counter()
    k = kkt_sensitivity(again.point)
    kkt_time = time.perf_counter() - t1

    objective = get_objective(problem.objective)
    f_opt = float(again.point.solver.get_function("nlp_f")(again.point.x, again.point.p))
    J = again.objective
    to_J = J / f_opt if objective.kind == "peak" else J / (2.0 * f_opt)  # dJ = to_J df
    n2 = 2 * problem.n_harmonics
    rows = optimum_rows(names, np.asarray(again.point.p, float).ravel()[: len(names)], k, J, to_J)
    doubtful = [r["parameter"] for r in rows if not r["trustworthy"]]
    if doubtful:
        warnings.warn(f"dJ*/dp of {', '.join(doubtful)}: the envelope theorem and the optimum's own derivative "
                      "disagree (table columns derivative and derivative_check), so the KKT solve is not sound "
                      "there and neither value is to be trusted; re-solve at p +- dp or sweep the parameter",
                      RuntimeWarning, stacklevel=2)
    labels = [f"a{i + 1}" for i in range(n2 // 2)] + [f"b{i + 1}" for i in range(n2 // 2)]
    import pandas as pd  # 0.5 s to import: only where a table is made

    coeffs = pd.DataFrame(k.dx_dp[:n2, :], index=labels, columns=list(names))
    return OptimumSensitivities(
        table=pd.DataFrame(rows), coefficients=coeffs, stage=stage.name, objective=J,
        result_objective=stage.objective, active=per_group(k.active, again.point.groups),
        weakly_active=per_group(k.weak, again.point.groups),
        resolve_time=resolve_time, kkt_time=kkt_time, kkt=k, speed=again.speed, problem=problem,
        transcription=transcription, model=spec, point=again.point, to_objective=to_J)


def checked_names(parameters: Sequence[str]) -> tuple[str, ...]:
    """The parameters' dotted names, checked: known, none twice, none kinematic (`KINEMATIC`)."""
    names = tuple(check_parameter(n) for n in parameters)
    if not names:
        raise ValueError("parameters must name at least one press parameter")
    if len(set(names)) != len(names):
        raise ValueError(f"parameters name one twice: {names!r}")
    for n in names:
        if n in KINEMATIC:
            raise ValueError(f"parameter {n!r} moves the working window and the kinematics (the window's heights "
                             "are fractions of the stroke): sweep it instead (po.sweep)")
    return names


def optimum_rows(names: tuple[str, ...], values: np.ndarray, k: KktSensitivity, J: float, to_J: float) -> list[dict]:
    """The rows of `OptimumSensitivities.table`, one per parameter (`names` at `values`), from the KKT
    sensitivity `k` of the NLP whose objective f gives the optimum's value `J` with dJ = `to_J` df."""
    weak = int(k.weak.sum())
    rows = []
    for j, n in enumerate(names):
        p = float(values[j])
        d, dc = to_J * float(k.df_dp[j]), to_J * float(k.df_dp_direct[j])
        rows.append({
            "parameter": n, "parameter_value": p, "objective": J, "derivative": d, "derivative_check": dc,
            "trustworthy": derivatives_agree(d, dc, J / abs(p)),
            "normalised": to_J * float(k.df_dp[j]) * p / J,
            "step_up": k.step_up[j] / abs(p), "step_down": k.step_down[j] / abs(p),
            "change_up": k.change_up[j], "change_down": k.change_down[j], "weakly_active": weak,
            "kkt_residual": k.residual, "kkt_regularisation": k.regularisation,
            "coefficients_one_sided": bool(weak or min(k.step_up[j], -k.step_down[j]) / abs(p) < ONE_SIDED)})
    return rows


__all__ = ["AGREE_RTOL", "KINEMATIC", "NEGLIGIBLE", "ONE_SIDED", "OptimumSensitivities", "SensitivityError",
           "derivatives_agree", "optimum_sensitivities"]
