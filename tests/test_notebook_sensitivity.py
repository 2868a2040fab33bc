"""Notebook 06 (sensitivity studies) in a reduced version: its papermill parameters set to fewer
clearances and parameters and a looser tolerance, executed in a Jupyter kernel as a user runs it (no
forced matplotlib backend). The full notebook runs with ``pytest -m slow`` (nbmake)."""

from pathlib import Path

import papermill
import pytest

NOTEBOOK = Path(__file__).resolve().parents[1] / "notebooks" / "06_sensitivity.ipynb"
REDUCED = {"wear_clearances": [1e-4, 4e-4], "press_parameters": ["slider_mass", "crank_pin.stiffness"],
           "rtol": 1e-8, "optimum_parameters": ["slider_mass"]}


@pytest.mark.slow  # 82 s (papermill: optima and sensitivities in a kernel)
def test_reduced_sensitivity_notebook_runs_and_shows_its_figures(tmp_path, monkeypatch):
    monkeypatch.delenv("MPLBACKEND", raising=False)  # the kernel's default (inline) backend
    nb = papermill.execute_notebook(str(NOTEBOOK), str(tmp_path / "06_reduced.ipynb"), parameters=REDUCED,
                                    cwd=str(NOTEBOOK.parent), kernel_name="python3", progress_bar=False)
    outputs = [out for cell in nb.cells if cell.cell_type == "code" for out in cell.get("outputs", [])]
    assert not [out for out in outputs if out.get("output_type") == "error"]
    figures = sum("image/png" in out.get("data", {}) for out in outputs)
    # wear, tornado, and the four optima studies and the wear study drawn from benchmarks/results
    assert figures >= 2 + sum((NOTEBOOK.parents[1] / "benchmarks" / "results" / f"study_{c}.csv").exists()
                              for c in ("stroke_rate", "clearance", "ram_speed", "slider_mass", "wear"))
    text = "".join(out.get("text", "") for out in outputs)
    assert "optimal peak torque" in text and "crank_pin.stiffness" in text
