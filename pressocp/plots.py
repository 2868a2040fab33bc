"""Figures (matplotlib): speed designs, responses compared, impacts and optima.

No backend is chosen here: in Jupyter the figures show inline, and a script picks one with the
``MPLBACKEND`` convention (the command line uses Agg)."""

from __future__ import annotations

import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from .drive import Drive, MotorCycle
from .io import atomic_path
from .report import journal_orbits
from .result import SimResult
from .mechanism.ideal import ideal_response
from .units import force_unit, format_force, key_unit

#: Axis labels (with units) of the `SimResult` series, and the factor from SI to the plotted unit.
SERIES_LABELS = {
    "omega": ("crank speed ω [rad/s]", 1.0),
    "ram_height": ("ram height h [mm]", 1e3),
    "ram_velocity": ("ram velocity dh/dt [m/s]", 1.0),
    "ram_acceleration": ("ram acceleration [m/s²]", 1.0),
    "torque": ("motor torque [N·m]", 1.0),
    "slider_normal_force": ("slider normal force [N]", 1.0),
    "crank_pin_force": ("crank-pin force [N]", 1.0),
    "wrist_pin_force": ("wrist-pin force [N]", 1.0),
    "crank_pin_eccentricity": ("crank-pin eccentricity |e|/c [-]", 1.0),
    "wrist_pin_eccentricity": ("wrist-pin eccentricity |e|/c [-]", 1.0),
    "rod_midspan_deflection": ("rod midspan deflection [µm]", 1e6),
}


#: The `SimResult` series that are forces (N): an axis shows them in N or kN by the largest it draws.
FORCE_SERIES = ("slider_normal_force", "crank_pin_force", "wrist_pin_force")


def series_axis(name: str, *values) -> tuple[str, float]:
    """The axis label (with its unit) of a `SimResult` series and the factor from SI to that unit:
    `SERIES_LABELS`, a force in N or kN by the largest magnitude of `values` (N, arrays or numbers,
    `pressocp.units.force_unit`)."""
    label, scale = SERIES_LABELS.get(name, (name, 1.0))
    if name in FORCE_SERIES:
        unit, scale = force_unit(*values)
        label = label.replace("[N]", f"[{unit}]")
    return label, scale


def draw_levels(ax, levels: Sequence[tuple[float, str]], legend: bool = True, loc: str = "upper left") -> None:
    """Draw reference levels on an axis: each (value, label) as a dashed line at `value` (plotted
    units), and at -value too when the axis already shows negative values (a peak bounds the
    magnitude of a signed series), labelled once. With `legend`, the axis gets its own legend of the
    levels alone, at `loc`."""
    signed = any(np.nanmin(line.get_ydata(), initial=0.0) < 0 for line in ax.get_lines())
    handles = []
    for k, (value, label) in enumerate(levels):
        style = {"color": "0.25", "lw": 0.9, "ls": ("--", ":", "-.")[k % 3], "zorder": 1}
        handles.append(ax.axhline(value, label=label, **style))
        if value > 0 and signed:
            ax.axhline(-value, **style)
    if legend:
        ax.legend(handles=handles, fontsize=7, loc=loc)


def rigid_torque_level(objective: str, peak: float) -> tuple[float, str]:
    """The level (N m, label) of the rigid-press optimum's peak torque: the floor of the peak torque
    when that is the objective, else only the rigid optimum's peak (it minimised something else)."""
    name = "rigid-press floor" if objective == "peak_torque" else "rigid-press optimum's peak"
    return peak, f"{name} ±{peak:.1f} N·m"


def ram_speed_error_axis(ax, curves, window: tuple[float, float], ram_speed: float, tol: float) -> None:
    """Draw the ram speed in the working window relative to the one asked for (%), with the tolerance
    dashed: `curves` are (label, SimResult, plot keywords), each against its time from its first
    sample; `window` (s), `ram_speed` and `tol` (m/s). The axis spans three tolerances; a curve that
    leaves it gets a note in its colour with its largest error, and one that is mostly off it (a
    speed that was not designed to hold the window, e.g. the constant one) is not drawn (drawn, it
    was a vertical streak where it crossed the axis)."""
    limit = 300 * tol / abs(ram_speed)
    off_scale = []
    for curve, res, style in curves:
        t = res.t - res.t[0]
        inside = (t >= window[0]) & (t <= window[1])
        err = np.where(inside, 100 * (res.ram_velocity / ram_speed - 1), np.nan)
        worst = float(np.nanmax(np.abs(err), initial=0.0))
        shown = np.mean(np.abs(err[inside]) <= limit) >= 0.5 if inside.any() else True
        line, = ax.plot(t, err if shown else np.full_like(t, np.nan), label=curve, **style)
        if worst > limit:
            where = "beyond the axis" if shown else "off the scale, not drawn"
            off_scale.append((f"{curve}: up to {worst:.3g} % off ({where})", line.get_color()))
    for k, (text, color) in enumerate(off_scale):
        ax.text(0.01, 0.95 - 0.12 * k, text, transform=ax.transAxes, va="top", fontsize=7, color=color)
    for y in (-100 * tol / abs(ram_speed), 100 * tol / abs(ram_speed)):
        ax.axhline(y, color="k", ls="--", lw=0.8)
    ax.set_ylabel(f"ram speed error\nin the window [%]\n(asked {ram_speed:g} m/s)", fontsize=8)
    ax.set_ylim(-limit, limit)


def plot_responses(
    responses: Sequence[tuple[str, SimResult]],
    window: tuple[float, float] | None = None,
    series: Sequence[str] = ("omega", "ram_height", "ram_velocity", "torque", "slider_normal_force"),
    title: str = "",
    ram_speed: tuple[float, float] | None = None,
    levels: Mapping[str, Sequence[tuple[float, str]]] | None = None,
):
    """Stack time histories of several responses over one cycle, one axis per series.

    Parameters
    ----------
    responses : sequence of (label, SimResult)
        Curves to draw; each against its time from its first sample (a later cycle overlays the first).
    window : (t1, t2), optional
        Working window to shade, s.
    series : sequence of str
        `SimResult` field names to plot (`SERIES_LABELS` gives their axis labels and units).
    title : str
        Figure title.
    ram_speed : (target, tolerance), optional
        Ram velocity asked for in the window and its allowed deviation, m/s: with a window and a
        ram-velocity axis, a last axis shows the relative ram speed error over the window and the
        tolerance (dashed).
    levels : mapping of series name to sequence of (value, label), optional
        Reference levels to draw across a series' axis, in SI (`draw_levels`): the rigid-press
        floor of the peak torque, a cap on the pin forces.

    Returns
    -------
    matplotlib.figure.Figure
    """
    error_axis = ram_speed is not None and window is not None and "ram_velocity" in series
    rows = len(series) + error_axis
    fig, axes = plt.subplots(rows, 1, figsize=(8, 1.9 * rows + 0.6), sharex=True)
    axes = np.atleast_1d(axes)
    for ax, name in zip(axes, series):
        label, scale = series_axis(name, *(getattr(res, name) for _, res in responses))
        for curve, res in responses:
            ax.plot(res.t - res.t[0], getattr(res, name) * scale, label=curve, lw=1.1)
        ax.set_ylabel(label, fontsize=8)
        if levels and name in levels:
            draw_levels(ax, [(value * scale, text) for value, text in levels[name]], legend=ax is not axes[0])
    if error_axis:
        ram_speed_error_axis(axes[-1], [(curve, res, {"lw": 1.1}) for curve, res in responses], window, *ram_speed)
    for ax in axes:
        if window is not None:
            ax.axvspan(*window, color="0.9", zorder=0)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")
    axes[-1].set_xlabel("time in the cycle t [s]" + (" (grey: working window)" if window is not None else ""))
    if title:
        fig.suptitle(textwrap.fill(title, 100), fontsize=10)
    fig.tight_layout()
    return fig


#: The orbits' unit: micrometres per metre.
MICROMETRES = 1e6


def plot_journal_orbits(
    responses: Sequence[tuple[str, SimResult]],
    state_names: Sequence[str],
    clearances: Mapping[str, float],
    window: tuple[float, float] | None = None,
    title: str = "",
):
    """The journal orbits of the joints with clearance: per joint (one column), the journal's x/y
    eccentricity inside the clearance circle (µm, equal aspect; the cycle's start marked; the
    model's e, the bearing centre minus the journal centre, x across the slide and y along it), and
    under it the eccentricity ratio |e|/c against time.

    Parameters
    ----------
    responses : sequence of (label, SimResult)
        Responses to draw; those without states (the ideal press) appear in the time panels only.
    state_names : sequence of str
        The model's state names (`PressModel.state_names`: ``crank_pin_ex``, ...) naming the rows
        of `SimResult.states`.
    clearances : mapping of joint name to float
        The radial clearance of each joint to draw, m (its circle's radius).
    window : (t1, t2), optional
        Working window to shade in the time panels, s.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    joints = list(clearances)
    fig, axes = plt.subplots(2, len(joints), figsize=(4.6 * len(joints) + 0.6, 8.4), squeeze=False,
                             gridspec_kw={"height_ratios": [1.6, 1.0]})
    for col, joint in enumerate(joints):
        orbit_ax, time_ax = axes[0, col], axes[1, col]
        radius = clearances[joint] * MICROMETRES
        reach = radius
        for k, (curve, res) in enumerate(responses):
            orbit = journal_orbits(res, state_names)
            if f"{joint}_ex" in orbit:
                x, y = orbit[f"{joint}_ex"] * MICROMETRES, orbit[f"{joint}_ey"] * MICROMETRES
                orbit_ax.plot(x, y, color=f"C{k}", lw=0.9, label=curve)
                orbit_ax.plot(x[:1], y[:1], "o", color=f"C{k}", ms=4)
                reach = max(reach, float(np.max(np.hypot(x, y))))
            time_ax.plot(res.t - res.t[0], getattr(res, f"{joint}_eccentricity"), color=f"C{k}", lw=1.0, label=curve)
        orbit_ax.add_patch(plt.Circle((0.0, 0.0), radius, fill=False, color="k", ls="--", lw=1.0,
                                      label=f"clearance c = {radius:.4g} µm"))
        orbit_ax.set_xlim(-1.1 * reach, 1.1 * reach)
        orbit_ax.set_ylim(-1.1 * reach, 1.1 * reach)
        orbit_ax.set_aspect("equal")
        orbit_ax.set_xlabel("eccentricity e_x, across the slide [µm]", fontsize=8)
        orbit_ax.set_ylabel("eccentricity e_y, along the slide [µm]", fontsize=8)
        orbit_ax.set_title(f"{joint.replace('_', ' ')}: journal orbit (dot: cycle start)", fontsize=9)
        orbit_ax.legend(fontsize=7, loc="best")
        orbit_ax.grid(alpha=0.3)
        time_ax.set_ylabel(SERIES_LABELS[f"{joint}_eccentricity"][0], fontsize=8)
        time_ax.set_xlabel("time in the cycle t [s]" + (" (grey: working window)" if window is not None else ""))
        if window is not None:
            time_ax.axvspan(*window, color="0.9", zorder=0)
        time_ax.grid(alpha=0.3)
    axes[1, 0].legend(fontsize=7, loc="best")
    if title:
        fig.suptitle(textwrap.fill(title, 100), fontsize=10)
    fig.tight_layout()
    return fig


def save(fig, path: str | Path) -> Path:
    """Save a figure as PNG (150 dpi) atomically (`pressocp.io.atomic_path`) and close it."""
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=150, format="png")
    finally:
        plt.close(fig)
    return Path(path)


def plot_sixbar_emulation(emulation: dict, constant_height=None, zone_times=None):
    """Figs. 3-5 of the source paper: six-bar stroke, the four-bar's with the fitted speed, that
    speed, and both presses' motor torque on ideal joints (the six-bar at constant input speed).

    Parameters
    ----------
    emulation : dict
        From `pressocp.design.emulate_sixbar`.
    constant_height : ndarray, optional
        Four-bar ram height at constant crank speed, for comparison (m).
    zone_times : (t1, t2), optional
        Six-bar working zone to shade, s.
    """
    e = emulation
    t = e["t"]
    fig, axes = plt.subplots(4, 1, figsize=(8, 9.5), sharex=True)
    axes[0].plot(t, e["h_sixbar"] * 1e3, lw=2.5, color="0.6", label="six-bar drag-link press")
    axes[0].plot(t, e["h_fourbar"] * 1e3, "--", color="C3", label="four-bar, fitted 15-harmonic speed")
    if constant_height is not None:
        axes[0].plot(t, constant_height * 1e3, ":", color="C0", label="four-bar, constant speed")
    axes[0].set_ylabel("ram height h [mm]")
    axes[1].plot(t, e["v_sixbar"], lw=2.5, color="0.6", label="six-bar")
    axes[1].plot(t, e["v_fourbar"], "--", color="C3", label="four-bar, fitted speed")
    axes[1].set_ylabel("ram velocity [m/s]")
    axes[2].plot(t, e["speed"].omega(t), color="C3", label="required four-bar crank speed")
    axes[2].axhline(e["speed"].mean_speed, color="0.5", lw=0.8, ls=":", label="mean speed 2π/T")
    axes[2].set_ylabel("crank speed ω [rad/s]")
    axes[3].plot(t, e["torque_sixbar"], lw=2.5, color="0.6",
                 label=f"six-bar, constant input speed (peak {np.max(np.abs(e['torque_sixbar'])):.3g} N·m)")
    axes[3].plot(t, e["torque_fourbar"], "--", color="C3",
                 label=f"four-bar, fitted speed (peak {np.max(np.abs(e['torque_fourbar'])):.3g} N·m)")
    axes[3].set_ylabel("motor torque [N·m]\n(ideal joints)")
    axes[3].set_xlabel("time t [s]")
    err = e["max_position_error"] / (np.max(e["h_sixbar"]) - np.min(e["h_sixbar"]))
    axes[0].set_title(f"Four-bar servo press emulating a six-bar link press (max position error {100 * err:.2g} % of stroke)",
                      fontsize=9)
    for ax in axes:
        if zone_times is not None:
            ax.axvspan(*zone_times, color="0.92", zorder=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_impact_study(study) -> "plt.Figure":
    """Figs. 6 and 9 of the source paper: torque, slider normal force and wrist-pin force, clearance vs ideal joints,
    at constant speed (left) and at the rigid-designed speed (right)."""
    fig, axes = plt.subplots(4, 2, figsize=(12, 9), sharex="col")
    cols = [("constant crank speed", study.constant, study.constant_rigid),
            ("rigid-designed speed", study.designed, study.designed_rigid)]
    rows = [series_axis(name, *(getattr(r, name) for _, *pair in cols for r in pair)) + (name,)
            for name in ("omega", "torque", "slider_normal_force", "wrist_pin_force")]
    ratios = study.ratios()
    for j, (title, clr, rig) in enumerate(cols):
        for i, (label, scale, name) in enumerate(rows):
            ax = axes[i, j]
            ax.plot(clr.t, getattr(clr, name) * scale, lw=0.9, color="C3", label="model with clearance")
            ax.plot(rig.t, getattr(rig, name) * scale, lw=1.6, color="k", ls="--", label="ideal joints")
            ax.grid(alpha=0.3)
            if j == 0:
                ax.set_ylabel(label, fontsize=8)
        key = "constant" if j == 0 else "designed"
        axes[0, j].set_title(f"{title}: peak torque ×{ratios[key]['torque']:.2f}, "
                             f"normal force ×{ratios[key]['slider_normal_force']:.2f} of ideal", fontsize=9)
        axes[-1, j].set_xlabel("time t [s]")
        if j == 1:
            for ax in axes[:, j]:
                ax.axvspan(study.design.t1, study.design.t2, color="0.92", zorder=0)
    axes[1, 0].legend(fontsize=8)
    fig.tight_layout()
    return fig


#: An axis of `plot_speed_design` is scaled to the answer when the initial speed's range is more than
#: this many times the answer's (its impact spikes then flattened the answer and the goal lines).
FOCUS_RATIO = 2.5


def focus_on_answer(ax, initial: np.ndarray, others: Sequence[np.ndarray], unit: str) -> None:
    """Scale `ax` to the `others` (the answer, the rigid optimum, reference levels) with 30 % room when
    the `initial` curve spans more than `FOCUS_RATIO` times their range; its spikes then run off the
    axis and a note in its colour gives its extremes (in `unit`, the axis's)."""
    values = np.concatenate([np.asarray(y, float).ravel() for y in others])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return
    lo, hi = float(values.min()), float(values.max())
    first, last = float(np.nanmin(initial)), float(np.nanmax(initial))
    if hi <= lo or last - first <= FOCUS_RATIO * (hi - lo):
        return
    room = 0.3 * (hi - lo)
    ax.set_ylim(lo - room, hi + room)
    # four significant digits of the larger extreme, the same decimals for both (a 0 was 5.5e-37)
    decimals = max(0, 3 - int(np.floor(np.log10(max(abs(first), abs(last), 1e-300)))))
    ax.text(0.01, 0.03, f"initial speed: {first:,.{decimals}f} to {last:,.{decimals}f} {unit} (off the scale)",
            transform=ax.transAxes,
            fontsize=7, color="tab:red", va="bottom", zorder=5,
            bbox={"facecolor": "white", "alpha": 0.9, "edgecolor": "none", "pad": 1.5})


def plot_speed_design(result, title: str = "",
                      levels: Mapping[str, Sequence[tuple[float, str]]] | None = None) -> "plt.Figure":
    """Initial vs optimal speed (an `pressocp.ocp.OcpResult`): crank speed, motor torque, slider normal
    force and ram velocity on the target model, with the rigid optimum on the rigid model dashed and
    the working window shaded (Figs. 9-11 of the source paper).

    The torque axis shows the rigid-press optimum's peak (±; the floor, the least peak a rigid press
    allows, when the objective is the peak torque). When
    the problem caps the pin forces, an axis shows the larger pin force against the cap. A last axis
    shows the optimum's ram speed error in its window against the tolerance (dashed).

    Parameters
    ----------
    result : OcpResult
        From `optimize_speed`, with its initial and optimal simulations.
    title : str
        Figure title.
    levels : mapping of series name to sequence of (value, label), optional
        More reference levels (SI) for the axes ``"torque"``, ``"slider_normal_force"``,
        ``"pin_force"`` (when shown), drawn after the built-in ones (`draw_levels`).
    """
    si, so = result.initial_simulation, result.simulation
    if si is None or so is None:
        raise ValueError("result must hold the initial and optimal simulations (from optimize_speed)")
    cap = result.problem.max_pin_force
    rr = ideal_response(result.problem.press, result.problem.mechanism, result.rigid.speed, so.t)
    rows = [("omega", "crank speed ω, rad/s"), ("torque", "motor torque, N·m"),
            ("slider_normal_force", "slider normal force, N")]
    if cap is not None:
        rows.append(("pin_force", "larger pin force, N"))
    rows.append(("ram_velocity", "ram velocity, m/s"))
    fig, axes = plt.subplots(len(rows) + 1, 1, figsize=(8, 2.3 * len(rows) + 2.3), sharex=True)
    label = "optimum" if result.success else "best iterate (not converged)"
    curves = [("initial (rigid design), target model", si, {"lw": 0.8, "color": "tab:red"}),
              (f"{label}, target model", so, {"lw": 1.0, "color": "tab:blue"}),
              ("rigid optimum, rigid press", rr, {"lw": 0.8, "ls": "--", "color": "k"})]
    drawn = {"torque": [rigid_torque_level(result.problem.objective, result.rigid_peak_torque)]}
    if cap is not None:
        drawn["pin_force"] = [(cap, f"pin-force cap {format_force(cap)}")]
    for key, extra in (levels or {}).items():
        drawn.setdefault(key, []).extend(extra)
    for ax, (key, name) in zip(axes, rows):
        ys = [np.maximum(res.crank_pin_force, res.wrist_pin_force) if key == "pin_force" else getattr(res, key)
              for _, res, _ in curves]
        unit, scale = force_unit(*ys) if name.endswith(", N") else (None, 1.0)
        for (curve, res, style), y in zip(curves, ys):
            ax.plot(res.t, y * scale, label=curve, **style)
        ax.set_ylabel(name if unit is None else f"{name[:-1]}{unit}")
        marks = [value * scale for value, _ in drawn.get(key, [])]
        if key != "omega":
            focus_on_answer(ax, ys[0] * scale, [y * scale for y in ys[1:]] + [np.array(marks)],
                            unit or name.rsplit(", ", 1)[-1])
        if drawn.get(key):  # where the curves and levels leave room (impact spikes fill either end)
            draw_levels(ax, [(value * scale, text) for value, text in drawn[key]], loc="best")
    # the window's times are the optimum's (another speed crosses h/H at other times)
    ram_speed_error_axis(axes[-1], curves[1:2], (result.t1, result.t2), result.problem.ram_speed, result.problem.tol)
    for ax in axes:
        ax.axvspan(result.t1, result.t2, color="0.9", zorder=0)
        ax.grid(alpha=0.3)
    # upper centre: over the working window, where the crank runs slowly (upper right hid the return peak)
    axes[0].legend(fontsize=7, loc="upper center")
    axes[-1].set_xlabel("time, s (grey: working window)")
    if title:
        axes[0].set_title(title, fontsize=9)
    fig.tight_layout()
    return fig


def key_label(key: str, values=()) -> str:
    """A varied key with its display unit (`pressocp.units.key_unit`), for an axis:
    ``"problem.ram_speed [m/s]"``, ``"crank_pin.clearance [mm]"``; a force in N or kN by the
    largest of `values` (N)."""
    unit, _ = key_unit(key, values)
    return f"{key} [{unit}]" if unit else key


def key_values(key: str, values, column=None):
    """A varied key's values (SI) in the display unit of its whole `column` (default `values`;
    `pressocp.units.key_unit`); as given for a key without a unit (a name, a ratio)."""
    if key_unit(key)[0] is None:
        return values
    _, factor = key_unit(key, values if column is None else column)
    return np.asarray(values, dtype=float) * factor


#: A sweep figure's panels: (axis label, [(column, style, legend entry or None for the point's own)]).
#: The impacts task's rows hold ratios of peaks (model / rigid press) instead of peaks.
SWEEP_PANELS = (
    ("peak motor torque [N·m]", (("peak_torque_N_m", "o-", None), ("initial_peak_torque_N_m", "x:", "initial speed"),
                                 ("rigid_peak_torque_N_m", "--", "rigid-press floor"))),
    ("peak slider normal force [N]", (("peak_slider_normal_force_N", "o-", None),)),
    ("peak pin force [N]", (("peak_pin_force_N", "o-", None),)),
)
IMPACT_PANELS = tuple(
    (f"{series.replace('_', ' ')}:\nclearance model / rigid press", ((f"designed_{series}_ratio", "o-", None),
                                                                    (f"constant_{series}_ratio", "x:", "constant speed")))
    for series in ("torque", "slider_normal_force", "crank_pin_force", "wrist_pin_force"))


def _key_value(key: str, value: float, column) -> str:
    """``"key = value unit"`` of one value of a varied key, in the unit its whole `column` is shown in."""
    if key_unit(key)[0] is None:
        return f"{key} = {value:g}" if isinstance(value, (int, float)) else f"{key} = {value}"
    unit, factor = key_unit(key, column)
    return f"{key} = {value * factor:g} {unit}"


#: A linear panel whose values all lie within this share of their largest says so (`note_narrow_span`).
NARROW_SPAN = 0.1


def note_narrow_span(ax) -> None:
    """On a linear axis that does not start at 0, write how narrow the drawn values' span is when it
    is under `NARROW_SPAN` of their largest magnitude: matplotlib fits the axis to the data, so a
    1 % change fills the panel."""
    ys = [np.asarray(line.get_ydata(), float) for line in ax.get_lines()]
    ys = np.concatenate([y[np.isfinite(y)] for y in ys]) if ys else np.zeros(0)
    if ax.get_yscale() != "linear" or ys.size < 2:
        return
    lo, hi = float(ys.min()), float(ys.max())
    big = max(abs(lo), abs(hi))
    if big == 0.0 or lo * hi <= 0.0 or (hi - lo) >= NARROW_SPAN * big:
        return
    # above the panel, on its right (inside it the text ran over the data)
    ax.set_title(f"all within {100 * (hi - lo) / big:.2g} % of {big:,.4g} (the axis does not start at 0)",
                 loc="right", fontsize=7, color="0.35")


def plot_sweep(table, keys: Sequence[str], title: str = "") -> "plt.Figure":
    """Peaks against the first varied key of a `pressocp.sweep` table, one colour per combination of
    the other keys: motor torque (with the initial speed's and the rigid floor, for optima), slider
    normal force and the larger pin force; for the impacts task, each load's peak on the clearance
    model over the rigid press's, at the designed speed (and dotted at constant speed). Points not
    ``ok`` are left out. Raises ValueError when no point has anything to draw."""
    data = table[table["ok"].astype(bool)].copy() if "ok" in table else table.copy()
    if "peak_crank_pin_force_N" in data:
        data["peak_pin_force_N"] = data[["peak_crank_pin_force_N", "peak_wrist_pin_force_N"]].max(axis=1)
    panels = [(name, [c for c in cols if c[0] in data and data[c[0]].notna().any()])
              for name, cols in (SWEEP_PANELS if "peak_torque_N_m" in data else IMPACT_PANELS)]
    panels = [(name, cols) for name, cols in panels if cols]
    if data.empty or not panels:
        why = "no point is ok" if data.empty else "its rows hold no peaks or impact ratios"
        raise ValueError(f"nothing to draw: {why} ({len(table)} rows)")
    x, others = keys[0], list(keys[1:])
    scales = [force_unit(*(data[c] for c, _, _ in cols)) if name.endswith("[N]") else (None, 1.0)
              for name, cols in panels]
    groups = data.groupby(others, sort=True) if others else [((), data)]
    fig, axes = plt.subplots(len(panels), 1, figsize=(7, 2.4 * len(panels) + 0.6), sharex=True, squeeze=False)
    axes = axes[:, 0]
    for k, (values, group) in enumerate(groups):
        values = values if isinstance(values, tuple) else (values,)
        label = (", ".join(_key_value(o, v, data[o]) for o, v in zip(others, values))
                 or ("optimum" if "rigid_peak_torque_N_m" in group else "model"))
        group = group.sort_values(x)
        for ax, (_, cols), (_, scale) in zip(axes, panels, scales):
            for col, style, entry in cols:
                ax.plot(key_values(x, group[x], data[x]), group[col] * scale, style, color=f"C{k}",
                        lw=1.5 if entry is None else 0.8, label=label if entry is None else (entry if k == 0 else None))
    for ax, (name, _), (unit, _) in zip(axes, panels, scales):
        ax.set_ylabel(name if unit is None else f"{name[:-3]}[{unit}]", fontsize=8)
        ax.grid(alpha=0.3)
    if "initial_peak_torque_N_m" in data and data["initial_peak_torque_N_m"].max() > 5 * data["peak_torque_N_m"].max():
        axes[0].set_yscale("log")  # an impacting initial speed would flatten the optima against the floor
    for ax in axes:
        note_narrow_span(ax)
    axes[0].legend(fontsize=7)
    axes[-1].set_xlabel(key_label(x, data[x]))
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def plot_tornado(sensitivities, quantity: str = "peak_torque", title: str = "", ax=None) -> "plt.Figure":
    """Normalised sensitivities p/J dJ/dp of one quantity (a `pressocp.Sensitivities`), largest on top:
    the % change of the peak per % change of each parameter. One-sided rows (rival peaks) show both
    sides; rows whose error estimate is over `pressocp.sensitivity.RESOLVED` are grey and hatched
    (not resolved: their sign and size are not known). Drawn on `ax` when given (a panel of a larger
    figure)."""
    from .sensitivity import RESOLVED

    t = sensitivities.table[sensitivities.table["quantity"] == quantity].copy()
    scale = t["parameter_value"] / t["value"]
    t["up"], t["down"] = t["derivative_up"] * scale, t["derivative_down"] * scale
    t = t.reindex(t["normalised"].abs().sort_values().index)
    own = ax is None
    fig, ax = plt.subplots(figsize=(7, 0.45 * len(t) + 1.2)) if own else (ax.figure, ax)
    y = np.arange(len(t))
    resolved = t["resolved"].to_numpy(bool) if "resolved" in t else np.ones(len(t), bool)
    colours = ["tab:red" if v > 0 else "tab:blue" for v in t["normalised"]]
    ax.barh(y[resolved], t["normalised"][resolved], color=np.array(colours)[resolved])
    if not resolved.all():
        ax.barh(y[~resolved], t["normalised"][~resolved], color="0.85", edgecolor="0.5", hatch="//",
                label=f"not resolved (error estimate over {RESOLVED:.0%})")
    labelled = False
    for k, (_, row) in enumerate(t.iterrows()):
        if not row["unique"]:
            ax.plot([row["down"], row["up"]], [k, k], "k|-", lw=1, ms=8,
                    label=None if labelled else "rival peaks: p increasing / decreasing")
            labelled = True
    if not resolved.all() or not t["unique"].all():
        ax.legend(fontsize=7, loc="lower right")
    # each bar's value at its end, so that a short one (the only resolved row beside unresolved ones
    # hundreds of times longer) is still read
    for k, v in enumerate(t["normalised"].to_numpy(float)):
        ax.annotate(f"{v:+.3g}", (v, k), xytext=(3 if v >= 0 else -3, 0), textcoords="offset points",
                    va="center", ha="left" if v >= 0 else "right", fontsize=7)
    ax.margins(x=0.2)
    ax.set_yticks(y, t["parameter"])
    ax.axvline(0, color="k", lw=0.8)
    ax.set_xlabel(f"p / J · dJ/dp of {quantity} (% per %)")
    ax.grid(alpha=0.3, axis="x")
    if title:
        ax.set_title(title, fontsize=9)
    if own:
        fig.tight_layout()
    return fig


def plot_wear(table, design_clearance: float | None = None, title: str = "") -> "plt.Figure":
    """A `pressocp.studies.wear_study` table against the clearance (mm): peak torque on the model and on
    the ideal press, peak pin forces, and each journal's smallest eccentricity ratio (below the dashed
    line the journal leaves its wall: free flight and impact). `design_clearance` (m) is marked."""
    from .studies import FREE_FLIGHT_ECCENTRICITY

    c = table["clearance"] * 1e3
    fig, axes = plt.subplots(3, 1, figsize=(7, 7.4), sharex=True)
    axes[0].plot(c, table["peak_torque_N_m"], "o-", label="clearance model")
    axes[0].plot(c, table["ideal_joints_peak_torque_N_m"], "--", color="0.4", label="ideal joints")
    axes[0].set_ylabel("peak motor torque [N·m]")
    unit, scale = force_unit(*(table[f"peak_{j}_force_N"] for j in ("crank_pin", "wrist_pin")
                               if f"peak_{j}_force_N" in table))
    for k, joint in enumerate(("crank_pin", "wrist_pin")):
        if f"peak_{joint}_force_N" in table:
            axes[1].plot(c, table[f"peak_{joint}_force_N"] * scale, "o-", color=f"C{k}", label=joint.replace("_", " "))
        if f"min_{joint}_eccentricity" in table:
            axes[2].plot(c, table[f"min_{joint}_eccentricity"], "o-", color=f"C{k}", label=joint.replace("_", " "))
    axes[1].set_ylabel(f"peak pin force [{unit}]")
    axes[2].axhline(FREE_FLIGHT_ECCENTRICITY, ls="--", color="0.4", lw=0.8, label="leaves the wall")
    axes[2].set_ylabel("smallest |e|/c [-]")
    axes[2].set_xlabel("clearance of both joints [mm]")
    for ax in axes:
        if design_clearance is not None:
            ax.axvline(design_clearance * 1e3, color="0.6", lw=0.8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def plot_torque_speed(drive: Drive, cycles: Mapping[str, MotorCycle], title: str = "") -> "plt.Figure":
    """The cycles' operating points (motor torque against motor speed, in rpm) over the motor's
    envelope: its peak-torque curve in both directions, its continuous rating, its top speed, and
    each cycle's RMS torque as a dashed line."""
    rpm = 60 / (2 * np.pi)
    fig, ax = plt.subplots(figsize=(8, 5.5))
    speeds = np.linspace(0.0, drive.max_speed, 400)
    peak = drive.peak_torque_at(speeds)
    ax.fill_between(speeds * rpm, -peak, peak, color="0.93", label="peak-torque envelope")
    ax.plot(speeds * rpm, peak, color="0.4", lw=1.5)
    ax.plot(speeds * rpm, -peak, color="0.4", lw=1.5)
    for sign in (1, -1):
        ax.axhline(sign * drive.continuous_torque, color="0.4", ls=":", lw=1.2,
                   label="continuous rating" if sign == 1 else None)
    ax.axvline(drive.max_speed * rpm, color="0.4", ls="--", lw=1.2, label="top speed")
    for k, (label, c) in enumerate(cycles.items()):
        color = f"C{k}"
        ax.plot(c.speed * rpm, c.torque, color=color, lw=1.4,
                label=f"{label}: peak {c.peak_torque:.3g} N·m, RMS {c.rms_torque:.3g} N·m")
        ax.axhline(c.rms_torque, color=color, ls="--", lw=0.9)
    ax.set_xlabel("motor speed [rpm]")
    ax.set_ylabel("motor torque [N·m] (positive: driving)")
    ax.set_xlim(0.0, 1.05 * max(drive.max_speed, *(c.max_speed for c in cycles.values())) * rpm)
    ax.set_title(title or f"operating points over the motor's envelope (gear ratio {drive.gear_ratio:g})", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return fig


#: The panels of `plot_compared_cycles`: (series, axis label with "{unit}" for forces, unit in SI).
COMPARED_SERIES = (("torque", "crank torque [N·m]"), ("ram_velocity", "ram velocity dh/dt [m/s]"),
                   ("crank_pin_force", "crank-pin force [{unit}]"), ("wrist_pin_force", "wrist-pin force [{unit}]"))


def plot_compared_cycles(cycles: Sequence[tuple[str, Mapping[str, np.ndarray]]], title: str = "") -> "plt.Figure":
    """Designs overlaid against the crank angle (degrees from the first sample's turn, so that designs
    at other stroke rates line up): crank torque, ram velocity and the two pin forces (N, or kN from
    10 kN: `pressocp.units.force_unit`, one unit per axis).

    Parameters
    ----------
    cycles : sequence of (label, mapping)
        Each design's one cycle: ``theta`` (rad), ``torque`` (N m), ``ram_velocity`` (m/s),
        ``crank_pin_force`` and ``wrist_pin_force`` (N), arrays over the same samples; a missing
        series is not drawn for that design.
    title : str
        Figure title.
    """
    fig, axes = plt.subplots(len(COMPARED_SERIES), 1, figsize=(8, 2.1 * len(COMPARED_SERIES) + 0.8), sharex=True)
    for ax, (name, label) in zip(axes, COMPARED_SERIES):
        present = [k for k, (_, c) in enumerate(cycles) if name in c and "theta" in c]
        unit, scale = force_unit(*(cycles[k][1][name] for k in present)) if "{unit}" in label else (None, 1.0)
        for k in present:
            curve, c = cycles[k]
            turn = 2 * np.pi * np.floor(c["theta"][0] / (2 * np.pi))
            ax.plot(np.degrees(c["theta"] - turn), np.asarray(c[name]) * scale, color=f"C{k}", lw=1.1, label=curve)
        ax.set_ylabel(label.format(unit=unit), fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")
    axes[-1].set_xlabel("crank angle θ [deg] (0: top dead centre)")
    axes[-1].set_xticks(np.arange(0, 361, 45))
    if title:
        fig.suptitle(textwrap.fill(title, 100), fontsize=10)
    fig.tight_layout()
    return fig


def plot_operating_points(points: Sequence[tuple[str, Drive, np.ndarray, np.ndarray]], title: str = "") -> "plt.Figure":
    """Designs' motor operating points overlaid (torque against speed, rpm), each over its own drive's
    peak-torque envelope (one curve when the drives are equal) and top speed.

    Parameters
    ----------
    points : sequence of (label, Drive, motor speed rad/s, motor torque N m)
        Each design's drive and its cycle's operating points.
    title : str
        Figure title.
    """
    rpm = 60 / (2 * np.pi)
    fig, ax = plt.subplots(figsize=(8, 5.5))
    drawn: list[Drive] = []
    for k, (label, drive, speed, torque) in enumerate(points):
        color = f"C{k}"
        if drive not in drawn:
            speeds = np.linspace(0.0, drive.max_speed, 400)
            peak = drive.peak_torque_at(speeds)
            which = "both" if all(d == drive for _, d, _, _ in points) else label
            ax.plot(speeds * rpm, peak, color=color, ls="--", lw=1.2, label=f"peak-torque envelope ({which})")
            ax.plot(speeds * rpm, -peak, color=color, ls="--", lw=1.2)
            ax.axvline(drive.max_speed * rpm, color=color, ls=":", lw=1.0)
            drawn.append(drive)
        ax.plot(np.asarray(speed) * rpm, torque, color=color, lw=1.4,
                label=f"{label}: peak {np.max(np.abs(torque)):.3g} N·m (gear ratio {drive.gear_ratio:g})")
    ax.set_xlabel("motor speed [rpm] (dotted: top speed)")
    ax.set_ylabel("motor torque [N·m] (positive: driving)")
    ax.set_xlim(0.0, None)
    ax.set_title(title or "operating points over the motors' envelopes", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return fig
