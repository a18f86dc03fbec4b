"""A map and a Pareto front on a Dask distributed cluster give the numbers the local process pool gives."""

from __future__ import annotations

import dataclasses
import os

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.evaluation.parallel import cluster, scheduler_address
from placement.path.path_file import Timing
from placement.search.optimize import SearchSettings
from placement.search.pareto import pareto_front
from placement.search.sweep import sweep

pytestmark = pytest.mark.slow  # about a minute on a 2-core machine: starts first under -n 2

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def dask_cluster():
    """A local cluster; this process's environment is restored afterwards (Dask's nannies set OMP_NUM_THREADS,
    OPENBLAS_NUM_THREADS and MKL_NUM_THREADS to 1 in it, which every process spawned later would inherit)."""
    environment = dict(os.environ)
    try:
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as local:
            yield local
    finally:
        os.environ.clear()
        os.environ.update(environment)


def test_a_map_on_the_cluster_equals_the_map_of_the_process_pool(dask_cluster):
    robot, path = load_robot("orthoglide"), load_path("examples/rect.yaml")
    axes = {"x": np.linspace(-0.05, 0.05, 5), "phi": np.radians([0.0, 30.0, 60.0])}
    local = sweep(robot, path, axes, {"z": -0.03}, evaluation=EvaluatorSettings(workers=2))
    with cluster(dask_cluster.scheduler_address) as remote:
        assert remote is not None and remote.threads == 2
        distant = sweep(robot, path, axes, {"z": -0.03}, executor=remote.executor)
    np.testing.assert_array_equal(distant.value, local.value)
    np.testing.assert_array_equal(distant.feasible, local.feasible)


def test_a_front_on_the_cluster_equals_the_front_found_here(dask_cluster):
    robot, path = load_robot("orthoglide"), load_path("examples/rect.yaml")
    small = SearchSettings(population=16, max_generations=6)
    here = pareto_front(robot, path, ("energy", "transmission"), settings=small)
    with cluster(dask_cluster.scheduler_address) as remote:
        assert remote is not None
        there = pareto_front(robot, path, ("energy", "transmission"), settings=small, executor=remote.executor,
                             evaluation=EvaluatorSettings(workers=remote.threads))
    assert len(there.members) == len(here.members)
    for a, b in zip(there.members, here.members):
        np.testing.assert_array_equal(a.placement, b.placement)
        np.testing.assert_array_equal(a.values, b.values)


def test_the_scheduler_comes_from_the_option_else_the_environment(monkeypatch):
    monkeypatch.setenv("PLACEMENT_SCHEDULER", "tcp://10.1.2.3:8786")
    assert scheduler_address(None) == "tcp://10.1.2.3:8786"
    assert scheduler_address("tcp://other:8786") == "tcp://other:8786"
    monkeypatch.delenv("PLACEMENT_SCHEDULER")
    assert scheduler_address(None) is None


def test_an_unreachable_scheduler_is_a_clear_error(monkeypatch, capsys, tmp_path):
    monkeypatch.setattr("placement.evaluation.parallel.CONNECT_TIMEOUT_S", 1.0)
    assert main(["map", "--robot", "orthoglide", "--path", "examples/rect.yaml", "--grid", "x=-10:10:3",
                 "--out", str(tmp_path / "map"), "--scheduler", "tcp://127.0.0.1:9"]) == 2
    assert "cannot reach the Dask scheduler at 'tcp://127.0.0.1:9'" in capsys.readouterr().err


def test_placements_timed_optimally_on_the_cluster_equal_those_timed_here(dask_cluster):
    robot = load_robot("orthoglide")
    path = dataclasses.replace(load_path("examples/rect.yaml"), timing=Timing(mode="optimal"))
    placements = np.array([[0.0, 0.0, -0.03, 0.0, 0.0, 0.0], [0.04, -0.02, -0.1, 0.5, 0.0, 0.0],
                           [-0.06, 0.03, 0.0, -1.0, 0.0, 0.0]])
    objectives = ("energy", "cycle_time")
    here = Evaluator(robot, path, EvaluatorSettings(objective=objectives, workers=1)).evaluate(placements)
    with cluster(dask_cluster.scheduler_address) as remote:
        assert remote is not None
        there = Evaluator(robot, path, EvaluatorSettings(objective=objectives, workers=remote.threads),
                          remote.executor).evaluate(placements)
    np.testing.assert_array_equal(there.values, here.values)
    np.testing.assert_array_equal(there.margins, here.margins)
