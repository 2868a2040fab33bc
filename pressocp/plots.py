"""Figures (matplotlib, Agg-safe): speed designs and strokes."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .result import SimResult  # noqa: E402


def plot_responses(
    responses: Sequence[tuple[str, SimResult]],
    window: tuple[float, float] | None = None,
    series: Sequence[str] = ("omega", "ram_height", "ram_velocity", "torque", "slider_normal_force"),
    title: str = "",
):
    """Stack time histories of several responses, one axis per series.

    Parameters
    ----------
    responses : sequence of (label, SimResult)
        Curves to draw.
    window : (t1, t2), optional
        Working window to shade, s.
    series : sequence of str
        `SimResult` field names to plot.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    labels = {
        "omega": "crank speed ω [rad/s]",
        "ram_height": "ram height h [mm]",
        "ram_velocity": "ram velocity dh/dt [m/s]",
        "ram_acceleration": "ram acceleration [m/s²]",
        "torque": "motor torque [N·m]",
        "slider_normal_force": "slider normal force [N]",
        "crank_pin_force": "crank-pin force [N]",
        "wrist_pin_force": "wrist-pin force [N]",
        "rod_midspan_deflection": "rod midspan deflection [µm]",
    }
    scale = {"ram_height": 1e3, "rod_midspan_deflection": 1e6}
    fig, axes = plt.subplots(len(series), 1, figsize=(8, 1.9 * len(series) + 0.6), sharex=True)
    axes = np.atleast_1d(axes)
    for ax, name in zip(axes, series):
        for label, res in responses:
            ax.plot(res.t, getattr(res, name) * scale.get(name, 1.0), label=label, lw=1.2)
        if window is not None:
            ax.axvspan(*window, color="0.9", zorder=0)
        ax.set_ylabel(labels.get(name, name), fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")
    axes[-1].set_xlabel("time t [s]")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def save(fig, path) -> None:
    """Save a figure as PNG (150 dpi) and close it."""
    fig.savefig(path, dpi=150)
    plt.close(fig)
