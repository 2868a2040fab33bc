"""Figures carry their reference levels: the rigid-press floor on the torque, the pin-force cap."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import pressocp as po  # noqa: E402
from pressocp.plots import plot_responses, plot_speed_design  # noqa: E402


def horizontal_levels(ax) -> list[float]:
    """The y values of the horizontal lines (axhline) of an axis."""
    return sorted(float(line.get_ydata()[0]) for line in ax.get_lines()
                  if len(set(np.asarray(line.get_ydata(), float))) == 1 and list(line.get_xdata()) == [0, 1])


@pytest.fixture(scope="module")
def capped_optimum():
    """The ideal press at 60 spm, 6 harmonics, pin forces capped at 3200 N (a rigid stage, seconds)."""
    sc = po.Scenario.load("press75").with_overrides({"model.clearance": [], "problem.stroke_rate_spm": 60,
                                                      "problem.n_harmonics": 6, "problem.max_pin_force": 3200.0})
    return sc.optimize(False)


def test_levels_are_mirrored_on_signed_series_only(capped_optimum):
    sim = capped_optimum.simulation
    fig = plot_responses([("optimum", sim)], series=("torque", "crank_pin_force"),
                         levels={"torque": [(90.0, "floor")], "crank_pin_force": [(3200.0, "cap")]})
    torque_ax, pin_ax = fig.axes
    assert horizontal_levels(torque_ax) == [-90.0, 90.0]  # the torque changes sign over the cycle
    assert horizontal_levels(pin_ax) == [3200.0]  # a pin force is a magnitude
    assert [t.get_text() for t in pin_ax.get_legend().get_texts()] == ["cap"]
    plt.close(fig)


def test_speed_design_draws_the_floor_and_the_pin_cap(capped_optimum):
    r = capped_optimum
    assert r.success
    fig = plot_speed_design(r, levels={"torque": [(1.1 * r.rigid_peak_torque, "goal")]})
    by_label = {ax.get_ylabel(): ax for ax in fig.axes}
    assert horizontal_levels(by_label["motor torque, N·m"]) == pytest.approx(
        sorted([-1.1 * r.rigid_peak_torque, -r.rigid_peak_torque, r.rigid_peak_torque, 1.1 * r.rigid_peak_torque]))
    pin_ax = by_label["larger pin force, N"]
    assert horizontal_levels(pin_ax) == [3200.0]
    # the optimum meets its cap: the drawn peak is at or under the line, within the solver's tolerance
    peak = max(line.get_ydata().max() for line in pin_ax.get_lines()[1:2])
    assert 3000.0 < peak <= 3200.0 * (1 + 1e-3)
    plt.close(fig)


def test_an_overridden_scenario_names_its_changes():
    sc = po.Scenario.load("press75").with_overrides({"problem.stroke_rate_spm": 60})
    assert sc.name.endswith("problem.stroke_rate_spm = 60")
    named = po.Scenario.load("press75").with_overrides({"name": "mine", "problem.stroke_rate_spm": 60})
    assert named.name == "mine"


def test_the_rigid_optimum_is_a_floor_only_for_the_peak_torque():
    from pressocp.plots import rigid_torque_level

    assert rigid_torque_level("peak_torque", 108.5) == (108.5, "rigid-press floor ±108.5 N·m")
    assert rigid_torque_level("rms_torque", 106.0)[1].startswith("rigid-press optimum's peak")


def test_a_sweep_figure_draws_the_columns_its_rows_have():
    """An impacts sweep's rows hold ratios, not peaks: its figure draws them, one panel per load; a
    table with no point ok is refused (the command line then does not claim a figure)."""
    import pandas as pd

    from pressocp.plots import plot_sweep

    rows = [{"slider_mass": m, "ok": True, **{f"{s}_{load}_ratio": 1.0 + m / 100 + (s == "constant")
                                              for s in ("constant", "designed")
                                              for load in ("torque", "slider_normal_force", "crank_pin_force",
                                                           "wrist_pin_force")}} for m in (100.0, 150.0, 200.0)]
    fig = plot_sweep(pd.DataFrame(rows), ["slider_mass"])
    assert len(fig.axes) == 4
    for ax in fig.axes:
        lines = [ln for ln in ax.get_lines() if len(ln.get_xdata())]
        assert len(lines) == 2 and all(list(ln.get_xdata()) == [100.0, 150.0, 200.0] for ln in lines)
    plt.close(fig)
    optimum = pd.DataFrame([{"slider_mass": 100.0, "ok": True, "peak_torque_N_m": 1.0, "rigid_peak_torque_N_m": 0.9,
                             "peak_slider_normal_force_N": 2.0, "peak_crank_pin_force_N": 3.0,
                             "peak_wrist_pin_force_N": 4.0}])
    fig = plot_sweep(optimum, ["slider_mass"])
    assert len(fig.axes) == 3 and max(fig.axes[2].get_lines()[0].get_ydata()) == 4.0
    plt.close(fig)
    with pytest.raises(ValueError, match="nothing to draw: no point is ok"):
        plot_sweep(pd.DataFrame([{**rows[0], "ok": False}]), ["slider_mass"])
