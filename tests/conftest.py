
import pytest

from placement import load_robot
from placement.cli.memory import keep_freed_memory


@pytest.fixture
def orthoglide():
    """A freshly loaded Orthoglide (tests may modify its model)."""
    return load_robot("orthoglide")


@pytest.fixture
def fivebar():
    return load_robot("fivebar")


def pytest_configure(config):
    """The test processes keep freed memory for the next batch, as the command line does (placement.cli.memory)."""
    keep_freed_memory()


@pytest.hookimpl(tryfirst=True)
def pytest_sessionstart(session):
    """Under ``-n N``, before the workers start: the compiled kernels built once, into numba's disk cache, where
    the workers load them (tests/support/precompile.py)."""
    if session.config.pluginmanager.has_plugin("dsession"):  # pytest-xdist's controller, about to start workers
        from tests.support.precompile import compile_kernels

        compile_kernels()


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """Under ``-n N`` (pytest-xdist's default ``--dist load``): a module's tests that share a module-scoped fixture
    run in one worker, and the longest tests start first (tests/support/scheduling.py)."""
    if config.getvalue("dist") != "load":
        return None  # another --dist asked for explicitly
    from tests.support.scheduling import SharedFixtureScheduling

    return SharedFixtureScheduling(config, log)
