"""Notebooks show progress bars without a TqdmWarning (issue 32, section 8): the package draws its
bars with `tqdm.auto` (a widget in Jupyter, text in a terminal), and the notebook extra installs
ipywidgets, which the widget needs (without it tqdm warns "IProgress not found")."""

import ast
import tomllib
from pathlib import Path

import nbformat
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parents[1]


def tqdm_imports() -> dict[str, list[str]]:
    """Every import of tqdm in the package's modules: file -> the modules imported from."""
    found: dict[str, list[str]] = {}
    for path in sorted((ROOT / "pressocp").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([node.module] if isinstance(node, ast.ImportFrom) and node.module else
                     [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            hits = [n for n in names if n.split(".")[0] == "tqdm"]
            if hits:
                found.setdefault(str(path.relative_to(ROOT)), []).extend(hits)
    return found


def test_the_package_draws_progress_with_tqdm_auto_only():
    found = tqdm_imports()
    assert "pressocp/sweeps.py" in found  # the sweeps' bar, at least
    assert {module for modules in found.values() for module in modules} == {"tqdm.auto"}, found


def test_the_notebook_extra_installs_ipywidgets():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["optional-dependencies"]
    for extra in ("notebook", "test"):  # the tests run the notebooks too
        assert any(req.startswith("ipywidgets") for req in extras[extra]), extra


def test_a_progress_bar_in_a_notebook_is_a_widget_without_a_warning():
    """The sweeps' bar in a Jupyter kernel, with tqdm's warnings turned into errors: the notebook's widget
    bar, no TqdmWarning in any output."""
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(
        "import warnings\n"
        "from tqdm import TqdmWarning\n"
        "warnings.simplefilter('error', TqdmWarning)\n"
        "from pressocp.sweeps import tqdm\n"
        "bar = tqdm(total=3, desc='points')\n"
        "bar.update(3)\n"
        "bar.close()\n"
        "from tqdm.notebook import tqdm_notebook\n"
        "print('widget bar:', isinstance(bar, tqdm_notebook))")])
    NotebookClient(nb, timeout=120, kernel_name="python3").execute()
    outputs = nb.cells[0].outputs
    text = "".join(o.get("text", "") for o in outputs)
    assert "widget bar: True" in text
    assert not any(o.output_type == "error" for o in outputs)
    assert "TqdmWarning" not in text and "IProgress" not in text
    assert any("application/vnd.jupyter.widget-view+json" in o.get("data", {}) for o in outputs)
