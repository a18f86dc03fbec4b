"""Guides of a long path's search: chords that stay on the path, and answers that are the exact model's."""

import dataclasses

import numpy as np
import pytest
from scipy.spatial import cKDTree

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings, denser
from placement.path.load import load_path
from placement.path.segments import Hold
from placement.search import coarse_guide as guide
from placement.search.optimize import SearchSettings, optimize_placement, search_sampling
from placement.search.space import default_space


def contour(tmp_path, count):
    """A smooth free-form closed contour of ``count`` points, about 90 x 80 mm, at 0.66 m/s under the paper law."""
    theta = np.linspace(0.0, 2 * np.pi, count, endpoint=False)
    radius = 40.0 * (1 + 0.15 * np.cos(3 * theta) + 0.08 * np.sin(5 * theta))
    file = tmp_path / f"contour{count}.yaml"
    file.write_text("units: mm\nfeed_m_s: 0.66\ntime_step_s: 0.001\nprocess_forces_N: {feed: 10, radial: 215, axial: 25}"
                    "\nshape:\n  type: polyline\n  closed: true\n  points:\n"
                    + "".join(f"    - [{r * np.cos(a):.6f}, {r * np.sin(a):.6f}]\n" for r, a in zip(radius, theta)))
    return load_path(file)


def distance_to_chords(points, chords):
    """(N,) distance of each point to the nearest of the chords (segments)."""
    start = np.array([c.start_m for c in chords])
    direction = np.array([c.end_m - c.start_m for c in chords])
    share = np.clip(np.einsum("nkj,kj->nk", points[:, None] - start, direction) / (direction**2).sum(axis=1), 0, 1)
    return np.linalg.norm(points[:, None] - (start + share[..., None] * direction), axis=2).min(axis=1)


def test_chords_stay_within_their_bound_of_the_points_they_skip(tmp_path):
    path = contour(tmp_path, 3000)
    path = dataclasses.replace(path, holds=(Hold(1000, 0.5),))
    longest, tolerance = path.length_m / 100, path.length_m / 10_000
    merged = guide.merge_lines(path, longest, tolerance)
    assert 100 <= len(merged.segments) < 300
    assert all(chord.length_m <= longest * (1 + 1e-12) for chord in merged.segments)
    vertices = np.array([segment.start_m for segment in path.segments])
    assert distance_to_chords(vertices, merged.segments).max() <= tolerance * (1 + 1e-12)
    # Consecutive chords join, from the first point to the last, and the hold stays at its point
    np.testing.assert_array_equal(merged.segments[0].start_m, path.segments[0].start_m)
    np.testing.assert_array_equal(merged.segments[-1].end_m, path.segments[-1].end_m)
    assert all(np.array_equal(a.end_m, b.start_m) for a, b in zip(merged.segments, merged.segments[1:]))
    (hold,) = merged.holds
    np.testing.assert_array_equal(merged.segments[hold.after - 1].end_m, path.segments[999].end_m)


def test_a_loop_back_to_its_start_is_never_one_chord(tmp_path):
    """A small hole's contour (a 0.5 mm circle of 40 sides) under a chord bound larger than the hole: merged into one
    chord, it would be a chord of no length, without direction, whose samples are NaN (the coarse guide of a CamBam
    program with 1 mm holes made every placement unevaluable)."""
    path = contour(tmp_path, 40)
    path = dataclasses.replace(path, segments=tuple(dataclasses.replace(s, start_m=s.start_m / 80, end_m=s.end_m / 80)
                                                    for s in path.segments))
    tolerance = 1.2e-3  # every point of the hole is within it of the start
    merged = guide.merge_lines(path, 0.01, tolerance)
    assert len(merged.segments) > 1 and min(chord.length_m for chord in merged.segments) > 0
    vertices = np.array([segment.start_m for segment in path.segments])
    assert distance_to_chords(vertices, merged.segments).max() <= tolerance * (1 + 1e-12)
    assert np.isfinite(merged.sample(1e-4).position_m).all()


def wave(tmp_path, radius_mm, count=40):
    """A row of half circles of ``radius_mm`` (G2, G3 in turn) whose ends lie on the X axis, as a G-code program."""
    arcs = "".join(f"G{2 + k % 2} X{2 * radius_mm * (k + 1):g} Y0 I{radius_mm:g} J0\n" for k in range(count))
    (tmp_path / "wave.nc").write_text(f"G21 G90\nG0 X0 Y0 Z0\nG1 F600\n{arcs}")
    (tmp_path / "wave.yaml").write_text("shape: {type: gcode, file: wave.nc}\n")
    return load_path(tmp_path / "wave.yaml")


def along(segments, count):
    """(N, 3) points along each segment (arcs included), ``count`` per segment, ends included."""
    return np.concatenate([s.point(np.linspace(0, s.length_m, count), np.ones(count), np.zeros(count))[0]
                           for s in segments])


def distance_to_path(guide_path, path):
    """(N,) distance of points along every segment of ``path`` to the guide: to its chords, and to its arcs (kept as
    they are) within their sampling's spacing (1e-6 m at most here)."""
    points = along(path.segments, 50)
    lines = [s for s in guide_path.segments if s.center_m is None]
    arcs = [s for s in guide_path.segments if s.center_m is not None]
    to_lines = distance_to_chords(points, lines) if lines else np.full(len(points), np.inf)
    if not arcs:
        return to_lines
    to_arcs = cKDTree(along(arcs, 4000)).query(points)[0]
    return np.minimum(to_lines, to_arcs)


@pytest.mark.parametrize("tolerance_mm, merges", [(0.5, False), (1.5, True)])
def test_arcs_are_merged_only_where_they_stay_within_the_bound(tmp_path, tolerance_mm, merges):
    """Half circles of 1 mm whose ends all lie on one line: a chord through their ends skips points 1 mm away (their
    sagittas), so under a 0.5 mm bound none is merged, and under 1.5 mm they are, every point of every arc within it."""
    path = wave(tmp_path, 1.0)
    merged = guide.merge_lines(path, 0.5, tolerance_mm * 1e-3)
    assert (len(merged.segments) < len(path.segments) / 4) == merges
    assert distance_to_path(merged, path).max() <= tolerance_mm * 1e-3 + 1e-6
    assert np.isfinite(merged.sample(1e-3).position_m).all()


def models(path):
    return guide.search_models(path, *search_sampling(path, EvaluatorSettings(), SearchSettings()))


def test_a_path_with_few_samples_needs_no_guide_and_one_with_many_gets_one(tmp_path):
    few = models(contour(tmp_path, 400))  # 800 samples, each segment on its own under the paper law
    assert not few.guided and few.polish_path is few.coarse_path is not None
    many = models(contour(tmp_path, 1000))  # 2,000 samples, even at the global search's coarse step
    assert many.guided and many.coarse_scale == 1.0  # a smooth contour: both guides are chords
    assert len(many.coarse_path.sample(many.coarse.time_step_s)) <= guide.COARSE_THRESHOLD
    assert 200 < len(many.polish_path.segments) <= 1000 + len(guide.extreme_directions(guide.POLISH_HORIZONTAL))
    zigzag = models(raster(tmp_path, passes=600))  # 1,200 lines no chord merges: the global guide is moments
    extremes = len(zigzag.coarse_path.segments) - guide.GLOBAL_MOMENTS
    assert zigzag.guided and 2 <= extremes <= len(guide.extreme_directions(guide.GLOBAL_HORIZONTAL))
    assert len(zigzag.coarse_path.sample(zigzag.coarse.time_step_s)) == 2 * len(zigzag.coarse_path.segments)


@pytest.fixture(scope="module")
def guided(tmp_path_factory):
    """A guided search of a 1,500-point contour (3,000 samples), the guides' thresholds lowered to make it one."""
    from placement import load_robot

    with pytest.MonkeyPatch.context() as patch:  # undone even when the search fails
        patch.setattr(guide, "GUIDE_THRESHOLD", 1_000)
        patch.setattr(guide, "POLISH_SEGMENTS", 150)
        robot = load_robot("orthoglide")
        path = contour(tmp_path_factory.mktemp("guide"), 1500)
        space = default_space(robot, free=("x", "y", "z"))
        result = optimize_placement(robot, path, space=space, evaluation=EvaluatorSettings(),
                                    settings=SearchSettings(population=16, max_generations=6, worst=False))
    return robot, path, (result.guide.polish_path, result.guide.polish), result


def test_the_guided_answer_is_the_exact_models_at_its_placement(guided):
    robot, path, polish, result = guided
    optimum = result.best
    placement = optimum.detail.placement
    exact = Evaluator(robot, path)
    assert optimum.detail.value == exact.detail(placement).value
    assert len(optimum.detail.samples) == len(path.sample()) == 3000
    assert optimum.recheck_value == denser(exact, 4).recheck(placement[None], exact).value[0]
    model, settings = polish
    assert len(model.segments) < 300 + len(guide.extreme_directions(guide.POLISH_HORIZONTAL)) < len(path.segments)
    assert optimum.guide_value == Evaluator(robot, model, settings).evaluate(placement[None]).value[0]
    # The chords of a smooth contour cost about what its points do: the gap reported is small and measured
    assert abs(optimum.guide_gap) < 0.01
    # The global search's guide of a smooth contour is its chords too, as close (moments are for a raster's zigzags)
    coarse = Evaluator(robot, result.guide.coarse_path, result.guide.coarse).evaluate(placement[None]).value[0]
    assert result.guide.coarse_scale == 1.0 and abs(coarse / optimum.detail.value - 1) < 0.01


def raster(tmp_path, passes=60):
    """A CAM raster (as CAMotics' tiger is made): passes 60 mm along X at F300, each followed by a 0.5 mm step
    along Y at F150, at a depth, as a G-code program: a zigzag no chord can merge."""
    moves = "".join(f"G1 X{60 * ((k + 1) % 2)} F300\nG1 Y{0.5 * (k + 1):g} F150\n" for k in range(passes))
    (tmp_path / "raster.nc").write_text(f"G21 G90\nG0 X0 Y0 Z1\nG1 Z-2 F150\n{moves}")
    return load_path(tmp_path / "raster.nc")


def moments_energy(robot, path, count, placements, rng):
    """The moments guide's energy at ``placements``, times the moving time each piece stands for over its own
    (the path's duration from its own samples, which have no hold), and the guide."""
    piece_s = path.time_step_s
    moments = guide.sampled_moments(path, count, piece_s, rng)
    settings = EvaluatorSettings(time_step_s=piece_s * (1 + 1e-6))
    duration_s = float(np.ptp(path.sample().t_s))
    value = Evaluator(robot, moments, settings).evaluate(placements).value
    return value * duration_s / (count * piece_s), moments, settings


@pytest.fixture(scope="module")
def raster_case(tmp_path_factory):
    from placement import load_robot

    robot = load_robot("orthoglide")
    path = raster(tmp_path_factory.mktemp("raster"))
    space = default_space(robot, half_turn=path.half_turn_symmetric())
    points = space.full(np.random.default_rng(3).uniform(space.lower, space.upper, (60, len(space.free))))
    exact = Evaluator(robot, path).evaluate(points)
    placements = points[np.isfinite(exact.value)][:8]
    assert len(placements) == 8
    return robot, path, placements, exact.value[np.isfinite(exact.value)][:8]


def test_the_moments_are_pieces_of_the_path_at_its_own_speed_and_as_long_in_time(raster_case):
    """Each piece starts and ends on the path's line it was drawn on (or that line continued by less than its own
    length, where the line is shorter), runs at that line's feed, and lasts one time step."""
    robot, path, placements, exact = raster_case
    count = 200
    _, moments, settings = moments_energy(robot, path, count, placements[:1], np.random.default_rng(0))
    assert len(moments.segments) == count and not moments.holds
    lines = np.array([[s.start_m, s.end_m] for s in path.segments])
    for piece in moments.segments:
        direction = piece.end_m - piece.start_m
        # the path's line that contains the piece's ends: collinear, same direction of travel
        along = [k for k, (a, b) in enumerate(lines) if np.linalg.norm(np.cross(b - a, piece.start_m - a)) < 1e-12
                 and np.linalg.norm(np.cross(b - a, piece.end_m - a)) < 1e-12 and (b - a) @ direction > 0]
        assert along, piece
        segment = path.segments[along[0]]
        assert piece.feed_ratio == segment.feed_ratio
        assert piece.length_m / path.speed_m_s(piece) == pytest.approx(path.time_step_s, rel=1e-9)
    samples = moments.sample(settings.time_step_s)
    assert len(samples) == 2 * count


def test_the_guides_reach_as_far_as_the_path_in_the_directions_limits_bind(raster_case):
    """The workspace box binds where the path reaches farthest: along each of the 26 directions of a cube's faces,
    edges and corners, and each degree of the path's plane (which a turn phi brings onto the box's sides), the guides'
    samples reach the path's own farthest sample (their extremes' pieces), which the moments alone miss; their
    length, EXTREME_SHARE of a moment's, adds about that share each to the objective."""
    robot, path, placements, exact = raster_case
    models = guide.search_models(path, *search_sampling(path, EvaluatorSettings(), SearchSettings()))
    assert not models.guided  # below the thresholds: build the global guide as a long path's is built
    piece_s = path.time_step_s
    moments = guide.sampled_moments(path, guide.GLOBAL_MOMENTS, piece_s, np.random.default_rng(0))
    directions = guide.extreme_directions(guide.POLISH_HORIZONTAL)
    extended = guide.with_extremes(moments, path, directions)
    own = path.sample().position_m
    reach = [guide_path.sample(piece_s * (1 + 1e-6)).position_m for guide_path in (moments, extended)]
    np.testing.assert_allclose((reach[1] @ directions.T).max(axis=0), (own @ directions.T).max(axis=0),
                               atol=guide.EXTREME_SHORTFALL_M)
    assert ((reach[0] @ directions.T).max(axis=0) < (own @ directions.T).max(axis=0) - 1e-4).any()
    # the polish's chords too, which may cut the path's corners by up to their bound (not this raster's)
    chords = guide.merge_lines(path, path.length_m / 10, path.length_m / 1000)
    extended_chords = guide.with_extremes(chords, path, directions)
    reach_chords = [c.sample(piece_s).position_m @ directions.T for c in (chords, extended_chords)]
    np.testing.assert_allclose(reach_chords[1].max(axis=0), (own @ directions.T).max(axis=0),
                               atol=guide.EXTREME_SHORTFALL_M)
    settings = EvaluatorSettings(time_step_s=piece_s * (1 + 1e-6))
    with_them, without = (Evaluator(robot, p, settings).evaluate(placements).value for p in (extended, moments))
    added = len(extended.segments) - len(moments.segments)
    # each extreme piece is EXTREME_SHARE of a moment's length, at half its feed at the slowest (F150 of F300)
    assert np.abs(with_them / without - 1).max() < 2 * added * guide.EXTREME_SHARE / len(moments.segments)


def test_the_moments_guide_estimates_the_exact_energy_as_a_quadrature_in_time(raster_case):
    """The power at a sample of a paper-timed path depends on where the tool is and how it moves there: the moments,
    drawn uniformly in time, estimate the energy as a stratified quadrature whose error falls with their number;
    their ranking of placements is the exact one. A guide drawn uniformly over segments instead would give the 0.5 mm
    steps, 1/121 of the time, half the weight."""
    robot, path, placements, exact = raster_case
    errors = []
    for count in (64, 1024):
        estimate, *_ = moments_energy(robot, path, count, placements, np.random.default_rng(0))
        errors.append(np.abs(estimate / exact - 1).max())
        assert (np.argsort(estimate) == np.argsort(exact)).all() or count == 64
    assert errors[1] < 0.002 and errors[1] < errors[0]
