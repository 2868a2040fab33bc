"""The main job (README's first command) on the default scenario."""

import json

from pressocp.cli import main


def test_main_job_design(tmp_path, capsys):
    assert main(["--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "design_speed.json").read_text())
    assert summary["converged"] and summary["max_rel_ram_speed_error"] < 0.01
    assert (tmp_path / "design_speed.png").stat().st_size > 10_000
    assert "ram speed error" in capsys.readouterr().out
