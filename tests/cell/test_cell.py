"""The robot cell: cell files, the tool body's dynamics, and collision distances proven by geometry."""

from __future__ import annotations

import pickle
import re
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
import pytest
import yaml

from placement import load_robot
from placement.cell.cell_file import load_cell
from placement.cell.exceptions import CellFileError
from placement.collision.distances import CollisionScene
from placement.robot.exceptions import RobotFileError
from placement.robot.tool import mount_tool, pose_placement, tool_inertia
from tests.support.paths import ROOT
from tests.support.robot_copies import edited_copy, with_gripper

UR5_CELL = ROOT / "examples" / "cell_ur5_table_wall.yaml"
ORTHOGLIDE_CELL = ROOT / "examples" / "cell_orthoglide.yaml"
TOLERANCE_M = 1e-6  # GJK and EPA converge to about this (m)


@pytest.fixture(scope="module")
def ur5():
    return load_robot("ur5")


def write_cell(folder: Path, document: dict, name: str = "cell.yaml") -> Path:
    path = folder / name
    path.write_text(yaml.safe_dump(document, sort_keys=False), encoding="utf-8")
    return path


def tool_shape_placement(robot, tool) -> pin.SE3:
    """World placement of the tool's collision shape at the reference configuration, by Pinocchio alone."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    frame = robot.model.getFrameId(tool.frame or robot.mount_frame)
    return data.oMf[frame] * pose_placement(tool) * pose_placement(tool.collision)


def distance_of(scene: CollisionScene, first: str, second: str, q: np.ndarray, threshold_m=None) -> np.ndarray:
    return scene.distances(q, threshold_m)[:, scene.pairs.index((first, second))]


# ---------------------------------------------------------------- analytic distances of primitive shapes


def _tool(collision: dict) -> dict:
    return {"name": "probe", "mass_kg": 1.0, "inertia_kg_m2": [1e-3, 1e-3, 1e-3, 0, 0, 0], "collision": collision}


def _world_body(placement: pin.SE3, offset_m, shape: dict) -> dict:
    """A cell body at ``offset_m`` (in the axes of ``placement``) from ``placement``'s origin, aligned with it."""
    xyz = placement.translation + placement.rotation @ np.asarray(offset_m, dtype=float)
    return {**shape, "xyz_m": xyz.tolist(), "rpy_rad": pin.rpy.matrixToRpy(placement.rotation).tolist()}


@pytest.mark.parametrize("gap_m", [0.2, 0.03, -0.02])
def test_sphere_sphere_distance_and_witnesses_are_analytic(ur5, tmp_path, gap_m):
    tool = _tool({"type": "sphere", "radius_m": 0.05, "xyz_m": [0.0, 0.0, 0.1]})
    cell = load_cell(write_cell(tmp_path, {"tool": tool}))
    centre = tool_shape_placement(ur5, cell.tool).translation
    direction = np.array([0.6, -0.48, 0.64])
    other = centre + (0.05 + 0.08 + gap_m) * direction
    path = write_cell(tmp_path, {"tool": tool, "obstacles": {"ball": {"type": "sphere", "radius_m": 0.08,
                                                                      "xyz_m": other.tolist()}}})
    scene = CollisionScene(ur5, load_cell(path))
    assert distance_of(scene, "probe", "ball", ur5.reference_q)[0] == pytest.approx(gap_m, abs=TOLERANCE_M)
    closest = scene.closest(ur5.reference_q)
    k = scene.pairs.index(("probe", "ball"))
    np.testing.assert_allclose(closest.first_m[k], centre + 0.05 * direction, atol=TOLERANCE_M)
    np.testing.assert_allclose(closest.second_m[k], other - 0.08 * direction, atol=TOLERANCE_M)
    assert closest.distance_m[k] == pytest.approx(gap_m, abs=TOLERANCE_M)


def _point_box_signed(point, half):
    """Signed distance from a point (box frame) to a box centred at the origin: negative inside."""
    outside = np.maximum(np.abs(point) - half, 0.0)
    return np.linalg.norm(outside) if outside.any() else -np.min(half - np.abs(point))


@pytest.mark.parametrize("offset", [[0.25, 0.1, -0.05], [0.0, 0.0, 0.17], [0.12, 0.02, 0.0], [0.05, -0.03, 0.02]])
def test_sphere_box_distance_is_analytic(ur5, tmp_path, offset):
    """A sphere on the tool against a rotated box: outside, touching a face, overlapping, centre inside."""
    radius, half = 0.04, np.array([0.1, 0.06, 0.14])
    box_rotation = pin.rpy.rpyToMatrix(0.3, -0.7, 1.1)
    tool = _tool({"type": "sphere", "radius_m": radius, "xyz_m": [0.0, 0.0, 0.1]})
    centre = tool_shape_placement(ur5, load_cell(write_cell(tmp_path, {"tool": tool})).tool).translation
    box_centre = centre - box_rotation @ np.asarray(offset)
    box = {"type": "box", "size_m": (2 * half).tolist(), "xyz_m": box_centre.tolist(),
           "rpy_rad": pin.rpy.matrixToRpy(box_rotation).tolist()}
    scene = CollisionScene(ur5, load_cell(write_cell(tmp_path, {"tool": tool, "obstacles": {"block": box}})))
    expected = _point_box_signed(np.asarray(offset), half) - radius
    assert distance_of(scene, "probe", "block", ur5.reference_q)[0] == pytest.approx(expected, abs=TOLERANCE_M)


@pytest.mark.parametrize("gap", [[0.1, 0.0, -0.05], [0.03, 0.04, -0.01], [-0.01, -0.05, -0.02], [-0.03, -0.02, -0.025]])
def test_box_box_distance_is_analytic(ur5, tmp_path, gap):
    """A box on the tool against a box aligned with it, ``gap`` apart along each axis (negative: overlapping):
    separated along one or two axes, or overlapping on all three (distance: minus the smallest overlap)."""
    half_tool, half_block = np.array([0.03, 0.04, 0.05]), np.array([0.1, 0.07, 0.06])
    tool = _tool({"type": "box", "size_m": (2 * half_tool).tolist(), "xyz_m": [0.0, 0.0, 0.1], "rpy_rad": [0.2, 0, 0]})
    placement = tool_shape_placement(ur5, load_cell(write_cell(tmp_path, {"tool": tool})).tool)
    offset = np.array([1.0, -1.0, 1.0]) * (half_tool + half_block + np.asarray(gap))
    block = _world_body(placement, offset, {"type": "box", "size_m": (2 * half_block).tolist()})
    scene = CollisionScene(ur5, load_cell(write_cell(tmp_path, {"tool": tool, "obstacles": {"block": block}})))
    separation = np.maximum(np.asarray(gap), 0.0)
    expected = np.linalg.norm(separation) if separation.any() else max(gap)
    assert distance_of(scene, "probe", "block", ur5.reference_q)[0] == pytest.approx(expected, abs=TOLERANCE_M)


def _cube_stl(path: Path, half: float) -> Path:
    """An ASCII STL of a cube of half edge ``half`` (m) centred at its origin."""
    corners = np.array([[x, y, z] for x in (-half, half) for y in (-half, half) for z in (-half, half)])
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    lines = ["solid cube"]
    for a, b, c, d in faces:
        for tri in ((a, b, c), (a, c, d)):
            lines += ["facet normal 0 0 0", "outer loop", *(f"vertex {' '.join(map(str, corners[i]))}" for i in tri),
                      "endloop", "endfacet"]
    path.write_text("\n".join([*lines, "endsolid cube"]) + "\n")
    return path


@pytest.mark.parametrize("gap_m", [0.05, -0.01])
def test_mesh_hulls_give_convex_distances_and_penetration(ur5, tmp_path, gap_m):
    """Two cube meshes (scaled) become convex hulls; coal gives their distance, negative when they overlap."""
    _cube_stl(tmp_path / "cube.stl", 0.5)
    tool = _tool({"type": "mesh", "file": "cube.stl", "scale": 0.06, "xyz_m": [0.0, 0.0, 0.1]})  # 60 mm cube
    placement = tool_shape_placement(ur5, load_cell(write_cell(tmp_path, {"tool": tool})).tool)
    block = _world_body(placement, [0.03 + 0.05 + gap_m, 0.0, 0.0],
                        {"type": "mesh", "file": "cube.stl", "scale": [0.1, 0.2, 0.3]})
    scene = CollisionScene(ur5, load_cell(write_cell(tmp_path, {"tool": tool, "obstacles": {"block": block}})))
    assert distance_of(scene, "probe", "block", ur5.reference_q)[0] == pytest.approx(gap_m, abs=TOLERANCE_M)
    assert any("convex hulls" in notice for notice in scene.notices)


# ---------------------------------------------------------------- a robot link against a box


def test_ur5_link_approaching_a_box_gives_the_analytic_distance(ur5, tmp_path):
    """The forearm swung down toward a large box: its distance to the box's top face is the lowest vertex of the
    link's mesh (a linear function's minimum over a convex hull is at a vertex), placed by Pinocchio."""
    top_z, rpy = 0.3, [0.0, 0.0, 0.4]
    box = {"type": "box", "size_m": [2.0, 2.0, 2.0], "xyz_m": [0.9, 0.0, top_z - 1.0], "rpy_rad": rpy}
    cell = load_cell(write_cell(tmp_path, {"margin_m": 0.0, "obstacles": {"floor": box}, "ignore": [
        ["base_link", "floor"], ["shoulder_link", "floor"]]}))
    scene = CollisionScene(ur5, cell)
    item = next(g for g in scene.geometry_model.geometryObjects if g.name.startswith("wrist_1_link"))
    vertices = np.array(coal.MeshLoader().load(item.meshPath, np.ones(3)).vertices())
    q = np.repeat(ur5.reference_q[None], 7, axis=0)
    q[:, 1] = np.linspace(-1.9, -0.6, 7)  # the shoulder lowers the arm toward the box
    data = ur5.model.createData()
    expected = []
    for row in q:
        pin.forwardKinematics(ur5.model, data, row)
        placement = data.oMi[item.parentJoint] * item.placement
        world = vertices @ placement.rotation.T + placement.translation
        expected.append(world[:, 2].min() - top_z)
    got = distance_of(scene, "wrist_1_link", "floor", q)
    assert np.diff(expected).max() < 0 and expected[0] > 0 > expected[-1]  # it approaches, then enters
    np.testing.assert_allclose(got, expected, atol=TOLERANCE_M)


# ---------------------------------------------------------------- the prefilter


def test_prefilter_never_changes_a_distance_below_the_threshold(ur5):
    scene = CollisionScene(ur5, load_cell(UR5_CELL))
    rng = np.random.default_rng(7)
    low = np.array([a.position_min for a in ur5.actuators])
    high = np.array([a.position_max for a in ur5.actuators])
    q = low + (high - low) * rng.random((150, ur5.model.nq))
    exact = scene.distances(q)
    bounds = scene._per_pair(scene._bounds(*scene._placed(q), np.inf))
    assert (bounds <= exact + 1e-9).all()  # overlapping pairs too
    for threshold in (0.0, 0.05, 0.2):
        filtered = scene.distances(q, threshold_m=threshold)
        below = exact <= threshold
        np.testing.assert_array_equal(filtered[below], exact[below])
        assert (filtered[~below] > threshold).all() and (filtered[~below] <= exact[~below] + 1e-9).all()  # GJK's rounding
        assert np.array_equal(filtered >= scene.required_m, exact >= scene.required_m) or threshold < 0.01
    assert (scene.distances(q, threshold_m=0.05) != exact).mean() > 0.5  # the bounds spare most pairs


def test_refined_bounds_stay_below_the_exact_distances_of_the_orthoglide_cell():
    """Boxes and cylinders against boxes: the projections' gaps are tight, never above coal's distances, and
    the prefiltered distances decide every clearance as the exact ones do."""
    robot = load_robot("orthoglide")
    scene = CollisionScene(robot, load_cell(ORTHOGLIDE_CELL))
    q = robot.reference_q + np.random.default_rng(3).uniform(-0.25, 0.25, (400, robot.model.nq))
    exact = scene.distances(q)
    bounds = scene._per_pair(scene._bounds(*scene._placed(q), np.inf))
    assert (bounds <= exact + 1e-9).all()  # face to face, a bound is the distance, to GJK's rounding
    assert np.median(exact - bounds) < 0.01  # tighter than the bounding spheres' (their median gap is about 4 cm)
    for threshold in (0.0, 0.056, 0.2):
        filtered = scene.distances(q, threshold_m=threshold)
        below = exact <= threshold
        np.testing.assert_allclose(filtered[below], exact[below], rtol=0, atol=1e-12)
        assert (filtered[~below] > threshold).all()
        if threshold >= scene.required_m.max():  # a threshold at least the clearance decides as the exact distances
            assert np.array_equal(filtered >= scene.required_m, exact >= scene.required_m)


def test_a_runs_smallest_distance_is_exact_and_its_other_distances_are_bounds_below_the_exact_ones():
    """Runs of configurations along straight lines in joint space (a path's samples): each pair's smallest
    distance over a run is coal's wherever it is within the threshold, though most exact distances are spared;
    a bound above a distance would spare the wrong ones (a looser one from the joints' motion too)."""
    robot = load_robot("orthoglide")
    scene = CollisionScene(robot, load_cell(ORTHOGLIDE_CELL))
    rng = np.random.default_rng(5)
    runs, run = 60, 40
    ends = robot.reference_q + rng.uniform(-0.25, 0.25, (runs, 2, robot.model.nq))
    share = np.linspace(0.0, 1.0, run)[None, :, None]
    q = (ends[:, :1] * (1 - share) + ends[:, 1:] * share).reshape(runs * run, -1)
    exact = scene.distances(q)
    smallest = exact.reshape(runs, run, -1).min(axis=1)
    for threshold in (0.0, 0.056, 0.2, np.inf):
        filtered = scene.distances(q, threshold_m=threshold, run=run)
        assert (filtered <= exact + 1e-9).all()  # lower bounds everywhere, to GJK's rounding
        least = filtered.reshape(runs, run, -1).min(axis=1)
        within = smallest <= threshold
        assert within.any() and (threshold == np.inf or not within.all())
        np.testing.assert_array_equal(least[within], smallest[within])
        assert (least[~within] > threshold).all()
    assert (scene.distances(q, threshold_m=0.056, run=run) != exact).mean() > 0.5  # most are spared
    with pytest.raises(ValueError, match="runs of 7"):
        scene.distances(q[:20], threshold_m=0.056, run=7)


def test_no_point_of_a_shape_moves_more_than_its_levers_allow():
    """Between two configurations, every point of a shape's bounding sphere moves by at most the sum of its joints'
    levers times their motion (Pinocchio's placements, on the Orthoglide's closed loop and the UR5's chain)."""
    for robot, cell in ((load_robot("orthoglide"), ORTHOGLIDE_CELL), (load_robot("ur5"), UR5_CELL)):
        scene = CollisionScene(robot, load_cell(cell))
        start, index, length = scene._levers
        _, centre, radius, _, _ = scene._enclosures
        data, geometry_data = robot.model.createData(), pin.GeometryData(scene.geometry_model)
        rng = np.random.default_rng(7)
        tight = 0.0
        for _ in range(40):
            ends = robot.reference_q + rng.uniform(-0.3, 0.3, (2, robot.model.nq))
            placed = []
            for q in ends:
                pin.updateGeometryPlacements(robot.model, data, scene.geometry_model, geometry_data, q)
                placed.append([(p.rotation, p.act(c)) for p, c in zip(geometry_data.oMg, centre)])
            for g, ((r0, c0), (r1, c1)) in enumerate(zip(*placed)):
                move = np.linalg.norm(c1 - c0) + np.linalg.norm(r1 - r0, 2) * radius[g]  # the most a point moves
                allowed = length[start[g]:start[g + 1]] @ np.abs(ends[1] - ends[0])[index[start[g]:start[g + 1]]]
                assert move <= allowed + 1e-12
                tight = max(tight, move / allowed if allowed else 0.0)
        assert tight > 0.5  # the levers are not loose everywhere


def test_along_a_path_few_exact_distances_settle_each_runs_smallest(monkeypatch):
    """Runs of small steps, as a path's samples: the bounds that an exact distance gives its neighbours (the bodies'
    moves, the gap along coal's normal) leave a few exact distances per pair and run (every value below the
    smallest found would take one without them: about 12 per pair and run here), and never rise above coal's."""
    robot = load_robot("orthoglide")
    scene = CollisionScene(robot, load_cell(ORTHOGLIDE_CELL))
    runs, run = 30, 60
    ends = robot.reference_q + np.random.default_rng(5).uniform(-0.1, 0.1, (runs, 2, robot.model.nq))
    share = np.linspace(0.0, 1.0, run)[None, :, None]
    q = (ends[:, :1] * (1 - share) + ends[:, 1:] * share).reshape(runs * run, -1)
    exact = scene.distances(q)
    smallest = exact.reshape(runs, run, -1).min(axis=1)
    calls = []
    compute = pin.computeDistance
    monkeypatch.setattr(pin, "computeDistance", lambda *args: calls.append(1) or compute(*args))
    filtered = scene.distances(q, threshold_m=0.2, run=run)
    within = smallest <= 0.2
    np.testing.assert_array_equal(filtered.reshape(runs, run, -1).min(axis=1)[within], smallest[within])
    assert (filtered <= exact + 1e-9).all()
    assert within.sum() > 500 and len(calls) < 6 * within.sum()


# ---------------------------------------------------------------- which pairs


def test_ur5_skips_adjacent_links_and_checks_the_tool_against_the_wrist(ur5):
    scene = CollisionScene(ur5, load_cell(UR5_CELL))
    chain = ["base_link", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link", "wrist_2_link",
             "wrist_3_link"]
    pairs = {frozenset(pair) for pair in scene.pairs}
    assert not scene.touching_at_reference
    for parent, child in zip(chain, chain[1:]):
        assert frozenset((parent, child)) not in pairs
    assert frozenset(("wrist_3_link", "ee_link")) not in pairs  # one body (ee_link is fixed to wrist_3_link)
    assert frozenset(("upper_arm_link", "wrist_1_link")) in pairs
    assert frozenset(("wrist_2_link", "spindle")) in pairs and frozenset(("wrist_3_link", "spindle")) not in pairs
    assert frozenset(("base_link", "table")) not in pairs  # ignored by the cell
    for (_, second), required in zip(scene.pairs, scene.required_m):
        assert required == (0.01 if second in ("table", "wall", "fixture") else 0.0)


def _orthoglide_with_collision_elements(folder: Path) -> Path:
    """A copy of the Orthoglide whose URDF declares its visual shapes as collision shapes too."""
    sidecar = edited_copy("orthoglide", folder, lambda document: None)
    urdf = sidecar.parent / "orthoglide.urdf"
    text = urdf.read_text()
    collisions = re.sub(r"<material.*?</material>", "", text).replace("<visual>", "<collision>").replace(
        "</visual>", "</collision>")
    links = re.findall(r"(<link name=\"[^\"]+\">)(.*?)(</link>)", collisions, flags=re.S)
    for (head, body, _), (_, original, _) in zip(links, re.findall(r"(<link name=\"[^\"]+\">)(.*?)(</link>)", text,
                                                                       flags=re.S)):
        text = text.replace(head + original, head + original + body, 1)
    urdf.write_text(text)
    return sidecar


def test_links_drawn_by_visuals_only_are_checked_against_the_cell_not_against_each_other():
    scene = CollisionScene(load_robot("orthoglide"), load_cell(ORTHOGLIDE_CELL))
    robot_names = {body.name for body in scene.bodies if body.is_robot}
    assert all(second not in robot_names for _, second in scene.pairs)
    assert {("platform", "vice"), ("bar1_z", "table")} <= set(scene.pairs)
    assert any("drawings are not clearances" in notice for notice in scene.notices)


def test_orthoglide_skips_tree_and_closure_neighbours(tmp_path):
    robot = load_robot(_orthoglide_with_collision_elements(tmp_path))
    scene = CollisionScene(robot, load_cell(ORTHOGLIDE_CELL))
    pairs = {frozenset(pair) for pair in scene.pairs}
    touching = {frozenset(pair) for pair in scene.touching_at_reference}
    considered = pairs | touching  # skipped as neighbours: neither checked nor found touching
    for axis in "xyz":
        assert frozenset((f"slider_{axis}", f"yoke_{axis}")) not in considered  # parent and child
        assert frozenset((f"yoke_{axis}", f"bar1_{axis}")) not in considered
        assert frozenset((f"bar2_{axis}", f"far_{axis}")) not in considered  # joined by the parallelogram's closure
    for axis in "yz":  # the far links weld to the platform through a wrist joint without shapes
        assert frozenset((f"far_{axis}", "platform")) not in considered
    assert frozenset(("bar1_x", "bar1_y")) in pairs
    assert touching and not touching & pairs
    assert (scene.distances(robot.reference_q) > 0).all()


def test_sidecar_ignore_pairs_are_skipped_and_checked(tmp_path):
    document = yaml.safe_load((ROOT / "robots" / "ur5" / "ur5.yaml").read_text())
    document["collision"] = {"ignore_pairs": [["upper_arm_link", "wrist_1_link"]]}
    (tmp_path / "ur5.yaml").write_text(yaml.safe_dump(document))
    scene = CollisionScene(load_robot(tmp_path / "ur5.yaml"))
    assert ("upper_arm_link", "wrist_1_link") not in scene.pairs and ("upper_arm_link", "wrist_2_link") in scene.pairs
    document["collision"] = {"ignore_pairs": [["upper_arm_link", "elbow"]]}
    (tmp_path / "ur5.yaml").write_text(yaml.safe_dump(document))
    with pytest.raises(RobotFileError, match=r"ur5.yaml, field 'collision.ignore_pairs.0.1': no link 'elbow'"):
        CollisionScene(load_robot(tmp_path / "ur5.yaml"))


def test_a_reduced_robot_places_its_shapes_as_the_full_model_does():
    """The Panda with joint 3 and the fingers locked: every shape where the full model puts it."""
    panda = load_robot("panda")
    scene = CollisionScene(panda)
    full = pin.buildModelFromUrdf(str(panda.urdf_path))
    q_full = pin.neutral(full)
    for name, value in panda.locked_joints.items():
        q_full[full.joints[full.getJointId(name)].idx_q] = value
    for name in panda.model.names[1:]:
        q_full[full.joints[full.getJointId(name)].idx_q] = panda.reference_q[panda.model.joints[
            panda.model.getJointId(name)].idx_q]
    data = full.createData()
    pin.framesForwardKinematics(full, data, q_full)
    geometry_data = pin.GeometryData(scene.geometry_model)
    pin.updateGeometryPlacements(panda.model, panda.model.createData(), scene.geometry_model, geometry_data,
                                 panda.reference_q)
    checked = 0
    for item, placement in zip(scene.geometry_model.geometryObjects, geometry_data.oMg):
        link = panda.model.frames[item.parentFrame].name
        local = panda.model.frames[item.parentFrame].placement.inverse() * item.placement
        expected = data.oMf[full.getFrameId(link)] * local
        np.testing.assert_allclose(placement.translation, expected.translation, atol=1e-12)
        np.testing.assert_allclose(placement.rotation, expected.rotation, atol=1e-12)
        checked += 1
    assert checked >= 9 and "panda_link3" in {body.name for body in scene.bodies}
    assert scene.distances(panda.reference_q).shape == (1, len(scene.pairs))


def test_a_base_link_inside_an_obstacle_is_an_error_naming_the_pair(ur5, tmp_path):
    document = yaml.safe_load(UR5_CELL.read_text())
    document["ignore"] = []
    with pytest.raises(CellFileError, match=r"field 'ignore': 'base_link' is fixed to the base and .* from 'table'"):
        CollisionScene(ur5, load_cell(write_cell(tmp_path, document)))


def test_scene_travels_to_another_process(ur5):
    scene = CollisionScene(ur5, load_cell(UR5_CELL))
    again = pickle.loads(pickle.dumps(scene))
    q = ur5.reference_q[None] + np.linspace(0, 0.5, 4)[:, None]
    np.testing.assert_array_equal(again.distances(q), scene.distances(q))
    assert again.pairs == scene.pairs


def test_distances_refuse_configurations_that_are_not_finite(ur5):
    scene = CollisionScene(ur5)
    with pytest.raises(ValueError, match="finite"):
        scene.distances(np.full((2, ur5.model.nq), np.nan))
    with pytest.raises(ValueError, match=r"\(M, 6\)"):
        scene.distances(np.zeros((2, 5)))


# ---------------------------------------------------------------- bad cell files


@pytest.mark.parametrize(("change", "field", "message"), [
    ({"obstacles": {"cone": {"type": "cone", "radius_m": 0.1}}}, "obstacles.cone", "does not match any of the expected"),
    ({"obstacles": {"slab": {"type": "box", "size_m": [0.1, -0.2, 0.1]}}}, "obstacles.slab.size_m.1",
     "greater than 0"),
    ({"obstacles": {"part": {"type": "mesh", "file": "missing.stl"}}}, "obstacles.part.file", "mesh file not found"),
    ({"keep_out": {"ball": {"type": "sphere", "radius_m": 0}}}, "keep_out.ball.radius_m", "greater than 0"),
    ({"workpiece_region": {"min_m": [0, 0, 0.5], "max_m": [1, 1, 0.5]}}, "workpiece_region", "must be below max_m"),
    ({"tool": {"mass_kg": 1.0, "inertia_kg_m2": [1e-3, 1e-3, -1e-3, 0, 0, 0]}}, "tool.inertia_kg_m2",
     "positive definite"),
    ({"tool": {"mass_kg": 1.0, "inertia_kg_m2": [1e-3, 1e-3, 3e-3, 0, 0, 0]}}, "tool.inertia_kg_m2",
     "triangle inequality"),
    ({"tool": {"mass_kg": 1.0, "inertia_kg_m2": [[1e-3, 0, 0], [1e-4, 1e-3, 0], [0, 0, 1e-3]]}}, "tool.inertia_kg_m2",
     "symmetric"),
    ({"tool": {"mass_kg": 0.0, "inertia_kg_m2": [1e-3, 1e-3, 1e-3, 0, 0, 0]}}, "tool.mass_kg", "greater than 0"),
    ({"obstacles": {"a": {"type": "sphere", "radius_m": 0.1}}, "keep_out": {"a": {"type": "sphere", "radius_m": 0.1}}},
     "keep_out.a", "also an obstacle"),
    ({"tool": {"mass_kg": 1.0, "inertia_kg_m2": [1e-3, 1e-3, 1e-3, 0, 0]}}, "tool.inertia_kg_m2", "expected six numbers"),
    ({"margin": 0.01}, "margin", "unknown field"),
])
def test_bad_cell_files_name_file_and_field(tmp_path, change, field, message):
    path = write_cell(tmp_path, change)
    with pytest.raises(CellFileError) as error:
        load_cell(path)
    assert error.value.field == field and message in error.value.problem and str(path) in str(error.value)


@pytest.mark.parametrize(("change", "field", "message"), [
    ({"ignore": [["base_lnk", "table"]]}, "ignore.0", "expected a robot link (or the tool) and an obstacle"),
    ({"ignore": [["base_link", "shoulder_link"]]}, "ignore.0", "expected a robot link"),
    ({"obstacles": {"wrist_1_link": {"type": "sphere", "radius_m": 0.1, "xyz_m": [2, 2, 2]}}},
     "obstacles.wrist_1_link", "also the name of a robot link"),
    ({"tool": {"frame": "flange", "mass_kg": 1.0, "inertia_kg_m2": [1e-3, 1e-3, 1e-3, 0, 0, 0],
               "collision": {"type": "sphere", "radius_m": 0.02}}}, "tool.frame", "no frame 'flange'"),
])
def test_cell_names_are_checked_against_the_robot(ur5, tmp_path, change, field, message):
    document = {**yaml.safe_load(UR5_CELL.read_text()), **change}
    path = write_cell(tmp_path, document)
    with pytest.raises(CellFileError) as error:
        CollisionScene(ur5, load_cell(path))
    assert error.value.field == field and message in error.value.problem and str(path) in str(error.value)


def test_a_mesh_that_is_no_mesh_is_an_error(ur5, tmp_path):
    (tmp_path / "flat.stl").write_text("solid flat\nendsolid flat\n")
    path = write_cell(tmp_path, {"obstacles": {"part": {"type": "mesh", "file": "flat.stl"}}})
    with pytest.raises(CellFileError, match=re.escape("field 'obstacles.part.file': cannot read")):
        CollisionScene(ur5, load_cell(path))


def test_example_cells_load_and_start_clear():
    for robot_name, path in (("ur5", UR5_CELL), ("orthoglide", ORTHOGLIDE_CELL)):
        robot = load_robot(robot_name)
        cell = load_cell(path)
        scene = CollisionScene(robot, cell)
        assert cell.workpiece_region is not None and cell.tool is not None
        assert (scene.distances(robot.reference_q) >= scene.required_m).all()
        assert {"table", cell.tool.name} <= {body.name for body in scene.bodies}


# ---------------------------------------------------------------- the tool's dynamics

SPINDLE = {"name": "spindle", "xyz_m": [0.01, -0.02, 0.03], "rpy_rad": [0.3, -0.2, 0.5], "mass_kg": 2.0,
           "com_m": [0.005, 0.01, 0.075], "inertia_kg_m2": [0.0042, 0.0045, 0.0009, 0.0002, -0.0001, 0.0003]}


def _random_state(robot, rng):
    q = pin.randomConfiguration(robot.model, -np.ones(robot.model.nq), np.ones(robot.model.nq))
    return q, rng.normal(size=robot.model.nv), rng.normal(size=robot.model.nv)


def test_mount_tool_adds_the_tools_newton_euler_wrench(ur5, tmp_path):
    """rnea with the tool = rnea without + Jᵀ·(m (a_c - g), I ω̇ + ω × I ω) of the tool's centre of mass."""
    tool = load_cell(write_cell(tmp_path, {"tool": SPINDLE})).tool
    mounted = mount_tool(ur5, tool)
    model = pin.Model(ur5.model)
    frame = model.frames[model.getFrameId("tool0")]
    com = pin.SE3(np.eye(3), np.array(tool.com_m))
    com_frame = model.addFrame(pin.Frame("com", frame.parentJoint, frame.placement * pose_placement(tool) * com,
                                         pin.FrameType.OP_FRAME), False)
    data, data_mounted = model.createData(), mounted.model.createData()
    rng = np.random.default_rng(3)
    for _ in range(5):
        q, v, a = _random_state(ur5, rng)
        pin.forwardKinematics(model, data, q, v, a)
        pin.updateFramePlacements(model, data)
        jacobian = pin.computeFrameJacobian(model, data, q, com_frame, pin.LOCAL_WORLD_ALIGNED)
        rotation = data.oMf[com_frame].rotation
        inertia = rotation @ tool.inertia_matrix @ rotation.T
        omega = pin.getFrameVelocity(model, data, com_frame, pin.LOCAL_WORLD_ALIGNED).angular
        omega_dot = pin.getFrameAcceleration(model, data, com_frame, pin.LOCAL_WORLD_ALIGNED).angular
        a_com = pin.getFrameClassicalAcceleration(model, data, com_frame, pin.LOCAL_WORLD_ALIGNED).linear
        force = tool.mass_kg * (a_com - model.gravity.linear)
        torque = inertia @ omega_dot + np.cross(omega, inertia @ omega)
        expected = pin.rnea(model, data, q, v, a) + jacobian[:3].T @ force + jacobian[3:].T @ torque
        np.testing.assert_allclose(pin.rnea(mounted.model, data_mounted, q, v, a), expected, atol=1e-9)
    assert ur5.model.inertias[6] != mounted.model.inertias[6]  # the copy carries the tool, not the original
    assert pin.Model(ur5.model).inertias[6] == load_robot("ur5").model.inertias[6]


def test_mount_tool_equals_a_urdf_with_the_tool_as_a_fixed_link(ur5, tmp_path):
    tool = load_cell(write_cell(tmp_path, {"tool": SPINDLE})).tool
    (xx, xy, xz), (_, yy, yz), (_, _, zz) = tool.inertia_kg_m2
    link = (f'<link name="spindle"><inertial><origin xyz="{" ".join(map(str, tool.com_m))}" rpy="0 0 0"/>'
            f'<mass value="{tool.mass_kg}"/><inertia ixx="{xx}" ixy="{xy}" ixz="{xz}" iyy="{yy}" iyz="{yz}" izz="{zz}"/>'
            '</inertial></link><joint name="spindle_mount" type="fixed"><parent link="tool0"/><child link="spindle"/>'
            f'<origin xyz="{" ".join(map(str, tool.xyz_m))}" rpy="{" ".join(map(str, tool.rpy_rad))}"/></joint>')
    text = ur5.urdf_path.read_text().replace("</robot>", link + "</robot>")
    (tmp_path / "ur5_spindle.urdf").write_text(text)
    reference = pin.buildModelFromUrdf(str(tmp_path / "ur5_spindle.urdf"))
    reference.armature[:] = ur5.model.armature
    reference.gravity = ur5.model.gravity
    mounted = mount_tool(ur5, tool)
    rng = np.random.default_rng(5)
    for _ in range(5):
        q, v, a = _random_state(ur5, rng)
        np.testing.assert_allclose(pin.rnea(mounted.model, mounted.model.createData(), q, v, a),
                                   pin.rnea(reference, reference.createData(), q, v, a), atol=1e-9)
    assert tool_inertia(tool).mass == 2.0


def test_a_sidecar_declares_a_tool_that_a_cells_tool_replaces(tmp_path):
    document = yaml.safe_load((ROOT / "robots" / "ur5" / "ur5.yaml").read_text())
    with_gripper(document)
    (tmp_path / "ur5.yaml").write_text(yaml.safe_dump(document))
    robot = load_robot(tmp_path / "ur5.yaml")
    assert ("wrist_2_link", "gripper") in CollisionScene(robot).pairs
    scene = CollisionScene(robot, load_cell(UR5_CELL))
    assert "spindle" in {b.name for b in scene.bodies} and "gripper" not in {b.name for b in scene.bodies}
    document["tool"]["frame"] = "flange"
    (tmp_path / "ur5.yaml").write_text(yaml.safe_dump(document))
    with pytest.raises(RobotFileError, match=r"ur5.yaml, field 'tool.frame': no frame 'flange'"):
        load_robot(tmp_path / "ur5.yaml")
    document["tool"]["collision"] = {"type": "mesh", "file": "gripper.stl"}
    (tmp_path / "ur5.yaml").write_text(yaml.safe_dump(document))
    with pytest.raises(RobotFileError, match=r"ur5.yaml, field 'tool.collision.file': mesh file not found"):
        load_robot(tmp_path / "ur5.yaml")
