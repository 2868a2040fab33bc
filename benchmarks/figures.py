"""Regenerate the committed figures in benchmarks/results/ (PNG):

* design_speed.png  rigid speed design of the 60 spm scenario (`pressocp design press60`)
* sixbar.png        six-bar stroke and the four-bar emulating it (seed Figs. 3-5)
* impacts.png       constant vs rigid-designed speed with clearances, 75 spm (`pressocp impacts`; seed Figs. 6, 9)
* simeon_midspan.png  Simeon flexible slider crank: midspan deflection beside the reference

    python benchmarks/figures.py
"""

import argparse
import shutil
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from pressocp import PressParams, Scenario  # noqa: E402
from pressocp.design import emulate_sixbar  # noqa: E402
from pressocp.jobs import design_job, impacts_job  # noqa: E402
from pressocp.mechanism import SixBar, constant_speed_zone  # noqa: E402
from pressocp.plots import plot_sixbar_emulation, save  # noqa: E402
from pressocp.rigid import rigid_kinematics  # noqa: E402
from pressocp.studies import SIMEON_REFERENCE, simeon_crank  # noqa: E402

OUT = Path(__file__).parent / "results"


def main() -> None:
    OUT.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:  # the jobs' other files are not committed figures
        design_job(Scenario.load("press60"), Path(tmp))
        impacts_job(Scenario.load("press75"), Path(tmp))
        shutil.copy(Path(tmp) / "design.png", OUT / "design_speed.png")
        shutil.copy(Path(tmp) / "impacts.png", OUT / "impacts.png")
    e = emulate_sixbar(PressParams())
    h_const = rigid_kinematics(PressParams(), 2 * np.pi * e["t"])["ram_height"]
    zone = constant_speed_zone(PressParams(), SixBar(), 1.0)
    save(plot_sixbar_emulation(e, h_const, (zone.t_start, zone.t_end)), OUT / "sixbar.png")
    fig, ax = plt.subplots(figsize=(8, 4.4))
    for n in (2, 4, 8):
        r = simeon_crank(n_elements=n)
        ax.plot(r.t, r.rod_midspan_deflection * 1e3, lw=1, label=f"pressocp, {n} elements "
                f"(w(0.1 s) = {r.rod_midspan_deflection[-1] * 1e3:.4f} mm)")
    ref = SIMEON_REFERENCE
    for y in (ref["midspan_extremes"], -ref["midspan_extremes"]):
        ax.axhline(y * 1e3, color="k", ls=":", lw=1)
    ax.plot([ref["t"]], [ref["midspan_deflection"] * 1e3], "k*", ms=10,
            label="test-set reference: 0.18932 mm at 0.1 s; extremes ±1.65 mm (dotted)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("midspan deflection [mm]")
    ax.set_title("Simeon flexible slider crank (150 rad/s, undamped 8 mm steel rod)", fontsize=9)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save(fig, OUT / "simeon_midspan.png")


if __name__ == "__main__":
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args()
    main()
