"""The workspace estimated from what the actuators reach (placement/workshop/reach.py), against analytic reach.

The test five-bar exported in Gepetto's format (tests/data/gepetto_fivebar, the geometry of
tests/support/fivebar_analytic.py), its actuators given ranges of ±0.3, ±0.6 and ±1.2 rad in the
URDF, goes through ``assemble --write``; the built-in Delta's box comes from the same rule, against
Williams' closed form (tests/support/delta_analytic.py).
"""

import shutil
import warnings

import numpy as np
import pytest
import yaml

from placement import load_robot
from placement.__main__ import main
from placement.workshop.catalog import sidecar_path
from placement.workshop.gepetto import EstimatesWarning, estimated_workspace
from tests.support.delta_analytic import williams_inverse_kinematics
from tests.support.fivebar_analytic import reached_on_branch
from tests.support.paths import DATA

RANGES_RAD = (0.3, 0.6, 1.2)  # each actuator's range either side of the exported pose
RASTER_M = 0.002  # step of the raster on which the largest box inside the analytic reach is found
SHARE = 0.8  # the estimated box's area, at least, as a share of that largest box's


def _limited_fivebar(folder, range_rad: float) -> tuple[np.ndarray, np.ndarray]:
    """The x-y corners (m) of the box ``assemble --write`` estimates for the five-bar with actuators of ±range."""
    copy = folder / f"fivebar_{range_rad}"
    shutil.copytree(DATA / "gepetto_fivebar", copy)
    urdf = copy / "robot.urdf"
    text = urdf.read_text()
    for joint in ("mot1", "mot2"):
        start = text.index(f'<joint name="{joint}"')
        at = text.index('<limit effort="10" velocity="10"/>', start)
        text = text[:at] + f'<limit effort="10" velocity="10" lower="{-range_rad}" upper="{range_rad}"/>' + text[at + 34:]
    urdf.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EstimatesWarning)
        assert main(["assemble", str(copy), "--write"]) == 0
    robot = load_robot(copy)
    assert [(a.position_min, a.position_max) for a in robot.actuators] == [(-range_rad, range_rad)] * 2
    box = yaml.safe_load(sidecar_path(copy).read_text())["workspace"]
    assert box["min_m"][2] == -0.001 and box["max_m"][2] == 0.001  # 1 mm either side of the plane it moves in
    return np.array(box["min_m"][:2]), np.array(box["max_m"][:2])


@pytest.fixture(scope="module")
def boxes(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ranges")
    return {range_rad: _limited_fivebar(folder, range_rad) for range_rad in RANGES_RAD}


def largest_inside_area(range_rad: float) -> float:
    """Area (m²) of the largest axis-aligned rectangle of raster cells all inside the analytic reach (an upper
    bound, within a raster step along its sides, of the largest box inside it)."""
    x, y = np.meshgrid(np.arange(-0.45, 0.45, RASTER_M), np.arange(0.0, 0.45, RASTER_M), indexing="ij")
    inside = reached_on_branch(x, y, range_rad)
    heights, best = np.zeros(inside.shape[1], int), 0
    for row in inside:  # the largest rectangle under the histogram of the columns' runs ending at this row
        heights = np.where(row, heights + 1, 0)
        stack: list[int] = []
        for i, height in enumerate([*heights, 0]):
            while stack and heights[stack[-1]] >= height:
                top = heights[stack.pop()]
                best = max(best, top * (i - (stack[-1] + 1 if stack else 0)))
            stack.append(i) if i < len(heights) else None
    return best * RASTER_M**2


@pytest.mark.parametrize("range_rad", RANGES_RAD)
def test_the_box_lies_in_the_analytic_reach_and_fills_most_of_it(boxes, range_rad):
    """Every point of the box is reached on the branch (arms neither stretched nor folded, the assembly mode
    kept, the actuators in range), and its area is most of the largest box the analytic reach holds."""
    low, high = boxes[range_rad]
    x, y = np.meshgrid(np.linspace(low[0], high[0], 61), np.linspace(low[1], high[1], 61))
    assert reached_on_branch(x, y, range_rad).all()
    area, largest = float(np.prod(high - low)), largest_inside_area(range_rad)
    assert area >= SHARE * largest, (area, largest)


def test_the_box_grows_with_the_actuators_ranges(boxes):
    """Doubling the actuators' ranges lets the tip reach farther: the box's area at least doubles, as the largest
    box inside the analytic reach grows 3.3 and 2.5 times (from 7 844 to 26 264 and 64 960 mm²)."""
    areas = [float(np.prod(boxes[r][1] - boxes[r][0])) for r in RANGES_RAD]
    assert areas[1] >= 2 * areas[0] and areas[2] >= 2 * areas[1], areas


def test_the_delta_box_lies_in_williams_reach():
    """The Delta's three actuators (arms in [-0.9, 1.5] rad) give a box of three directions, every point of which
    Williams' closed form reaches with the knees out and the arms in range, larger than the IRB 340's stated
    working box (the sidecar's, 0.8 x 0.8 x 0.25 m)."""
    robot = load_robot("delta")
    document = estimated_workspace(robot, {})
    low, high = np.array(document["workspace"]["min_m"]), np.array(document["workspace"]["max_m"])
    points = np.stack(np.meshgrid(*(np.linspace(a, b, 15) for a, b in zip(low, high)), indexing="ij"), -1).reshape(-1, 3)
    still = np.zeros_like(points)
    theta = williams_inverse_kinematics(points, still, still)[0]
    assert np.isfinite(theta).all() and (theta >= -0.9).all() and (theta <= 1.5).all()
    stated = robot.workspace
    assert stated is not None
    assert np.prod(high - low) >= np.prod(np.subtract(stated.max_m, stated.min_m)), (low, high)
