import os
import signal
from concurrent.futures import Executor, Future

import matplotlib
import pytest
from hypothesis import settings

from pressocp import PressParams, SpeedProblem, design_speed

matplotlib.use("Agg")

# A test run started in the background by a shell without job control (``cmd &`` in a script, nohup)
# starts with SIGINT ignored, so Python installs no KeyboardInterrupt handler and the processes the
# tests start inherit the ignored signal: the Ctrl-C tests (test_interrupt, test_workers) then fail
# for the shell's reason. A user's terminal has the default, restored here (a child gets SIG_DFL).
if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

#: Hypothesis profiles, for the property tests that leave ``max_examples`` to them (each example a
#: design and a response, seconds): "default", the default run, draws a few; "thorough" many, chosen
#: with HYPOTHESIS_PROFILE=thorough (benchmarks/bench_slow_tests.py, the `slow_tests` job).
settings.register_profile("default", max_examples=12)
settings.register_profile("thorough", max_examples=200)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))


class Serial(Executor):
    """Runs each task when submitted, in this process."""

    def submit(self, fn, *args, **kwargs):
        f = Future()
        try:
            f.set_result(fn(*args, **kwargs))
        except BaseException as err:  # noqa: BLE001 - handed to the caller through the future
            f.set_exception(err)
        return f


@pytest.fixture
def serial():
    """An executor that runs every task in the test's process (sweeps without worker processes)."""
    return Serial()


@pytest.fixture(scope="session")
def impact_speed():
    """The rigid-designed speed of the default press at T = 0.8 s, -0.1 m/s over h/H 0.7 -> 0.3: its
    wrist-pin force reverses (the impact scenario)."""
    return design_speed(SpeedProblem(PressParams(), period=0.8, ram_speed=-0.1)).speed
