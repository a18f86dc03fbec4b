"""Basins: the search keeps the distinct local optima it finds, and its best does not depend on the seed."""

import numpy as np
import pytest

from placement.evaluation.evaluator import EvaluatorSettings
from placement.evaluation.results import Evaluation
from placement.output.report import basins_json, format_result
from placement.path import load_path
from placement.placing.transform import VARIABLES
from placement.search.basins import Basin, basin_starts, distinct, flipped_branches, unresolved
from placement.search.optimize import SearchSettings, _search, optimize_placement
from placement.search.space import PlacementSpace
from tests.support.paths import EXAMPLE, EXAMPLES

SEEDS = (0, 1, 8)  # on the groove, seeds 0 and 1 of the search before basins stopped in the 0° basin; 8 on a kink
# of its valley, 2.3e-6 above the best, before the polish went on across kinks (placement.search.kinks)


def _space() -> PlacementSpace:
    """x in [-1, 1] and a periodic phi in [-90°, 90°)."""
    return PlacementSpace(free=("x", "phi"), lower=np.array([-1.0, -np.pi / 2]), upper=np.array([1.0, np.pi / 2]),
                          fixed=np.zeros(6), periods=np.array([0.0, np.pi]))


def test_each_visited_region_gives_its_best_point_as_a_start_across_the_periodic_edge():
    space = _space()
    rng = np.random.default_rng(0)
    points = np.column_stack([rng.uniform(-1, 1, 400), rng.uniform(-np.pi / 2, np.pi / 2, 400)])
    # Two basins: phi near 0 and phi near ±90° (the same basin across the edge), the second one lower.
    turn = np.minimum(np.abs(points[:, 1]), np.pi / 2 - np.abs(points[:, 1]))
    signed = points[:, 0] ** 2 + np.where(np.abs(points[:, 1]) < np.pi / 4, turn**2 + 0.1, turn**2)
    starts = basin_starts(points, signed, space, count=2)
    assert len(starts) == 2
    assert np.pi / 2 - abs(starts[0, 1]) < 0.2 and abs(starts[1, 1]) < 0.2  # the lower basin first
    # A point across the edge from the best one (phi = -89° against 89°) is the same region: not a start.
    edge = np.array([[0.0, np.radians(89.0)], [0.0, np.radians(-89.0)], [0.0, 0.0]])
    assert len(basin_starts(edge, np.array([0.0, 0.01, 0.5]), space, count=3)) == 2


def test_polished_optima_closer_than_the_radius_are_one_basin():
    space = _space()
    optima = [np.array([0.0, np.radians(89.9)]), np.array([0.001, np.radians(-89.9)]), np.array([0.0, 0.0])]
    assert distinct(optima, [1.0, 0.9, 2.0], space, radius=0.02) == [1, 2]


def test_a_basin_is_unresolved_when_closer_than_the_denser_sampling_moves_either():
    basin = Basin(placement=np.zeros(6), value=10.02, recheck_value=10.0, holds=True)
    assert unresolved(10.0, 10.001, basin)  # 0.02 apart, the basin's own sampling gap 0.02
    assert not unresolved(10.0, 10.001, Basin(np.zeros(6), 10.05, 10.051, True))


@pytest.fixture(scope="module")
def groove():
    """The paper's groove (Orthoglide, examples/rect.yaml) searched at the default budget with three seeds."""
    from placement import load_robot

    robot = load_robot("orthoglide")
    path = load_path(EXAMPLE)
    settings = EvaluatorSettings(threads=1, workers=1)
    results = [optimize_placement(robot, path, evaluation=settings, settings=SearchSettings(seed=seed, worst=False))
               for seed in SEEDS]
    return robot, results


@pytest.mark.slow  # three searches: about 30 s on an idle 2-core machine
def test_the_best_energy_does_not_depend_on_the_seed(groove):
    _, results = groove
    energies = np.array([result.best.detail.value for result in results])
    # Seeds 0 and 1 end on one lowest point of the crease, seed 8 on another, 0.5 mm away and 2e-8 apart before
    # printing; the search of the printed lattice ends on the best printed point near each: 4.767175949 and
    # 4.767175258 J, 1.45e-7 apart (their cells' best corners were 3.3e-7 apart).
    assert np.ptp(energies) <= 2e-7 * energies.min()
    # Each finds the rectangle turned by about 90° (4.7672 J), and lists the one turned by about 0° (4.7683 J)
    # as a basin of its own, resolved by the 4x denser re-check.
    for result in results:
        assert abs(abs(np.degrees(result.best.detail.placement[3])) - 89.6) < 0.5
        assert result.best.holds
        zero = [b for b in result.best.basins if abs(np.degrees(b.placement[3])) < 5]
        assert zero and zero[0].holds
        assert 1e-4 < (zero[0].value - result.best.detail.value) / result.best.detail.value < 1e-3
        assert not result.best.unresolved


@pytest.mark.slow
def test_the_report_and_json_list_the_other_basins(groove):
    robot, results = groove
    text = format_result(robot, results[0])
    assert "other basins within 5 % (distinct local optima, as printed):" in text
    entries = basins_json(results[0].best)
    assert entries and {"placement", "energy_J", "recheck_value", "holds", "within_recheck_resolution"} <= set(entries[0])
    assert entries[0]["energy_J"] == pytest.approx(results[0].best.basins[0].value)
    assert entries[0]["relative_difference"] > 0


def _three_seeds(robot_name: str, path_file: str, cell_file: str | None, seeds: tuple[int, ...]) -> np.ndarray:
    """The best energies of a search at the default budget with each seed."""
    from placement import equip, load_cell, load_robot

    robot = load_robot(robot_name)
    if cell_file is not None:
        robot = equip(robot, load_cell(EXAMPLES / cell_file))
    path = load_path(EXAMPLES / path_file)
    settings = EvaluatorSettings(threads=1, workers=1)
    results = [optimize_placement(robot, path, evaluation=settings, settings=SearchSettings(seed=seed, worst=False))
               for seed in seeds]
    assert all(result.best is not None and result.best.holds for result in results)
    return np.array([result.best.detail.value for result in results])


@pytest.mark.slow  # three searches of the UR5: about 40 s on an idle 2-core machine
def test_the_ur5s_best_energy_does_not_depend_on_the_seed():
    """The UR5's best lies on a valley of equal energy (the rectangle turned about the base's vertical axis), on its
    tilt's bound; each seed ends somewhere else along it, and the best printed point near each is within 6.3e-8 of the
    others' (4.0e-7 over seeds 0-9 before the printed lattice was searched)."""
    energies = _three_seeds("ur5", "rect.yaml", None, (0, 1, 2))
    assert np.ptp(energies) <= 1e-7 * energies.min()


@pytest.mark.slow  # three searches of the pocket in its cell: about 40 s on an idle 2-core machine
def test_the_pockets_best_energy_does_not_depend_on_the_seed():
    """Seeds 0, 4 and 6 stopped 2.7 % above the best (66.7437 J) before the global search's first population took the
    best half of a seed-free scan and the polish started from regions that break a limit on the finer sampling. Its
    optimum lies on a limit: the corners of its cell on the limit's feasible side were reported, and which lay nearest
    the limit changed with the cell (seed 9 1.4e-6 below seeds 0-8); the search of the printed lattice reports the same
    printed point for every seed."""
    energies = _three_seeds("orthoglide", "pocket.yaml", "cell_orthoglide.yaml", (0, 4, 6))
    assert np.ptp(energies) == 0.0


class _TwoBranches:
    """A stand-in for the Evaluator of a redundant arm (free y and one knot ``j@0``): a wide basin at y = 0.3 on the
    knot's positive branch (objective 1) and, at its mirror image (y = -0.3, the knot negated), a narrow one 10 %
    lower whose attraction region is 0.02 across in each variable: a global search seldom visits it."""

    settings = EvaluatorSettings()

    def evaluate(self, placements: np.ndarray) -> Evaluation:
        y, knot = placements[:, 1], placements[:, 6]
        wide = 1.0 + (y - 0.3) ** 2 + (knot - 1.0) ** 2
        narrow = 0.9 + ((y + 0.3) ** 2 + (knot + 1.0) ** 2) / 0.01**2
        return Evaluation(placements=placements, objectives=("energy",), values=np.minimum(wide, narrow)[:, None],
                          margins=np.ones((len(placements), 1)), limits=("none",),
                          reachable=np.ones(len(placements), dtype=bool))


def test_the_other_branch_of_a_redundant_arm_is_polished_though_rarely_visited():
    """The best of the wide basin, flipped onto the other branch (its knot and y negated), starts a polish in the
    narrow one: every seed ends there (the search before flipped branches ended in the wide basin on every seed)."""
    space = PlacementSpace(free=("y", "j@0"), lower=np.array([-1.0, -2.0]), upper=np.array([1.0, 2.0]),
                           fixed=np.zeros(7), names=(*VARIABLES, "j@0"))
    model = _TwoBranches()
    for seed in range(5):
        candidates, problem, optima = _search(model, model, space, 1.0, SearchSettings(seed=seed), None)
        assert problem.lookup(candidates[0])[0][0] == pytest.approx(0.9, abs=1e-6)
        assert np.allclose(candidates[0], [-0.3, -1.0], atol=1e-3)
        assert any(abs(problem.lookup(o)[0][0] - 1.0) < 1e-6 for o in optima)  # the wide basin, kept as a basin


def test_branches_flip_only_with_a_free_knot():
    with_knot = PlacementSpace(free=("y", "phi", "theta", "j@0"), lower=-np.ones(4), upper=np.ones(4),
                               fixed=np.zeros(7), names=(*VARIABLES, "j@0"))
    images = flipped_branches(np.array([0.2, 0.3, 0.4, 0.5]), with_knot)
    assert np.allclose(images, [[0.2, 0.3, 0.4, -0.5], [-0.2, -0.3, 0.4, -0.5]])  # theta: a turn about y, kept
    assert len(flipped_branches(np.array([0.0, 0.3]), _space())) == 0


class _TwoBasins:
    """A stand-in for the Evaluator over (x, phi): a basin at x = 0.5 (objective 0) and one at x = -0.5 (objective
    0.5), no limit."""

    settings = EvaluatorSettings()

    def evaluate(self, placements: np.ndarray) -> Evaluation:
        x, phi = placements[:, 0], placements[:, 3]
        value = np.minimum((x - 0.5) ** 2, 0.5 + (x + 0.5) ** 2) + 50 * phi**2
        return Evaluation(placements=placements, objectives=("energy",), values=value[:, None],
                          margins=np.ones((len(placements), 1)), limits=("none",),
                          reachable=np.ones(len(placements), dtype=bool))


def test_the_candidates_come_best_first_so_a_best_that_fails_once_printed_gives_way_to_its_own_basin():
    """The report takes the first candidate that keeps every limit once printed: after the best, the next best (the
    global search's final population around it, 81.04 J on the paper's 80 x 160 worst), not the next basin's optimum
    (the search before took the cube's top corner, 75.35 J, where the best at Q- failed once printed)."""
    space = PlacementSpace(free=("x", "phi"), lower=np.array([-1.0, -1.0]), upper=np.array([1.0, 1.0]),
                           fixed=np.zeros(6))
    model = _TwoBasins()  # a short global search, its visited points all among the starts' pool (basins.START_POOL)
    candidates, problem, optima = _search(model, model, space, 1.0, SearchSettings(seed=0, max_generations=10), None)
    values = problem.lookup(np.array(candidates))[0]
    assert len(optima) == 2 and np.all(np.diff(values) >= 0)
    assert abs(candidates[1][0] - 0.5) < 0.1 and values[1] < 0.5


@pytest.mark.slow  # two searches of the Orthoglide, one direction each: about 10 s
def test_the_tables_realistic_worst_stays_at_q_minus_when_its_optimum_fails_once_printed(tmp_path):
    """The paper's Table, realistic timing law, 80 x 160 mm: the most-energy placement is against the cube's three
    faces at Q- (81.06 J). On seeds 0 and 4 its polished optimum there fails the workspace limit once printed, and the
    search reported the next basin, at the cube's top corner (75.35 J, 7 % less); it now reports the best point of
    its own basin that keeps every limit once printed."""
    from placement import load_robot

    text = EXAMPLE.read_text().replace("width: 30, length: 60", "width: 80, length: 160")
    (tmp_path / "rect.yaml").write_text(text.replace("mode: paper", "mode: realistic"))
    robot, path = load_robot("orthoglide"), load_path(tmp_path / "rect.yaml")
    for seed in (0, 4):
        worst = optimize_placement(robot, path, evaluation=EvaluatorSettings(time_step_s=0.002, threads=1, workers=1),
                                   settings=SearchSettings(seed=seed, best=False)).worst
        assert worst.holds and worst.detail.value > 81.0
        assert worst.detail.placement[2] == pytest.approx(-0.12679, abs=1e-3)  # z at the bottom face, not the top (73 mm)
