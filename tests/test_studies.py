"""The study figures of notebook 06 and benchmarks/bench_studies.py, on reduced cases (seconds): optima
against a varied value with the rigid-press floor, and a tornado chart of normalised sensitivities.
(The wear study is in test_sweep.py; the full studies run in the benchmarks and the slow notebook.)"""

import numpy as np
import pytest

import pressocp as po
from pressocp.plots import plot_sweep, plot_tornado


def test_optima_against_the_stroke_rate_with_the_floor(tmp_path, serial):
    # the ideal press with 6 harmonics: each optimum is its own floor, and faster strokes cost torque
    base = po.Scenario.load("press75").with_overrides({"model.clearance": [], "problem.n_harmonics": 6})
    table = po.sweep(base, {"problem.stroke_rate_spm": [60, 75]}, task="optimize", executor=serial,
                     progress=False)
    assert table["ok"].all()
    np.testing.assert_allclose(table["peak_torque_N_m"], table["rigid_peak_torque_N_m"], rtol=1e-3)
    assert table["peak_torque_N_m"].iloc[1] > table["peak_torque_N_m"].iloc[0]
    assert (table["peak_torque_N_m"] < table["initial_peak_torque_N_m"]).all()
    fig = plot_sweep(table, ["problem.stroke_rate_spm"], "reduced study")
    labels = [line.get_label() for line in fig.axes[0].get_lines()]
    assert "rigid-press floor" in labels and "initial speed" in labels
    fig.savefig(tmp_path / "study.png")
    assert (tmp_path / "study.png").stat().st_size > 10_000


def test_tornado_of_normalised_sensitivities(tmp_path):
    # the clearance model at constant speed (no impact): the slider's inertia makes the torque, so its
    # normalised sensitivity is the largest of the two and positive
    press = po.PressParams()
    model = po.build_model(press, clearance=("wrist_pin",))
    s = po.sensitivities(model, po.FourierSpeed.constant(0.8), ("slider_mass", "rod_mass"), rtol=1e-8)
    t = s.table.set_index("parameter")
    assert t.loc["slider_mass", "normalised"] > abs(t.loc["rod_mass", "normalised"]) > 0
    fig = plot_tornado(s, title="reduced tornado")
    assert [label.get_text() for label in fig.axes[0].get_yticklabels()] == ["rod_mass", "slider_mass"]
    fig.savefig(tmp_path / "tornado.png")
    assert (tmp_path / "tornado.png").stat().st_size > 5_000
    assert s.derivative("peak_torque", "slider_mass") == pytest.approx(t.loc["slider_mass", "derivative"])
