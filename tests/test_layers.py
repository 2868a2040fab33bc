"""The package's layers import one way: `lint-imports` with the contracts in pyproject.toml passes,
and the same check fails on a contract that the code breaks (so the check is live)."""

from __future__ import annotations

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

