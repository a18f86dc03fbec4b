"""
Energy per part against feed
============================

How much does a faster feed cost? The groove at the isotropic point, timed by the realistic law (the tool
stops at each corner), at feeds from 0.1 to 1 m/s (``placement.search.feed.feed_study``, what
``placement feed`` runs). Slow, the motors hold the sliders against gravity and the cutting force for
longer; fast, the Joule losses of acceleration grow.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import placement
from placement.output.plots import feed_figure
from placement.search.feed import feed_study
from placement.timing.rules import override_timing

try:
    EXAMPLES = Path(__file__).resolve().parents[1]  # examples/, whatever the working folder
except NameError:  # run by the documentation's build, in examples/gallery/ without __file__
    EXAMPLES = Path.cwd().parent

robot = placement.load_robot("orthoglide")
path = placement.load_path(EXAMPLES / "rect.yaml")
realistic = override_timing(path, "realistic")  # what --timing realistic does
study = feed_study(robot, realistic, np.zeros(6), np.linspace(0.1, 1.0, 10))

cheapest = int(np.nanargmin(study.energy_J))
for feed, time_s, energy in zip(study.feeds_m_s, study.time_s, study.energy_J):
    print(f"feed {feed:.1f} m/s: {time_s:.3f} s and {energy:.2f} J a part")
print(f"least energy a part at {study.feeds_m_s[cheapest]:.1f} m/s")
feed_figure(study, "rectangle 30 x 60 mm at O_b, realistic timing")
plt.show()
