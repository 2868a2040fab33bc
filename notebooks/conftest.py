"""The notebooks run as tests (nbmake) in a real Jupyter kernel, as a user opens them: without a
forced matplotlib backend, and each executed notebook must contain its figures (PNG outputs)."""

import os

from nbmake.nb_run import NotebookRun

_execute = NotebookRun.execute


def png_outputs(nb) -> int:
    """Number of PNG outputs in an executed notebook."""
    return sum("image/png" in out.get("data", {}) for cell in nb.cells if cell.cell_type == "code"
               for out in cell.get("outputs", []))


def execute_and_check_figures(self):
    """nbmake's run in a kernel started without MPLBACKEND (the user's default, inline in Jupyter),
    then fail when the executed notebook shows no figure."""
    saved = os.environ.pop("MPLBACKEND", None)
    try:
        result = _execute(self)
    finally:
        if saved is not None:
            os.environ["MPLBACKEND"] = saved
    if result.error is None and png_outputs(result.nb) == 0:
        raise AssertionError(f"{self.filename}: the executed notebook contains no figure (no image/png output)")
    return result


NotebookRun.execute = execute_and_check_figures

#: Notebooks that solve optima, sensitivities or impact studies (45 s to minutes): run with ``pytest -m slow``
#: (and by the benchmark job `slow_tests`).
SLOW_NOTEBOOKS = {"02_clearance_impacts.ipynb",  # 146 s (impact studies; by default: tests/test_status.py)
                  "04_speed_optimisation.ipynb", "05_your_press.ipynb", "06_sensitivity.ipynb",
                  "07_drive_sizing.ipynb"}


def pytest_collection_modifyitems(config, items):
    import pytest

    for item in items:
        if getattr(item, "nbmake", False) and item.name in SLOW_NOTEBOOKS:
            item.add_marker(pytest.mark.slow)
