"""How pytest-xdist shares the tests between its worker processes (``python -m pytest -n 2``).

Each test is its own unit of work, handed to whichever worker is free, except the tests of a module
that builds a module-scoped fixture (a search, a browser, a Dask cluster, a workbench): they go to
one worker together, in their order, so that the fixture is built once. The units marked ``slow``
(``pytestmark = pytest.mark.slow`` in a module, or ``@pytest.mark.slow`` on a test: about a minute
on a 2-core machine) start first, so that no worker is left with a long test while the other has
finished; ``-m "not slow"`` leaves them out.
"""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

from xdist.scheduler import LoadScopeScheduling

from tests.support.paths import ROOT


@cache
def builds_a_module_fixture(module: str) -> bool:
    """Whether the test module (a path from the repository's root) defines a module-scoped fixture."""
    file = ROOT / module
    return file.suffix == ".py" and file.is_file() and 'scope="module"' in Path(file).read_text(encoding="utf-8")


@cache
def slow_tests(module: str) -> frozenset[str] | None:
    """The tests of a module (a path from the repository's root) marked ``slow``: None for all of them (the module's
    ``pytestmark`` has the mark), else the names of the test functions that carry it."""
    file = ROOT / module
    if file.suffix != ".py" or not file.is_file():
        return frozenset()
    tree = ast.parse(file.read_text(encoding="utf-8"))

    def slow(node: ast.expr) -> bool:
        return any(isinstance(part, ast.Attribute) and part.attr == "slow" for part in ast.walk(node))

    for statement in tree.body:
        if isinstance(statement, ast.Assign) and any(getattr(target, "id", "") == "pytestmark"
                                                     for target in statement.targets) and slow(statement.value):
            return None
    return frozenset(node.name for node in tree.body if isinstance(node, ast.FunctionDef)
                     and any(slow(decorator) for decorator in node.decorator_list))


def is_slow(scope: str) -> bool:
    """Whether a unit of work (a module or a test's node id) holds a test marked ``slow``."""
    module, _, test = scope.partition("::")
    marked = slow_tests(module)
    return marked is None or (bool(marked) and (not test or test.split("[")[0] in marked))


class SharedFixtureScheduling(LoadScopeScheduling):
    """Tests one at a time, a module's tests together when they share a module-scoped fixture; the longest first."""

    def _split_scope(self, nodeid: str) -> str:
        module = nodeid.split("::", 1)[0]
        return module if builds_a_module_fixture(module) else nodeid

    def _assign_work_unit(self, node) -> None:
        if not getattr(self, "ordered", False):  # the first assignment: the queue is full, in xdist's order
            ordered = sorted(self.workqueue.items(), key=lambda unit: not is_slow(unit[0]))  # stable: otherwise as before
            self.workqueue.clear()
            self.workqueue.update(ordered)
            self.ordered = True
        super()._assign_work_unit(node)
