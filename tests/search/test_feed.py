"""Energy against feed: the time per part follows the timing law, the tool never outruns the feed."""

import numpy as np
import pytest

from placement import EvaluatorSettings, load_path, load_robot
from placement.cli import main
from placement.search.feed import feed_study
from tests.support.paths import EXAMPLE

FEEDS = np.array([0.1, 0.3, 0.66, 0.9, 2.0])


def test_paper_timing_takes_length_over_feed_and_breaks_the_speed_limit_when_too_fast():
    path = load_path(EXAMPLE)
    study = feed_study(load_robot("orthoglide"), path, np.zeros(6), FEEDS, EvaluatorSettings(time_step_s=0.002))
    np.testing.assert_allclose(study.time_s, path.length_m / FEEDS, rtol=1e-12)
    np.testing.assert_allclose(study.top_speed_m_s, FEEDS, rtol=1e-12)
    assert study.feasible.tolist() == [True, True, True, True, False]  # the sliders' 1 m/s, at 2 m/s on 45° diagonals
    assert "speed" in study.binding[-1]
    assert set(study.speed_bound) == {"feed"}


def test_realistic_timing_never_outruns_the_feed_and_saturates(tmp_path):
    file = tmp_path / "rect.yaml"
    file.write_text(EXAMPLE.read_text().replace("mode: paper", "mode: realistic"))
    study = feed_study(load_robot("orthoglide"), load_path(file), np.zeros(6), FEEDS,
                       EvaluatorSettings(time_step_s=0.002))
    assert (study.top_speed_m_s <= FEEDS * (1 + 1e-9)).all()
    assert (np.diff(study.time_s) <= 1e-12).all()  # faster feeds never take longer
    assert study.top_speed_m_s[-1] < FEEDS[-1]  # 2 m/s is never reached on a 30 mm side at 10 m/s²
    # And it says why: the feed where it is reached, the sides' length where it is not.
    assert study.speed_bound[0] == "feed" and study.speed_bound[-1] == "length (short of the feed cap)"


@pytest.mark.parametrize("feeds", ["0:1:3", "0.1:1", "0.1:1:0", "a:b:c", "0.1:inf:3", "0.1:1e300:3"])
def test_bad_feed_ranges_exit_2(feeds, capsys):
    assert main(["feed", "--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=0", "--feeds", feeds]) == 2
    assert "--feeds:" in capsys.readouterr().err


def test_the_feed_command_prints_the_table_and_draws(tmp_path, capsys):
    png = tmp_path / "feed.png"
    assert main(["feed", "--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=0", "--feeds", "0.3:0.9:3",
                 "--time-step", "0.004", "--png", str(png)]) == 0
    out = capsys.readouterr().out
    assert "energy/part J" in out and out.count(" hold") == 3 and png.is_file()


def test_a_placement_where_no_feed_holds_exits_2(capsys):
    assert main(["feed", "--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=1000", "--feeds", "0.1:1:3",
                 "--time-step", "0.01"]) == 2
    assert "no feed keeps every limit at this placement (workspace (x max) at the first)" in capsys.readouterr().err
