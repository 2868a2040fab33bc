"""The press DAE: rigid limit, energy balance, flexible rod (modes, Simeon benchmark), cross-method
agreement, the impacts of the kinematic design at 75 spm, bad input and integrator failures.

References: the rigid inverse dynamics (itself checked against tests/references/newton_euler.py),
the Euler-Bernoulli formula, the Simeon slider crank (shared/reference/benchmarks.md section 1),
work-energy bookkeeping and scipy's Radau on the same equations.
"""

import numpy as np
import pytest
import scipy.linalg as sla

from pressocp import Bearing, Counterbalance, FourierSpeed, PressParams, ProcessForce, beam, rigid_response
from pressocp.mechanism.slider_crank import flexible_rod_energies
from pressocp.model import build_model
from pressocp.simulate import (Integrator, SimulationError, expect_settled, for_repeated_use, newton_periodic,
                               periodic_orbit, periodic_state, runs_compiled, simulate)
from pressocp.studies import simeon_crank

FLORES_PERIOD = 60.0 / 5000.0


def _rel_peak_errors(res, ref, names=("torque", "crank_pin_force", "wrist_pin_force", "slider_normal_force")):
    return {n: res.peak(n) / ref.peak(n) - 1 for n in names}


#: A press with both extra ram forces: a gas counterbalance and a process-force curve
#: (their torque on the ideal press is checked against virtual work in test_ram_forces.py).
RAM_FORCES = dict(counterbalance=Counterbalance(force=2500.0, gas_length=0.3, exponent=1.4),
                  process_force=ProcessForce(heights=(0.02, 0.05, 0.07), forces=(0.0, 4000.0, 500.0)))


@pytest.mark.parametrize("extra", [{}, RAM_FORCES], ids=["bare", "ram_forces"])
def test_rigid_model_equals_rigid_inverse_dynamics(extra):
    p = PressParams(crank_com=0.01, **extra)
    s = FourierSpeed(1.0, [2.0, 1.0], [0.5, -1.0], theta0=0.3)
    r = simulate(build_model(p, clearance=()), s, n_out=301)
    ref = rigid_response(p, s, r.t)
    for n in ("torque", "ram_acceleration", "slider_normal_force", "crank_pin_force", "wrist_pin_force"):
        assert np.allclose(getattr(r, n), getattr(ref, n), rtol=0, atol=1e-9 * ref.peak(n)), n


@pytest.mark.parametrize("stiffness", [None, 1e14], ids=["hertz", "stiffer"])
def test_rigid_limit_flores(stiffness):
    """Both clearances 1 um with stiff contact -> within 2 % of the ideal joints (5000 rpm, g = 0)."""
    b = Bearing(clearance=1e-6, journal_radius=0.01, stiffness=stiffness)
    p = PressParams.flores().replace(crank_pin=b, wrist_pin=b)
    s = FourierSpeed.constant(FLORES_PERIOD)
    r = simulate(build_model(p), s, periodic=True, integrator=Integrator(method="cvodes", rtol=1e-8))
    ref = rigid_response(p, s, r.t)
    for n in ("torque", "crank_pin_force", "wrist_pin_force", "slider_normal_force"):
        assert np.max(np.abs(getattr(r, n) - getattr(ref, n))) <= 0.02 * ref.peak(n), n
    assert max(abs(e) for e in _rel_peak_errors(r, ref).values()) < 0.02


@pytest.mark.slow  # 13 s; the flexible rod is checked by default against Simeon's slider crank
def test_flexible_rod_with_large_EI_is_rigid():
    p = PressParams.flores(clearance=1e-6).replace(rod_youngs_modulus=2.1e13)
    s = FourierSpeed.constant(FLORES_PERIOD)
    r = simulate(build_model(p, rod="flexible", clearance=(), n_elements=4), s, periodic=True, integrator=Integrator(method="cvodes", rtol=1e-8))
    ref = rigid_response(p, s, r.t)
    assert max(abs(e) for e in _rel_peak_errors(r, ref).values()) < 1e-3
    assert np.max(np.abs(r.rod_midspan_deflection)) < 1e-7


@pytest.mark.parametrize("rod, extra", [("rigid", {}), ("rigid", RAM_FORCES),
                                        pytest.param("flexible", {}, marks=pytest.mark.slow)])  # flexible: 13 s
def test_energy_balance_with_clearances(rod, extra, impact_speed):
    """W_motor + W_process = dT + dV + contact work (stored + dissipated) + rod damping work; the
    counterbalance's energy is potential."""
    m = build_model(PressParams(**extra), rod=rod, n_elements=2)
    r = simulate(m, impact_speed, t_end=0.8 if rod == "rigid" else 0.3, integrator=Integrator(method="cvodes", rtol=1e-10 if rod == "rigid" else 1e-9), work=True)
    E = r.energy
    dE = E["kinetic_end"] + E["potential_end"] - E["kinetic_start"] - E["potential_start"]
    imbalance = E["motor_work"] + E["process_work"] - dE - E["contact_work"] - E["rod_damping_work"]
    scale = max(abs(E["motor_work"]), abs(dE), abs(E["contact_work"]))
    assert abs(imbalance) <= 1e-4 * scale
    assert E["contact_work"] - E["contact_elastic_work"] > 0  # the contacts dissipate


def test_pinned_pinned_frequencies():
    """First three bending frequencies within 0.5 % at 8 elements; error falls with refinement."""
    p = PressParams()
    rho_a, EI, L = p.rod_mass / p.rod_length, p.rod_youngs_modulus * p.rod_area_moment, p.rod_length
    exact = np.array([(k * np.pi / L) ** 2 * np.sqrt(EI / rho_a) for k in (1, 2, 3)])
    errors = []
    for n in (2, 4, 8, 16):
        M, K = beam.pinned_pinned_matrices(L, n, rho_a, EI)
        w = np.sqrt(np.sort(sla.eigh(K, M, eigvals_only=True))[:3])
        errors.append(np.abs(w / exact - 1))
    assert np.all(errors[2] < 0.005)
    assert np.all(np.diff([e[0] for e in errors]) < 0)  # monotone convergence of mode 1
    # Hermite cubics: eigenvalue error O(h^4) -> about 16x per halving
    assert errors[1][0] / errors[2][0] > 10
    assert p.rod_first_bending_frequency == pytest.approx(exact[0])


@pytest.mark.parametrize("n_elements", [1, 3, 8])
def test_flexible_rod_energies_equal_sums_over_the_rod(n_elements):
    """The rod's energies from its integrals equal sums over Gauss points of the moving rod, with
    each point's velocity a central difference of its position along a straight path in time."""
    p = PressParams()
    rng = np.random.default_rng(n_elements)
    L, rho_a, ei = p.rod_length, p.rod_mass / p.rod_length, p.rod_youngs_modulus * p.rod_area_moment
    A0, A_dot = rng.normal(size=2) * 0.1, rng.normal(size=2)
    phi0, phi_dot = 0.3, 2.7
    u0, u_dot = rng.normal(size=2 * n_elements) * 1e-3, rng.normal(size=2 * n_elements) * 0.1

    def points(t):  # positions of the Gauss points at time t, their weights, w''
        phi = phi0 + phi_dot * t
        d, n = np.array([np.sin(phi), np.cos(phi)]), np.array([-np.cos(phi), np.sin(phi)])
        u = u0 + u_dot * t
        Le = L / n_elements
        out = []
        for e, dofs in enumerate(beam.element_dofs(n_elements)):
            ue = np.array([u[k] if k is not None else 0.0 for k in dofs])
            for s, wgt in zip(beam.GAUSS_S, beam.GAUSS_WS):
                N, N2 = beam.hermite(s, Le)
                out.append((A0 + A_dot * t - (e + s) * Le * d + (N @ ue) * n, wgt * Le, N2 @ ue))
        return out

    h = 1e-6
    kinetic = sum(0.5 * rho_a * wgt * np.sum(((rp - rm) / (2 * h)) ** 2)
                  for (rp, wgt, _), (rm, _, _) in zip(points(h), points(-h)))
    gravity = sum(rho_a * wgt * p.gravity * r[1] for r, wgt, _ in points(0.0))
    strain = sum(0.5 * ei * wgt * w2**2 for _, wgt, w2 in points(0.0))
    d0 = np.array([np.sin(phi0), np.cos(phi0)])
    T, V, U = (float(v) for v in flexible_rod_energies(p, n_elements, A0, A_dot, d0, phi_dot, u0, u_dot))
    assert T == pytest.approx(kinetic, rel=1e-8)
    assert V == pytest.approx(gravity, rel=1e-12)
    assert U == pytest.approx(strain, rel=1e-12)


def test_a_flexible_rod_carries_its_length_as_a_parameter():
    """With the rod's length and mass carried as symbols, the flexible rod's outputs and
    accelerations at the press's values equal those of the model built with numbers, and their
    derivatives with respect to the length equal central differences of models built with numbers
    at l -/+ h (the same physical state: the scaling stays at the press's values)."""
    import casadi as ca

    p = PressParams()
    carried = build_model(p, rod="flexible", n_elements=3, parameters=("rod_length", "rod_mass"))
    speed = FourierSpeed.constant(0.8, n_harmonics=carried.n_harmonics)
    x = np.random.default_rng(3).normal(size=carried.nx) * 0.3
    x[:4] = [0.3, -1.01, -0.2, 1.02]  # both journals pressed 2-5 % of their clearance into the bearing
    names = ("ram_height", "rod_midspan_deflection")

    def values(model, t, x, p):
        out = model.outputs(t=t, x=x, p=p)
        return ca.vertcat(*[out[n] for n in names], model.accelerations(t, x, p))

    def numeric(length):
        m = build_model(p.with_value("rod_length", length), rod="flexible", n_elements=3)
        return np.asarray(values(m, 0.1, x * carried.x_scale / m.x_scale, m.parameters(speed))).ravel()

    pv = carried.parameters(speed)
    assert np.isfinite(values(carried, 0.1, x, pv)).all()
    assert np.allclose(np.asarray(values(carried, 0.1, x, pv)).ravel(), numeric(p.rod_length), rtol=1e-9,
                       atol=0.0)
    t, X, P = ca.SX.sym("t"), ca.SX.sym("x", carried.nx), ca.SX.sym("p", carried.p.numel())
    k = len(pv) - 2  # the rod length's place in p
    dl = ca.Function("d", [t, X, P], [ca.jacobian(values(carried, t, X, P), P)[:, k]])
    h = 1e-4 * p.rod_length  # smaller steps lose digits to cancellation in the accelerations
    fd = (numeric(p.rod_length + h) - numeric(p.rod_length - h)) / (2 * h)
    ad = np.asarray(dl(0.1, x, pv)).ravel()
    assert np.all(np.abs(fd) > 0.0)  # every value depends on the length
    assert np.allclose(ad, fd, rtol=1e-5, atol=0.0)


def test_simeon_flexible_slider_crank():
    r = simeon_crank(n_elements=4)
    p = PressParams.simeon()
    slider = p.crank_radius + p.rod_length - r.ram_height[-1]  # distance from the crank axis
    assert slider == pytest.approx(0.169737333, rel=1e-4)
    assert -r.ram_velocity[-1] == pytest.approx(-8.7531, rel=1e-3)
    # midspan deflection: 1.8932e-4 m at 0.1 s; extremes about +-1.65 mm (different discretisation)
    assert r.rod_midspan_deflection[-1] == pytest.approx(1.8932e-4, rel=0.02)
    assert np.max(r.rod_midspan_deflection) == pytest.approx(1.65e-3, rel=0.02)
    assert np.min(r.rod_midspan_deflection) == pytest.approx(-1.65e-3, rel=0.02)


@pytest.fixture(scope="module")
def settled_impact_state(impact_speed):
    """Scaled state after two cycles of the impacting design (CVODES, rtol 1e-9)."""
    m = build_model(PressParams())
    return m, simulate(m, impact_speed, t_end=1.6, integrator=Integrator(method="cvodes", rtol=1e-9), n_out=3).states[:, -1] / m.x_scale


@pytest.mark.parametrize("method", ["idas", pytest.param("scipy-radau", marks=pytest.mark.slow)])
def test_cross_method_agreement(impact_speed, settled_impact_state, method):
    """IDAS and scipy's Radau agree with CVODES at rtol 1e-8 on the peaks within 1 % (impacting case).
    Radau (35 s) runs with the slow tests."""
    m, x0 = settled_impact_state
    runs = {meth: simulate(m, impact_speed, x0=x0, integrator=Integrator(method=meth, rtol=1e-8), n_out=16001)
            for meth in ("cvodes", method)}
    for n in ("torque", "slider_normal_force", "crank_pin_force", "wrist_pin_force"):
        assert runs[method].peak(n) == pytest.approx(runs["cvodes"].peak(n), rel=0.01), (method, n)


def test_impacts_of_the_kinematic_design_at_75_spm(impact_speed):
    """Constant speed: no force reversal, no impact. Rigid-designed speed at 75 spm: impact spikes."""
    p = PressParams()
    m = build_model(p)
    const = FourierSpeed.constant(0.8)
    rc = simulate(m, const, periodic=True, integrator=Integrator(method="cvodes", rtol=1e-8))
    rigid_c = rigid_response(p, const, rc.t)
    assert rigid_c.wrist_pin_force.min() > 500 and rc.wrist_pin_force.min() > 500  # never reverses
    assert rc.peak("torque") == pytest.approx(rigid_c.peak("torque"), rel=0.02)
    rd = simulate(m, impact_speed, periodic=True, integrator=Integrator(method="cvodes", rtol=1e-8))
    rigid_d = rigid_response(p, impact_speed, rd.t)
    assert rigid_d.wrist_pin_force.min() < 0.01 * rigid_d.peak("wrist_pin_force")  # the force reverses
    assert rd.wrist_pin_eccentricity.min() < 0.99  # the journal leaves the bearing surface (free flight)
    assert rd.peak("torque") > 2.0 * rigid_d.peak("torque")
    assert rd.peak("slider_normal_force") > 3.0 * rigid_d.peak("slider_normal_force")


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(clearance=("big_end",)), "clearance joint"),
        (dict(clearance=("crank_pin", "crank_pin")), "twice"),
        (dict(n_elements=0), "n_elements"),
        (dict(n_elements=65), "n_elements"),
        (dict(rod="elastic"), "rod"),
    ],
)
def test_build_model_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        build_model(PressParams(), **kwargs)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(t_end=0.0), "t_end"),
        (dict(t_end=-1.0), "t_end"),
        (dict(cycles=0), "cycles"),
    ],
)
def test_simulate_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        simulate(build_model(PressParams()), FourierSpeed.constant(1.0), **kwargs)


@pytest.mark.parametrize("kwargs, match", [
    (dict(method="euler"), r"method must be one of 'idas', 'cvodes'.*got 'euler'"),
    (dict(rtol=0.0), r"rtol must be in \(0, 0.01\), got 0.0"),
    (dict(rtol=5.0), r"rtol must be in \(0, 0.01\), got 5.0"),
    (dict(rtol=-1e-6), "rtol"),
    (dict(atol=-1.0), "atol"),
    (dict(max_steps=0), "max_steps"),
    (dict(step=0.0), r"step must be in \(0, inf\) s"),
])
def test_integrator_bad_input_fails_when_it_is_made(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Integrator(**kwargs)


def test_simulate_takes_integrator_settings_only_as_an_integrator():
    with pytest.raises(ValueError, match=r"integrator must be an Integrator, e.g. Integrator\('cvodes'"):
        simulate(build_model(PressParams()), FourierSpeed.constant(1.0), integrator="cvodes")


@pytest.mark.parametrize("method", ["idas", "cvodes", "cvodes-direct", "scipy-bdf"])
def test_forced_integrator_failure_is_typed_and_readable(method):
    m = build_model(PressParams())
    with pytest.raises(SimulationError) as info:  # cvodes-direct integrates no work quadratures
        simulate(m, FourierSpeed.constant(1.0), integrator=Integrator(method=method, max_steps=20),
                 work=method != "cvodes-direct")
    msg = str(info.value)
    assert method in msg and "hint" in msg
    assert info.value.method == method
    if method.startswith("cvodes"):
        assert "CV_TOO_MUCH_WORK" in msg and 0.0 < info.value.time < 1.0


@pytest.mark.parametrize("method, step", [("rk", 1e-5),
                                          pytest.param("collocation", 2e-5, marks=pytest.mark.slow)])  # 5-11 s
def test_fixed_step_methods_agree_with_cvodes(method, step):
    m = build_model(PressParams())
    s = FourierSpeed.constant(1.0)
    x0 = simulate(m, s, t_end=2.0, integrator=Integrator(method="cvodes", rtol=1e-9), n_out=3).states[:, -1] / m.x_scale
    ref = simulate(m, s, t_end=0.02, x0=x0, integrator=Integrator(method="cvodes", rtol=1e-10), n_out=21)
    r = simulate(m, s, t_end=0.02, x0=x0, integrator=Integrator(method=method, step=step), n_out=21)
    assert np.max(np.abs(r.torque - ref.torque)) < 1e-4 * ref.peak("torque")
    assert np.max(np.abs(r.wrist_pin_force - ref.wrist_pin_force)) < 1e-4 * ref.peak("wrist_pin_force")


def test_fixed_step_methods_take_the_step_asked_for():
    """RK4 is stable on the clearance model up to about 0.1 ms (benchmarks/results/stability.json). With
    outputs every 0.2 ms and a 50 us step it must take four steps per output and stay on the CVODES
    response; stepping at the output interval instead diverges."""
    m = build_model(PressParams())
    s = FourierSpeed.constant(1.0)
    x0 = simulate(m, s, t_end=2.0, integrator=Integrator(method="cvodes", rtol=1e-9), n_out=3).states[:, -1] / m.x_scale
    ref = simulate(m, s, t_end=0.1, x0=x0, integrator=Integrator(method="cvodes", rtol=1e-10), n_out=501)
    r = simulate(m, s, t_end=0.1, x0=x0, integrator=Integrator(method="rk", step=5e-5), n_out=501)
    assert np.max(np.abs(r.wrist_pin_force - ref.wrist_pin_force)) < 1e-4 * ref.peak("wrist_pin_force")


def test_periodic_orbit_is_a_periodic_solution():
    """The periodic response found and sampled in the same integrations (no work quadratures) is the
    periodic response of the classic path: settle, then integrate one more cycle with the work
    quadratures. Reference: the classic path at rtol 1e-10 (states 1e-3 of the clearance, peak 1e-5)."""
    m = build_model(PressParams())
    s = FourierSpeed.constant(0.8)
    ref = simulate(m, s, periodic=True, integrator=Integrator(method="cvodes", rtol=1e-10), n_out=2001, work=True)
    assert "motor_work" in ref.energy
    fast = simulate(m, s, periodic=True, integrator=Integrator(method="cvodes", rtol=1e-9), n_out=2001, work=False)
    assert "motor_work" not in fast.energy and fast.stats["steps"] > 0
    assert fast.stats["periodic"]["cycles"] >= 1
    scale = m.x_scale[:, None]
    assert np.max(np.abs((fast.states - ref.states) / scale)) < 1e-3  # scaled: eccentricity / clearance
    assert np.max(np.abs((fast.states[:, -1] - fast.states[:, 0]) / m.x_scale)) <= 1e-4  # periodic to its tol
    assert fast.peak("torque") == pytest.approx(ref.peak("torque"), rel=1e-5)


def test_a_periodic_run_is_as_periodic_as_asked():
    """On a worn (2 mm) wrist pin the contact transient dies slowly: a cycle periodic to the default
    1e-4 has its peak torque 1e-4 of itself (1e-2 N m) off, 100 x the integration's error at rtol
    1e-10. Asked for 1e-7, both paths (with and without work) return a cycle whose end state is within
    1e-7 of its start (scaled), and whose peak agrees to 1e-6 with a cycle settled further from it."""
    m = build_model(PressParams().with_value("wrist_pin.clearance", 2e-3))
    s = FourierSpeed.constant(0.8)
    integ = Integrator(method="cvodes", rtol=1e-10, periodic_tol=1e-7)
    runs = [simulate(m, s, periodic=True, integrator=integ, n_out=4001, work=w) for w in (False, True)]
    for r in runs:
        assert np.max(np.abs((r.states[:, -1] - r.states[:, 0]) / m.x_scale)) <= 1e-7
    # five more cycles from the returned state, then the sixth: settled by the test, not by the search
    x = simulate(m, s, cycles=5, x0=runs[0].states[:, -1] / m.x_scale, integrator=integ, n_out=6,
                 work=False).states[:, -1] / m.x_scale
    settled = simulate(m, s, x0=x, integrator=integ, n_out=4001, work=False)
    for r in runs:
        assert r.peak("torque") == pytest.approx(settled.peak("torque"), rel=1e-6)
    with pytest.raises(ValueError, match="periodic_tol"):
        Integrator(periodic_tol=0.0)


def test_a_kept_integrator_gives_the_same_bits():
    """The second simulation with the same settings reuses the first's integrator and returns the
    same numbers to the bit; other settings build another."""
    m = build_model(PressParams())
    s = FourierSpeed.constant(0.8)
    run = dict(t_end=0.1, n_out=51)  # the journals fall onto their bearings: contact, in a tenth of the time
    a = simulate(m, s, integrator=Integrator(method="cvodes", rtol=1e-7), **run)
    kept = dict(m.functions["integrators"])
    b = simulate(m, s, integrator=Integrator(method="cvodes", rtol=1e-7), **run)
    assert len(kept) == 1 and all(m.functions["integrators"][k] is f for k, f in kept.items())
    assert np.array_equal(a.states, b.states) and np.array_equal(a.torque, b.torque)
    assert a.stats["steps"] > 100
    simulate(m, s, integrator=Integrator(method="cvodes", rtol=1e-8), **run)
    assert len(m.functions["integrators"]) == 2


@pytest.mark.parametrize("method", ["idas", "cvodes", pytest.param("scipy-radau", marks=pytest.mark.slow)])  # 5-13 s
def test_a_compiled_model_integrates_the_same_motion(method):
    """``model.jit``: the integrator calls compiled code (kept in ``model.functions``), and the motion
    is the interpreted model's to the integration tolerance (a smooth scene: the periodic state at
    constant speed, journals on their walls; from rest they would fall onto them)."""
    s = FourierSpeed.constant(0.8)
    plain, compiled = build_model(PressParams()), build_model(PressParams())
    compiled.jit = True
    x0 = periodic_state(plain, s, integrator=Integrator(method="cvodes", rtol=1e-9))[0]
    rtol = 1e-6 if method.startswith("scipy") else 1e-9
    a = simulate(plain, s, integrator=Integrator(method=method, rtol=rtol), t_end=0.2, n_out=201, work=False, x0=x0)
    b = simulate(compiled, s, integrator=Integrator(method=method, rtol=rtol), t_end=0.2, n_out=201, work=False, x0=x0)
    if not method.startswith("scipy"):
        assert any(k[0] == "integrator_dae" for k in compiled.functions)
        assert not any(k[0] == "integrator_dae" for k in plain.functions)
    np.testing.assert_allclose(b.torque, a.torque, rtol=1e-5, atol=1e-6 * np.abs(a.torque).max())
    np.testing.assert_allclose(b.wrist_pin_force, a.wrist_pin_force, rtol=1e-5, atol=1e-6 * np.abs(a.wrist_pin_force).max())


def test_by_default_a_flexible_rod_runs_compiled_and_the_rigid_rod_interpreted():
    from pressocp.compile_cache import compiler_available

    flexible, rigid = build_model(PressParams(), rod="flexible", n_elements=1), build_model(PressParams())
    assert flexible.jit == rigid.jit == "auto"
    assert runs_compiled(flexible) == compiler_available()
    assert not runs_compiled(rigid)
    rigid.jit = True
    assert runs_compiled(rigid) == compiler_available()


def test_a_model_for_repeated_use_runs_compiled_unless_its_jit_was_chosen():
    """`for_repeated_use` (the optimiser's checks and verification): a rigid rod left at "auto" is
    compiled, sharing its built functions; a choice made (False or True), a flexible rod and the
    rigid press come back as they are."""
    from pressocp.compile_cache import compiler_available

    rigid = build_model(PressParams())
    again = for_repeated_use(rigid)
    assert runs_compiled(again) == compiler_available() and again.functions is rigid.functions
    assert rigid.jit == "auto" and not runs_compiled(rigid)
    rigid.jit = False
    assert for_repeated_use(rigid) is rigid
    for m in (build_model(PressParams(), rod="flexible", n_elements=1), build_model(PressParams(), clearance=())):
        assert for_repeated_use(m) is m


def test_a_jit_setting_that_is_not_true_false_or_auto_fails_before_integrating():
    m = build_model(PressParams())
    m.jit = "yes"
    with pytest.raises(ValueError, match="jit must be True, False or 'auto', got 'yes'"):
        simulate(m, FourierSpeed.constant(0.8), integrator=Integrator(method="idas", rtol=1e-6), t_end=0.01, n_out=3, work=False)


def test_without_a_c_compiler_a_compiled_model_says_so_and_runs_interpreted(monkeypatch):
    import pressocp.compile_cache as cc

    monkeypatch.setattr(cc, "compiler_available", lambda: False)
    m = build_model(PressParams())
    m.jit = True
    with pytest.warns(RuntimeWarning, match="no C compiler"):
        b = simulate(m, FourierSpeed.constant(0.8), integrator=Integrator(method="idas", rtol=1e-7), t_end=0.05, n_out=51, work=False)
    a = simulate(build_model(PressParams()), FourierSpeed.constant(0.8), integrator=Integrator(method="idas", rtol=1e-7), t_end=0.05,
                 n_out=51, work=False)
    assert np.array_equal(a.torque, b.torque)
    assert not any(k[0] == "integrator_dae" for k in m.functions)


class KinkedShots:
    """Stand-in for the periodic search's shots (`PeriodicShots`): the one-period map x -> x + a + |x|,
    whose residual a + |x| is lowest at x = 0 and has a kink there, so no step along Newton's direction
    (from a finite-difference Jacobian across the kink) lowers it."""

    def __init__(self, a):
        self.a, self.model, self.shots = np.asarray(a, float), type("M", (), {"nx": len(a)})(), 0

    def end_only(self):
        return type("F", (), {"map": lambda self, *args: self})()

    def shoot(self, xs, F=None):
        self.shots += 1
        xs = np.asarray(xs, float)
        return xs + (self.a[:, None] if xs.ndim > 1 else self.a) + np.abs(xs)


def test_newton_stops_where_its_line_search_finds_no_lower_residual():
    """Newton's search ends at the step whose line search finds nothing lower (here the first: 1 shot
    batch for the Jacobian and 10 halvings), returning the best state and its residual, instead of
    going on from a worse point to its step limit."""
    sh = KinkedShots([1e-3, 5e-4])
    x, res, steps = newton_periodic(sh, np.zeros(2), 1e-3, 1e-9, 8)
    assert steps == 1 and res == 1e-3 and np.array_equal(x, np.zeros(2)) and sh.shots == 1 + 10


@pytest.mark.slow  # 21 s
def test_newton_finishes_a_search_whose_settling_does_not_contract():
    """The 75 spm kinematic design impacts. At rtol 1e-10 the residual of its settling cycles rises
    over the last ones (1.7e-6 to 6.3e-6, above the tol of 1e-7), and Newton's method reaches the tol.
    A rule that stopped such a search before Newton's method (tried on 2026-11-29,
    docs/decisions/2026-11-29-periodic-search-without-contraction.md) made the tornado study fail here."""
    from pressocp import Scenario, design_speed

    scenario = Scenario.load("press75")
    model = for_repeated_use(scenario.build_model())
    x, info = periodic_state(model, design_speed(scenario.problem).speed, Integrator("cvodes", 1e-10), tol=1e-7)
    assert info["cycles"] == 12 and info["newton"] >= 1 and info["residual"] <= 1e-7


def test_settling_cycles_expected_to_settle():
    """Which settling cycles are integrated on the output grid: worked by hand from the rule (the first
    unless from rest, the second, later ones when residual x contraction <= tol)."""
    assert expect_settled([], 1e-6, from_rest=False) and not expect_settled([], 1e-6, from_rest=True)
    assert expect_settled([0.3], 1e-6, from_rest=True)  # the second cycle
    assert not expect_settled([0.3, 1e-3], 1e-6, from_rest=True)  # next ~ 1e-3 * (1e-3 / 0.3) = 3.3e-6
    assert expect_settled([0.3, 1e-4], 1e-6, from_rest=True)  # next ~ 3.3e-8


def test_the_orbit_does_not_depend_on_which_cycles_are_sampled():
    """From rest with the transient integrated without the output grid, and from a start already on
    the orbit (its first, coarse, cycle settles and is integrated again on the grid): the same
    sampled orbit as the search that samples every cycle, within its tolerance. (At rtol 1e-9 the
    cycle-to-cycle residual of this orbit stalls at 0.5-2e-6, the integration's noise: 1e-5 is a
    tolerance the search reaches in 3 cycles either way.)"""
    m = build_model(PressParams())
    s = FourierSpeed.constant(0.8)
    times = np.linspace(0.0, 0.8, 401)
    every, info = periodic_orbit(m, s, times, Integrator("cvodes", 1e-9), tol=1e-5)
    rest, info_rest = periodic_orbit(m, s, times, Integrator("cvodes", 1e-9), tol=1e-5, from_rest=True)
    assert info_rest["cycles"] == info["cycles"] >= 2
    assert np.max(np.abs(rest - every)) < 1e-5
    on, info_on = periodic_orbit(m, s, times, Integrator("cvodes", 1e-9), x_start=every[:, 0], tol=1e-5, from_rest=True)
    assert info_on["cycles"] == 1 and np.max(np.abs(on - every)) < 1e-5
