"""Display units (issue 32, section 8): forces of 10 kN or more in kN, one helper; sweep figures in
the sweep's own units (mm for clearances and lengths), the table staying in SI."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from pressocp.plots import key_label, plot_sweep  # noqa: E402
from pressocp.units import force_unit, format_force, key_unit  # noqa: E402


@pytest.mark.parametrize("values, unit", [
    ((9_999.9,), "N"), ((10_000.0,), "kN"), ((-25_000.0,), "kN"), ((np.array([1.0, 3e4]),), "kN"),
    ((np.array([1.0, np.nan]), 500.0), "N"), ((), "N"), ((np.array([2e3]), np.array([-1.2e4])), "kN"),
])
def test_forces_switch_to_kN_at_10_kN_by_the_largest_magnitude(values, unit):
    assert force_unit(*values) == (unit, {"N": 1.0, "kN": 1e-3}[unit])


def test_a_force_is_formatted_with_its_unit():
    assert format_force(584.23) == "584.2 N"
    assert format_force(22934.5) == "22.93 kN"
    assert format_force(-60000.0) == "-60.00 kN"


@pytest.mark.parametrize("key, values, unit, factor", [
    ("crank_pin.clearance", (), "mm", 1e3), ("press.rod_length", (), "mm", 1e3), ("crank_radius", (), "mm", 1e3),
    ("press.process_force.h_top", (), "mm", 1e3), ("process_force.speed_edge", (), "m/s", 1.0),
    ("slider_mass", (), "kg", 1.0), ("problem.ram_speed_tol", (), "m/s", 1.0),
    ("press.process_force.force", (2e4, 6e4), "kN", 1e-3), ("problem.max_pin_force", (3e3, 8e3), "N", 1.0),
    ("drive.power_limit", (), "kW", 1e-3), ("press.wrist_pin.exponent", (), None, 1.0),
])
def test_a_key_has_its_display_unit(key, values, unit, factor):
    assert key_unit(key, values) == (unit, factor)


@pytest.mark.parametrize("key, label", [
    ("problem.ram_speed", "problem.ram_speed [m/s]"),
    ("wrist_pin.clearance", "wrist_pin.clearance [mm]"),
    ("slider_mass", "slider_mass [kg]"),
    ("crank_pin.stiffness", "crank_pin.stiffness [N/m^exponent]"),
    ("problem.window", "problem.window"),
])
def test_a_varied_key_is_labelled_with_its_display_unit(key, label):
    assert key_label(key) == label


def sweep_table() -> pd.DataFrame:
    """A simulate sweep's rows over a clearance (m) and a process force (N), in SI as sweeps write them."""
    rows = []
    for force in (2e4, 6e4):
        for c in (5e-5, 1e-4, 2e-4):
            rows.append({"crank_pin.clearance": c, "press.process_force.force": force, "ok": True,
                         "peak_torque_N_m": 100.0 + 1e5 * c, "peak_slider_normal_force_N": 500.0,
                         "peak_crank_pin_force_N": 1.2e4 + force, "peak_wrist_pin_force_N": 9e3})
    return pd.DataFrame(rows)


def test_a_sweep_figure_draws_clearances_in_mm_and_large_forces_in_kN():
    table = sweep_table()
    fig = plot_sweep(table, ["crank_pin.clearance", "press.process_force.force"])
    torque, normal, pin = fig.axes
    assert pin.get_xlabel() == "crank_pin.clearance [mm]"
    lines = torque.get_lines()
    np.testing.assert_allclose(lines[0].get_xdata(), [0.05, 0.1, 0.2])
    np.testing.assert_allclose(lines[0].get_ydata(), [105.0, 110.0, 120.0])  # torque stays in N·m
    assert [line.get_label() for line in lines] == ["press.process_force.force = 20 kN",
                                                    "press.process_force.force = 60 kN"]
    assert normal.get_ylabel() == "peak slider normal force [N]"
    np.testing.assert_allclose(normal.get_lines()[0].get_ydata(), 500.0)
    assert pin.get_ylabel() == "peak pin force [kN]"
    np.testing.assert_allclose([line.get_ydata()[0] for line in pin.get_lines()], [32.0, 72.0])
    assert table["crank_pin.clearance"].tolist() == [5e-5, 1e-4, 2e-4] * 2  # the table is left in SI
    plt.close(fig)


def test_a_sweep_over_a_force_draws_it_in_kN_from_10_kN():
    table = sweep_table()
    fig = plot_sweep(table, ["press.process_force.force", "crank_pin.clearance"])
    assert fig.axes[-1].get_xlabel() == "press.process_force.force [kN]"
    np.testing.assert_allclose(fig.axes[0].get_lines()[0].get_xdata(), [20.0, 60.0])
    assert fig.axes[0].get_lines()[0].get_label() == "crank_pin.clearance = 0.05 mm"
    plt.close(fig)


def test_the_report_line_gives_the_process_force_and_the_counterbalance_in_kN():
    import pressocp as po
    from pressocp.report import describe_problem

    press = po.PressParams(process_force=po.ProcessForce(heights=(0.005, 0.02, 0.03), forces=(0.0, 6e4, 0.0)),
                           counterbalance=po.Counterbalance(force=1.5e3))
    line = describe_problem(po.SpeedProblem(press, period=0.8, ram_speed=-0.1))
    assert line.endswith(", process force up to 60.00 kN, counterbalance 1,500.0 N at bottom dead centre")
    assert "process force" not in describe_problem(po.SpeedProblem(po.PressParams(), period=0.8, ram_speed=-0.1))
