"""Which model level a scene needs (`recommend_model`): no more model than the loads require.

Two questions, both answered on the ideal press (closed form, milliseconds):

* **Do the journals leave their walls?** Without a process force the slider hangs from the rod, so the
  rod is in tension and the journals rest on their bearing walls; a clearance joint only shifts the
  ram by its clearance. When the axial pin force changes sign (the ram's downward acceleration
  exceeds g, or a process force pushes the rod), the journal crosses its clearance and hits the other
  wall: the clearance model is needed.
* **Does the rod bend dynamically?** The rod's first bending mode (pinned-pinned Euler-Bernoulli beam)
  against the highest harmonic of its loads (the axial pin force and the rod's angular acceleration,
  which drives its transverse inertia load): a load harmonic at a fraction r of the mode is amplified
  by 1 / (1 - r^2), 1 % at r = 0.1. Within a factor `MODE_FACTOR` the flexible rod is needed.

The flexible level is named as a concrete model: the 8-element rod reduced to its first 2 bending
modes (`REDUCED_ROD`), the fewest modes within 1e-3 of the 8-element rod's peaks on every periodic scene
measured, and faster per cycle than the 4-element rod (docs/measurements.md, "How many modes").

The factor 10 is deliberately conservative. "clearance" locates impacts but does not size them: the
size of an impact peak also depends on the rod's bending. A design that keeps the rod in tension (an
optimum) needs no more than the clearance level. How each level compares with the flexible rod across
scenes is measured in docs/measurements.md ("Model levels across scenes").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import checks as chk
from .model import ModelSpec
from .params import PressParams
from .rigid import rigid_inverse_dynamics, rigid_kinematics
from .speed import FourierSpeed

#: Samples of one period for the spectra.
SAMPLES = 4096
#: A harmonic counts when its amplitude is at least this share of the largest (the mean left out).
HARMONIC_SHARE = 0.01
#: The flexible rod is needed when its first bending mode is within this factor of the highest load
#: harmonic (1 % dynamic amplification at the factor).
MODE_FACTOR = 10.0
#: The level names, plainest first.
LEVELS = ("rigid", "clearance", "flexible")
#: (elements, modes) of the flexible rod the "flexible" level names. Peak torque and pin forces against
#: the 8-element rod, each periodic at rtol 1e-10 (2026-11-27): 2 modes within 1.7e-4 on the impacting
#: 69 spm design, 1.1e-4 and 2.7e-5 on the slender-rod scene's design and rigid optimum, 1.1e-7 on the
#: 75 spm seed optimum; 1 mode 3.0e-3 off on the impacting design; the 4-element rod 1.5e-3 off on the
#: slender rod's optimum. A cycle of the impacting design at rtol 1e-5: 0.42 s against 0.64 s for the
#: 4-element rod and 1.2 s for the 8-element one.
REDUCED_ROD = (8, 2)


@dataclass
class ModelRecommendation:
    """The model level a scene needs and why.

    Attributes
    ----------
    level : {"rigid", "clearance", "flexible"}
        "rigid": the ideal press gives the loads; "clearance": the rigid rod with the press's clearance
        joints; "flexible": the flexible rod (with the clearance joints).
    reason : str
        The measured numbers behind it.
    min_rod_tension : float
        Smaller axial pin force of the two pins over the cycle on the ideal press, N (negative: the
        joint force reverses).
    first_mode : float
        First bending mode of the rod, pinned at both ends, Hz.
    load_frequency : float
        Highest harmonic of the rod's loads with at least `HARMONIC_SHARE` of the largest amplitude, Hz.
    spec : ModelSpec
        The level as a model to build (``spec.build(params, n_harmonics)``): the ideal press, the rigid
        rod with both clearance joints, or the flexible rod reduced to `REDUCED_ROD` with them.
    """

    level: str
    reason: str
    min_rod_tension: float
    first_mode: float
    load_frequency: float
    spec: ModelSpec

    @property
    def mode_ratio(self) -> float:
        """first_mode / load_frequency."""
        return self.first_mode / self.load_frequency


#: Each level as a model (`ModelRecommendation.spec`).
LEVEL_SPECS = {"rigid": ModelSpec("rigid", ()), "clearance": ModelSpec("rigid"),
               "flexible": ModelSpec("flexible", n_elements=REDUCED_ROD[0], n_modes=REDUCED_ROD[1])}


def highest_harmonic(signal: np.ndarray, period: float) -> float:
    """Frequency of the highest harmonic of a periodic signal (one period, uniform samples) with at least
    `HARMONIC_SHARE` of the largest amplitude (the mean left out), Hz; 0 for a constant."""
    amp = np.abs(np.fft.rfft(signal))[1:]
    if amp.max(initial=0.0) <= 0.0:
        return 0.0
    k = np.flatnonzero(amp >= HARMONIC_SHARE * amp.max())
    return float((k[-1] + 1) / period)


def recommend_model(params: PressParams, speed: FourierSpeed) -> ModelRecommendation:
    """The model level the loads of `params` driven at `speed` need (see the module's notes).

    Parameters
    ----------
    params : PressParams
    speed : FourierSpeed
        The crank speed (a design, an optimum, or `FourierSpeed.constant(T)`).

    Returns
    -------
    ModelRecommendation
    """
    chk.instance("params", params, PressParams)
    chk.instance("speed", speed, FourierSpeed)
    T = speed.period
    t = np.linspace(0.0, T, SAMPLES, endpoint=False)
    th, om, al = speed.evaluate(t)
    dyn = rigid_inverse_dynamics(params, th, om, al)
    tension = np.minimum(dyn["crank_pin_tension"], dyn["wrist_pin_tension"])
    rod_alpha = rigid_kinematics(params, th, om, al)["rod_angular_acceleration"]
    f_load = max(highest_harmonic(dyn["crank_pin_tension"], T), highest_harmonic(rod_alpha, T), 1.0 / T)
    f_mode = params.rod_first_bending_frequency / (2 * np.pi)
    t_min = float(tension.min())
    reverses = t_min <= 0.0
    tension_note = (f"the rod force reverses (axial pin force down to {t_min:.4g} N on the ideal press): the "
                    "journals cross their clearances and hit" if reverses else
                    f"the rod stays in tension (axial pin force at least {t_min:.4g} N): the journals rest on "
                    "their bearing walls")
    mode_note = (f"the rod's first bending mode ({f_mode:.4g} Hz) is {f_mode / f_load:.3g} x the highest load "
                 f"harmonic ({f_load:.4g} Hz)")
    if f_mode < MODE_FACTOR * f_load:
        level = "flexible"
        reason = (f"{mode_note}, within a factor {MODE_FACTOR:g} -> flexible ({LEVEL_SPECS[level].describe()}); "
                  f"{tension_note}")
    elif reverses:
        level = "clearance"
        reason = (f"{tension_note} -> clearance; {mode_note}, more than {MODE_FACTOR:g} -> rigid rod (for the "
                  "loads between impacts: the size of an impact peak also depends on the rod's bending)")
    else:
        level = "rigid"
        reason = f"{tension_note} -> rigid press; {mode_note}, more than {MODE_FACTOR:g} -> rigid rod"
    return ModelRecommendation(level, reason, t_min, f_mode, f_load, LEVEL_SPECS[level])


__all__ = ["HARMONIC_SHARE", "LEVELS", "LEVEL_SPECS", "REDUCED_ROD", "MODE_FACTOR", "ModelRecommendation", "highest_harmonic", "recommend_model"]
