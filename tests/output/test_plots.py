"""Figures: the labels of the feed and front plots, measured on the rendered figure, never overlap."""

from __future__ import annotations

import itertools

import numpy as np

from placement import load_robot
from placement.output.plots import feed_figure, front_figure
from placement.search.feed import FeedStudy
from placement.search.pareto import FrontMember, ParetoFront
from placement.search.space import default_space


def _label_boxes(figure):
    """Window extents of every text label on the figure's axes, and of their legends, once drawn."""
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    return ([[text.get_window_extent(renderer) for text in ax.texts] for ax in figure.axes],
            [ax.get_legend().get_window_extent(renderer) for ax in figure.axes])


def _assert_apart(boxes, legend):
    for first, second in itertools.combinations(boxes, 2):
        assert not first.overlaps(second), (first, second)
    assert not any(box.overlaps(legend) for box in boxes)


def test_the_speed_labels_of_a_feed_plateau_do_not_overlap():
    """Eleven feeds of a contour the timing law slows to 27-28 mm/s: the points crowd on a short stretch of the
    curve, where labels at a fixed offset covered one another."""
    feeds = np.linspace(0.03, 0.1, 11)
    reached = 0.027 + 0.001 * np.linspace(0, 1, 11) ** 2
    time = 0.24 / reached
    study = FeedStudy(feeds_m_s=feeds, top_speed_m_s=reached, speed_bound=("feed",) * 11, time_s=time,
                      energy_J=5.0 + 0.02 * time, feasible=np.arange(11) < 9, binding=("joint",) * 11)
    (boxes,), (legend,) = _label_boxes(feed_figure(study, "plateau"))
    assert len(boxes) == 11  # one speed label per point
    _assert_apart(boxes, legend)


def test_the_optima_labels_of_a_front_that_is_one_placement_do_not_overlap():
    """Objectives that do not conflict: the front is one member, both optima sit on it, and their labels (at one
    offset from one point before) were drawn on top of each other."""
    member = FrontMember(placement=np.zeros(6), values=np.array([4.77, 1.05]), recheck_values=np.array([4.77, 1.05]),
                         margin=0.1)
    front = ParetoFront(objectives=("energy", "transmission"), members=(member,),
                        optima={"energy": 4.77, "transmission": 1.05}, knee=None,
                        space=default_space(load_robot("orthoglide")), regeneration="clip", evaluations=100)
    (boxes,), (legend,) = _label_boxes(front_figure(front, "one placement"))
    assert len(boxes) == 2
    _assert_apart(boxes, legend)
