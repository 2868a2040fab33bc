"""The package's layers import one way: `lint-imports` with the contracts in pyproject.toml passes,
and the same check fails on a contract that the code breaks (so the check is live). No function is
longer than 80 lines and no public one takes more than 10 parameters (issue #31's sizes)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

importlinter_cli = pytest.importorskip("importlinter.cli")

ROOT = Path(__file__).resolve().parents[1]


def lint(config: Path) -> int:
    return importlinter_cli.lint_imports(config_filename=str(config), no_cache=True)


def test_the_layer_contracts_hold(monkeypatch):
    monkeypatch.chdir(ROOT)
    assert lint(ROOT / "pyproject.toml") == 0


def test_a_contract_the_code_breaks_fails(tmp_path, monkeypatch):
    # the command line uses the jobs: with the jobs put above it, the check must fail
    config = tmp_path / "broken.ini"
    config.write_text("[importlinter]\nroot_package = pressocp\n\n"
                      "[importlinter:contract:upside-down]\nname = jobs over cli\ntype = layers\n"
                      "layers =\n    pressocp.jobs\n    pressocp.cli\n")
    monkeypatch.chdir(ROOT)
    assert lint(config) == 1


MAX_LINES, MAX_PARAMETERS = 80, 10


def oversized(source: str) -> list[str]:
    """Functions in `source` longer than `MAX_LINES` (docstring included), and public ones with more
    than `MAX_PARAMETERS` parameters (self and cls not counted)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            a = node.args
            params = [*a.posonlyargs, *a.args, *a.kwonlyargs, a.vararg, a.kwarg]
            count = sum(p is not None and p.arg not in ("self", "cls") for p in params)
            if node.end_lineno - node.lineno + 1 > MAX_LINES:
                found.append(f"{node.name}: {node.end_lineno - node.lineno + 1} lines")
            if count > MAX_PARAMETERS and not node.name.startswith("_"):
                found.append(f"{node.name}: {count} parameters")
    return found


def test_no_function_is_too_long_or_too_wide():
    found = [f"{path.relative_to(ROOT)}: {what}" for path in sorted((ROOT / "pressocp").rglob("*.py"))
             for what in oversized(path.read_text())]
    assert found == []


def test_the_size_check_sees_a_long_and_a_wide_function():
    long = "def f():\n" + "    x = 1\n" * MAX_LINES
    wide = "def g(self, " + ", ".join(f"a{i}" for i in range(MAX_PARAMETERS + 1)) + "):\n    pass\n"
    assert oversized(long) == [f"f: {MAX_LINES + 1} lines"]
    assert oversized(wide) == [f"g: {MAX_PARAMETERS + 1} parameters"]
    assert oversized("def _h(" + ", ".join(f"a{i}" for i in range(20)) + "):\n    pass\n") == []
