from concurrent.futures import Executor, Future

import matplotlib
import pytest

matplotlib.use("Agg")


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
