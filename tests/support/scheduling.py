"""How pytest-xdist shares the tests between its worker processes (``python -m pytest -n 2``).

Each test is its own unit of work, handed to whichever worker is free, except the tests of a module
that builds a module-scoped fixture (a search, a browser, a Dask cluster, a workbench): they go to
one worker together, in their order, so that the fixture is built once. The longest units start
first, so that no worker is left with a long test while the other has finished.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from xdist.scheduler import LoadScopeScheduling

from tests.support.paths import ROOT

# Units that take a minute or so on a 2-core machine (a Dask cluster, a browser, searches); they start first. Only
# the order changes: every test runs either way.
LONGEST_FIRST = ("tests/output/test_workbench_browser.py", "tests/evaluation/test_cluster.py",
                 "tests/cell/test_cell_search.py", "tests/search/test_study.py", "tests/cli/test_reuse.py",
                 "tests/search/test_optimize.py", "tests/path/test_gcode.py::test_the_pocket_example_runs_end_to_end")


@cache
def builds_a_module_fixture(module: str) -> bool:
    """Whether the test module (a path from the repository's root) defines a module-scoped fixture."""
    file = ROOT / module
    return file.suffix == ".py" and file.is_file() and 'scope="module"' in Path(file).read_text(encoding="utf-8")


class SharedFixtureScheduling(LoadScopeScheduling):
    """Tests one at a time, a module's tests together when they share a module-scoped fixture; the longest first."""

    def _split_scope(self, nodeid: str) -> str:
        module = nodeid.split("::", 1)[0]
        return module if builds_a_module_fixture(module) else nodeid

    def _assign_work_unit(self, node) -> None:
        if not getattr(self, "ordered", False):  # the first assignment: the queue is full, in xdist's order
            def rank(scope: str) -> int:
                return next((k for k, prefix in enumerate(LONGEST_FIRST) if scope.startswith(prefix)), len(LONGEST_FIRST))

            ordered = sorted(self.workqueue.items(), key=lambda unit: rank(unit[0]))  # stable: otherwise as before
            self.workqueue.clear()
            self.workqueue.update(ordered)
            self.ordered = True
        super()._assign_work_unit(node)
