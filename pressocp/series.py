"""The catalog of a response's series that the package reports: the loads whose peaks are compared
before and after, the pin forces, and the peaks a `pressocp.result.SimResult` gives."""

#: Loads reported before and after an optimisation (peak magnitudes): N m and N.
PEAK_SERIES = ("torque", "slider_normal_force", "crank_pin_force", "wrist_pin_force")
#: The journals' force magnitudes, N.
PIN_FORCES = ("crank_pin_force", "wrist_pin_force")
#: The peaks of `SimResult.peaks`: the loads and the ram's acceleration (m/s^2).
RESPONSE_PEAKS = (*PEAK_SERIES, "ram_acceleration")
