"""What a simulate job writes for the journals and the forces (issue 32, section 8): the x/y
eccentricities in results.csv, the orbits in journals.png, forces of 10 kN or more in kN in
report.txt and on the figures' axes. One simulate job of press75's rigid design (it impacts:
pin forces of about 23 kN, seconds)."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

import pressocp as po  # noqa: E402
from pressocp.jobs import simulate_job  # noqa: E402
from pressocp.plots import plot_journal_orbits, plot_responses  # noqa: E402

JOINTS = ("crank_pin", "wrist_pin")
#: press75's radial clearance at both pins, m (its file: 0.1 mm).
CLEARANCE = 1e-4


@pytest.fixture(scope="module")
def sim75(tmp_path_factory):
    """press75's rigid design simulated on its clearance model: the scenario, the folder, the report."""
    scenario = po.Scenario.load("press75")
    out = tmp_path_factory.mktemp("sim75")
    return scenario, out, simulate_job(scenario, out)


def test_results_csv_carries_the_x_y_eccentricities(sim75):
    """|e| from the x/y columns over the clearance is the model's own |e|/c output (its contact
    law's sqrt(|e|^2 + s^2) / c with the smoothing width s), sample by sample."""
    scenario, out, _ = sim75
    table = pd.read_csv(out / "results.csv")
    for joint in JOINTS:
        bearing = getattr(scenario.press, joint)
        assert bearing.clearance == CLEARANCE
        ex, ey = table[f"speed {joint}_ex [m]"].to_numpy(), table[f"speed {joint}_ey [m]"].to_numpy()
        ratio = table[f"speed {joint}_eccentricity [-]"].to_numpy()
        assert np.sqrt(ex**2 + ey**2 + bearing.smoothing_width**2) / CLEARANCE == pytest.approx(ratio, rel=1e-6)
        # the journal moves around its bearing: both coordinates change sign over the cycle
        assert ex.min() < -0.5 * CLEARANCE < 0.5 * CLEARANCE < ex.max()
        assert ey.min() < -0.5 * CLEARANCE < 0.5 * CLEARANCE < ey.max()
    assert not any(c.endswith("_dot [m]") for c in table.columns)  # positions only, not the rates


def test_journals_png_is_written_and_listed(sim75):
    _, out, report = sim75
    assert (out / "journals.png").stat().st_size > 20_000
    assert "journals.png" in report.summary["files"]


def response(t, states=None) -> po.SimResult:
    """A response with zero loads and the given states (4 eccentricities and their rates, m)."""
    zero = np.zeros_like(t)
    series = {name: zero for name in po.result.SERIES_UNITS if name != "t"}
    return po.SimResult(t=t, **series, states=np.zeros((0, 0)) if states is None else states)


def test_the_orbit_is_drawn_in_micrometres_inside_the_clearance_circle():
    t = np.linspace(0.0, 1.0, 50)
    names = ["crank_pin_ex", "crank_pin_ey", "wrist_pin_ex", "wrist_pin_ey", "crank_pin_ex_dot", "crank_pin_ey_dot",
             "wrist_pin_ex_dot", "wrist_pin_ey_dot"]
    states = np.zeros((8, t.size))
    states[0], states[1] = 9e-5 * np.cos(2 * np.pi * t), 9e-5 * np.sin(2 * np.pi * t)  # 90 µm circle
    states[2], states[3] = 2e-5, -3e-5
    fig = plot_journal_orbits([("ideal joints", response(t)), ("model", response(t, states))], names,
                              {"crank_pin": 1e-4, "wrist_pin": 2.5e-4})
    crank, wrist = fig.axes[0], fig.axes[1]
    for ax, radius in ((crank, 100.0), (wrist, 250.0)):
        assert ax.get_aspect() == 1.0
        assert "[µm]" in ax.get_xlabel() and "[µm]" in ax.get_ylabel()
        circles = [p for p in ax.patches if isinstance(p, matplotlib.patches.Circle)]
        assert [c.get_radius() for c in circles] == [pytest.approx(radius)]
    # only the response with states has an orbit: its line and its start marker
    orbit = crank.get_lines()[0]
    assert orbit.get_label() == "model" and len(crank.get_lines()) == 2
    np.testing.assert_allclose(orbit.get_xydata(), np.c_[90 * np.cos(2 * np.pi * t), 90 * np.sin(2 * np.pi * t)])
    np.testing.assert_allclose(wrist.get_lines()[0].get_xydata()[0], [20.0, -30.0])
    # the eccentricity ratio over time stays, for both responses
    assert len(fig.axes[2].get_lines()) == 2 and "|e|/c" in fig.axes[2].get_ylabel()
    plt.close(fig)


def test_report_shows_forces_of_10_kN_and_more_in_kN(sim75):
    """press75's impacting design: pin forces near 23 kN (kN row), slider normal force about 4.4 kN
    (N row). The rows read the summary's peaks (N) in kN."""
    _, out, report = sim75
    rows = {line.split(",")[0].strip(): line for line in report.text.splitlines() if line.startswith("peak ")}
    s = report.summary
    for joint in ("crank-pin", "wrist-pin"):
        key = f"peak_{joint.replace('-', '_')}_force_N"
        assert s[key] > 1e4
        cells = rows[f"peak {joint} force"].split()
        assert "force, kN" in rows[f"peak {joint} force"]
        assert float(cells[-1].replace(",", "")) == pytest.approx(s[key] / 1e3, abs=0.006)
    assert s["peak_slider_normal_force_N"] < 1e4
    normal = rows["peak slider normal force"]
    assert "force, N " in normal
    assert float(normal.split()[-1].replace(",", "")) == pytest.approx(s["peak_slider_normal_force_N"], abs=0.06)
    assert (out / "report.txt").read_text(encoding="utf-8").startswith(report.text)


def test_a_force_axis_is_in_kN_from_10_kN():
    t = np.linspace(0.0, 1.0, 11)
    big, small = response(t), response(t)
    big.crank_pin_force = np.full_like(t, 23_000.0)
    big.slider_normal_force = np.full_like(t, 9_999.0)
    small.crank_pin_force = np.full_like(t, 4_000.0)
    fig = plot_responses([("a", small), ("b", big)], series=("crank_pin_force", "slider_normal_force"),
                         levels={"crank_pin_force": [(20_000.0, "cap")]})
    pin, normal = fig.axes
    assert pin.get_ylabel() == "crank-pin force [kN]" and normal.get_ylabel() == "slider normal force [N]"
    assert [float(line.get_ydata()[0]) for line in pin.get_lines()[:2]] == [4.0, 23.0]
    assert 20.0 in [float(line.get_ydata()[0]) for line in pin.get_lines()[2:]]  # the cap, in kN too
    assert float(normal.get_lines()[1].get_ydata()[0]) == 9_999.0
    plt.close(fig)
