"""The study figures of notebook 06 and benchmarks/bench_studies.py, on reduced cases (seconds): a tornado
chart of normalised sensitivities. (Optima against a varied value with the floor and the wear study are
in test_sweep.py; the full studies run in the benchmarks and the slow notebook.)"""

import pytest

import pressocp as po
from pressocp.plots import plot_tornado


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
