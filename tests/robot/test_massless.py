"""Implausible physics refused as a robot loads (:mod:`placement.robot.plausibility`): moving links without inertia,
actuated joints without drive or effort limit, absurd link masses; the sidecar's ``links`` and ``--allow-massless``."""

import copy
import re
import shutil
import warnings
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin
import pytest
import yaml

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.cli import build_command_parser, main_parser
from placement.robot.exceptions import RobotFileError
from placement.robot.plausibility import MasslessWarning, links_without_inertia
from placement.workshop.checks import check_robot
from tests.support.robot_copies import GEPETTO_FIVEBAR, edited_copy, universal_shoulder_arm

FIVEBAR_LINKS = ["prox1", "dist1", "prox2", "dist2"]  # the moving links of the five-bar's four bodies
FIVEBAR_AT = np.array([0.0, 0.3, 0.0, 0.0, 0.0, 0.0])  # a reachable placement of examples/circle.yaml (m, rad)
UR5_AT = np.array([0.425, 0.1, 0.25, 0.0, 0.0, 0.0])  # the centre of the UR5's search space, for examples/rect.yaml


def without_inertials(text: str) -> str:
    """A URDF with every ``<inertial>`` removed, as ROS-Industrial's descriptions come."""
    return re.sub(r"<inertial>.*?</inertial>", "", text, flags=re.S)


def urdf_copy(name: str, folder, edit_urdf, edit_sidecar=lambda document: None):
    """A copy of built-in robot ``name`` beside its URDF (example-robot-data's too), the URDF text through
    ``edit_urdf`` and the sidecar through ``edit_sidecar``; returns the sidecar."""
    original = load_robot(name).urdf_path

    def edit(document):
        document["urdf"] = f"{name}.urdf"
        edit_sidecar(document)

    sidecar = edited_copy(name, folder, edit)
    (sidecar.parent / f"{name}.urdf").write_text(edit_urdf(original.read_text()))
    return sidecar


def inertials(urdf_text: str) -> dict[str, dict]:
    """Every link's ``<inertial>`` as the sidecar's ``links`` gives it: mass, centre of mass and the inertia turned
    from the inertial frame (its ``rpy``) to the link's axes, six numbers."""
    links = {}
    for link in ElementTree.fromstring(urdf_text).iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        origin = inertial.find("origin")
        xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
        rpy = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
        i = {key: float(value) for key, value in inertial.find("inertia").attrib.items()}
        tensor = np.array([[i["ixx"], i["ixy"], i["ixz"]], [i["ixy"], i["iyy"], i["iyz"]], [i["ixz"], i["iyz"], i["izz"]]])
        rotation = pin.rpy.rpyToMatrix(*rpy)
        turned = rotation @ tensor @ rotation.T
        links[link.get("name")] = {
            "mass_kg": float(inertial.find("mass").get("value")), "com_m": xyz,
            "inertia_kg_m2": [float(turned[0, 0]), float(turned[1, 1]), float(turned[2, 2]), float(turned[0, 1]),
                              float(turned[0, 2]), float(turned[1, 2])]}
    return links


def given_back(urdf_text: str, scale: float = 1.0):
    """A sidecar edit: the URDF's inertials under ``links`` (masses and inertias times ``scale``), with a source."""
    def edit(document):
        links = {name: inertial for name, inertial in inertials(urdf_text).items() if inertial["mass_kg"] > 0}
        for inertial in links.values():
            inertial["mass_kg"] *= scale
            inertial["inertia_kg_m2"] = [scale * value for value in inertial["inertia_kg_m2"]]
        document["links"] = links
        document["sources"]["links"] = "EST: the URDF's own inertials, given back"
    return edit


def energy_J(robot, path: str, placement: np.ndarray) -> float:
    """The electric energy of ``path`` at ``placement`` (J)."""
    detail = Evaluator(robot, load_path(path), EvaluatorSettings(workers=1)).detail(placement)
    assert detail.reachable
    return float(detail.energy.total_J)


@pytest.fixture
def massless_fivebar(tmp_path):
    """The five-bar with no <inertial> in its URDF (its sidecar unchanged)."""
    return urdf_copy("fivebar", tmp_path, without_inertials)


# --- refused, naming the links and the field -------------------------------------------------------------------------

def test_a_robot_without_inertials_is_refused_naming_its_links_the_field_and_the_ways_out(massless_fivebar):
    with pytest.raises(RobotFileError) as error:
        load_robot(massless_fivebar)
    assert error.value.path == massless_fivebar and error.value.field == "urdf.link.prox1.inertial"
    message = str(error.value)
    assert f"4 moving link(s) of fivebar.urdf have no inertia: {', '.join(FIVEBAR_LINKS)} without mass" in message
    assert "under the sidecar's links" in message and "--allow-massless" in message and "\n" not in message


def test_more_than_eight_links_are_counted_after_the_first_eight(tmp_path):
    """Without inertials, every one of the Orthoglide's 18 bodies lacks inertia: its weld stubs are welded to a
    platform without mass."""
    with pytest.raises(RobotFileError) as error:
        load_robot(urdf_copy("orthoglide", tmp_path, without_inertials))
    named = re.search(r"have no inertia: (.*?) without mass", str(error.value)).group(1)
    assert "18 moving link(s)" in str(error.value) and named.endswith(" and 10 more") and named.count(",") == 7


def test_a_flat_rotational_inertia_is_refused(tmp_path):
    def point_mass(text):
        return re.sub(r'(<link name="prox1">\s*<inertial>.*?<inertia) [^/]*/>',
                      r'\1 ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/>', text, count=1, flags=re.S)

    with pytest.raises(RobotFileError) as error:
        load_robot(urdf_copy("fivebar", tmp_path, point_mass))
    assert error.value.field == "urdf.link.prox1.inertial"
    assert "prox1 with a rotational inertia that is not positive definite" in str(error.value)


@pytest.mark.parametrize("argv", [["check", "{sidecar}"], ["--robot", "{sidecar}", "--path", "examples/circle.yaml"]])
def test_the_command_line_exits_2_with_one_error_line_naming_the_links(massless_fivebar, capsys, argv):
    assert main([arg.format(sidecar=massless_fivebar) for arg in argv]) == 2
    captured = capsys.readouterr()
    assert captured.err.count("\n") == 1 and captured.err.startswith(f"error: {massless_fivebar}, field 'urdf.link.")
    assert all(link in captured.err for link in FIVEBAR_LINKS) and "Traceback" not in captured.err


# --- what is legitimately massless ----------------------------------------------------------------------------------

def test_weld_stubs_and_a_gimbal_without_extent_are_legitimately_massless(tmp_path):
    """The Orthoglide's stubs welded to its platform, and the massless gimbal of a universal shoulder (the next
    joint at its origin, an arm with mass beyond), have no mass and load."""
    orthoglide, arm = load_robot("orthoglide"), load_robot(universal_shoulder_arm(tmp_path))
    for robot in (orthoglide, arm):
        assert any(inertia.mass == 0 for inertia in robot.model.inertias[1:])
        assert links_without_inertia(robot) == [] and robot.massless_links == ()
    assert check_robot(arm, 20).passed


@pytest.mark.parametrize(("offset_m", "massless", "named"), [(0.05, (), "gimbal"),
                                                               (0.0, ("upper", "fore"), "gimbal, upper, fore")])
def test_a_gimbal_with_extent_or_a_whole_massless_subtree_is_refused(tmp_path, offset_m, massless, named):
    with pytest.raises(RobotFileError, match=f"have no inertia: {named} without mass"):
        load_robot(universal_shoulder_arm(tmp_path, offset_m, massless))


# --- allowed knowingly ----------------------------------------------------------------------------------------------

def test_allow_massless_loads_with_one_warning_and_names_the_links(massless_fivebar):
    with pytest.warns(MasslessWarning) as caught:
        robot = load_robot(massless_fivebar, allow_massless=True)
    assert len(caught) == 1 and all(link in str(caught[0].message) for link in FIVEBAR_LINKS)
    assert robot.massless_links == tuple(FIVEBAR_LINKS)
    assert "the energies exclude the weight and inertia of 4 moving link(s)" in check_robot(robot, 20).warnings[0]


def test_allow_massless_runs_the_main_job_and_its_report_says_what_the_energies_leave_out(massless_fivebar, capsys,
                                                                                         tmp_path):
    result = tmp_path / "result.json"
    with pytest.warns(MasslessWarning) as caught:
        assert main(["--robot", str(massless_fivebar), "--path", "examples/circle.yaml", "--allow-massless", "--at",
                     "x=0,y=300", "--json", str(result)]) == 0
    said = [str(w.message) for w in caught if issubclass(w.category, MasslessWarning)]
    assert [text.split(" with ")[0] for text in said] == ["fivebar: loaded as asked (--allow-massless)"]
    assert "note: the energies exclude the weight and inertia of 4 moving link(s)" in capsys.readouterr().out
    assert yaml.safe_load(result.read_text())["massless_links"] == FIVEBAR_LINKS


def test_every_command_that_loads_a_robot_takes_allow_massless():
    assert main_parser().parse_args(["--robot", "r", "--path", "p", "--allow-massless"]).allow_massless
    lines = {"check": ["check", "r"], "map": ["map", "--robot", "r", "--path", "p", "--grid", "x=0:1:2"],
             "feed": ["feed", "--robot", "r", "--path", "p", "--at", "x=0", "--feeds", "0.1"],
             "app": ["app", "--robot", "r", "--path", "p"],
             "study": ["study", "--robots", "r", "--paths", "p", "--out", "o.csv"]}
    for argv in lines.values():
        assert build_command_parser().parse_args([*argv, "--allow-massless"]).allow_massless
        assert not build_command_parser().parse_args(argv).allow_massless


# --- the values given in the sidecar --------------------------------------------------------------------------------

@pytest.mark.parametrize(("name", "path", "at"), [("fivebar", "examples/circle.yaml", FIVEBAR_AT),
                                                  ("ur5", "examples/rect.yaml", UR5_AT)])
def test_the_urdf_inertials_given_back_in_links_reproduce_the_robot(tmp_path, name, path, at):
    """Stripped from the URDF and given back under the sidecar's links, the inertials (turned to the link axes for
    the UR5's, whose inertial frames are rotated) give the same model and the same energy at a fixed placement."""
    original = load_robot(name)
    text = original.urdf_path.read_text()
    robot = load_robot(urdf_copy(name, tmp_path, without_inertials, given_back(text)))
    for ours, theirs in zip(robot.model.inertias, original.model.inertias):
        np.testing.assert_allclose(ours.matrix(), theirs.matrix(), rtol=0, atol=1e-12)
    assert energy_J(robot, path, at) == pytest.approx(energy_J(original, path, at), rel=1e-9)


def test_the_efforts_are_affine_in_the_inertials_the_links_give(tmp_path, massless_fivebar):
    """The inverse dynamics is linear in the links' inertial parameters: the five-bar's links without inertia
    (allowed), as in its URDF, and twice as heavy and inert, under the sidecar's links, give efforts along the path
    (its process force and the rotors' inertia the same in all three) whose steps are equal, and large."""
    text = load_robot("fivebar").urdf_path.read_text()
    with pytest.warns(MasslessWarning):
        robots = [load_robot(massless_fivebar, allow_massless=True)]
    robots += [load_robot(urdf_copy("fivebar", tmp_path / f"x{scale}", without_inertials, given_back(text, scale)))
               for scale in (1.0, 2.0)]
    path = load_path("examples/circle.yaml")
    none, once, twice = (Evaluator(robot, path, EvaluatorSettings(workers=1)).detail(FIVEBAR_AT).effort
                         for robot in robots)
    np.testing.assert_allclose(twice - once, once - none, rtol=1e-9, atol=1e-9 * np.abs(once).max())
    assert np.abs(once - none).max() > 0.5 * np.abs(once).max()  # the links' weight and inertia: most of the effort


def test_a_links_entry_must_name_a_urdf_link_have_a_source_and_a_physical_inertia(tmp_path, massless_fivebar):
    inertial = {"mass_kg": 0.5, "com_m": [0.1, 0, 0], "inertia_kg_m2": [2.5e-5, 1.7e-3, 1.7e-3, 0, 0, 0]}
    cases = {"links.no_such_link": ({"no_such_link": inertial}, True, "no link 'no_such_link' in fivebar.urdf"),
             "links.prox1": ({"prox1": inertial}, False, "needs its source"),
             "links.prox1.inertia_kg_m2": ({"prox1": {**inertial, "inertia_kg_m2": [1, 1, 3, 0, 0, 0]}}, True,
                                           "triangle inequality")}
    original = yaml.safe_load(massless_fivebar.read_text())
    for field, (links, sourced, said) in cases.items():
        document = copy.deepcopy(original)
        document["links"] = links
        if sourced:
            document["sources"]["links"] = "EST: test"
        massless_fivebar.write_text(yaml.safe_dump(document))
        with pytest.raises(RobotFileError) as error:
            load_robot(massless_fivebar)
        assert error.value.field == field and said in str(error.value), field


def test_links_given_for_some_links_only_leave_the_others_named(tmp_path):
    text = load_robot("fivebar").urdf_path.read_text()

    def prox_only(document):
        given_back(text)(document)
        document["links"] = {name: document["links"][name] for name in ("prox1", "prox2")}

    with pytest.raises(RobotFileError, match="2 moving link\\(s\\) of fivebar.urdf have no inertia: dist1, dist2 "):
        load_robot(urdf_copy("fivebar", tmp_path, without_inertials, prox_only))


# --- efforts, speeds and masses -------------------------------------------------------------------------------------

def a1_limit(**values):
    """A URDF edit: joint a1's <limit> attributes set to ``values``."""
    def edit(text):
        for key, value in values.items():
            text = re.sub(rf'(<joint name="a1".*?<limit[^>]*? {key}=")[^"]*', rf"\g<1>{value}", text, count=1,
                          flags=re.S)
        return text
    return edit


def without_a1_drive(document):
    del document["actuators"][0]["drive"]


def test_a_zero_urdf_effort_is_refused_for_an_actuator_without_drive(tmp_path):
    with pytest.raises(RobotFileError) as error:
        load_robot(urdf_copy("fivebar", tmp_path / "refused", a1_limit(effort=0), without_a1_drive))
    assert error.value.field == "actuators.0.drive"
    assert "actuated joint(s) a1 have no drive and effort limit 0 in fivebar.urdf" in str(error.value)
    load_robot(urdf_copy("fivebar", tmp_path / "driven", a1_limit(effort=0)))  # its drive bounds the effort
    load_robot(urdf_copy("fivebar", tmp_path / "bounded", lambda text: text, without_a1_drive))  # the URDF's 50 N m
    with pytest.warns(MasslessWarning, match="without drive or effort limit \\(a1\\)"):
        load_robot(urdf_copy("fivebar", tmp_path / "allowed", a1_limit(effort=0), without_a1_drive), allow_massless=True)


def test_a_zero_urdf_velocity_is_refused_unless_the_sidecar_gives_one(tmp_path):
    def sidecar_silent(document):
        del document["actuators"][0]["velocity_max"]

    with pytest.raises(RobotFileError) as error:
        load_robot(urdf_copy("fivebar", tmp_path / "refused", a1_limit(velocity=0), sidecar_silent))
    assert error.value.field == "actuators.0.velocity_max"
    assert "joint 'a1' has velocity limit 0 in the URDF" in str(error.value) and "(rad/s)" in str(error.value)
    assert load_robot(urdf_copy("fivebar", tmp_path / "given", a1_limit(velocity=0))).actuators[0].velocity_max == 10


def test_an_absurd_link_mass_is_refused_unless_the_sidecar_gives_it(tmp_path):
    """A payload of 654 t on a five-bar whose moving bodies weigh about 0.5 kg: a mass in the wrong unit."""
    def tonnes(text):
        return re.sub(r'(<link name="payload">\s*<inertial>.*?<mass value=")[^"]*', r"\g<1>654000", text, count=1,
                      flags=re.S)

    with pytest.raises(RobotFileError) as error:
        load_robot(urdf_copy("fivebar", tmp_path / "refused", tonnes))
    assert error.value.field == "urdf.link.payload.inertial.mass"
    assert "link 'payload' of fivebar.urdf weighs 6.54e+05 kg" in str(error.value) and "links.payload" in str(error.value)

    def given(document):
        document["links"] = {"payload": {"mass_kg": 654000.0, "inertia_kg_m2": [1.0, 1.0, 1.0, 0, 0, 0]}}
        document["sources"]["links.payload"] = "EST: a test of a very heavy payload"

    heavy = load_robot(urdf_copy("fivebar", tmp_path / "given", tonnes, given))
    assert heavy.model.inertias[2].mass == pytest.approx(654000.4)  # dist1's body carries it
    load_robot(urdf_copy("fivebar", tmp_path / "heavy", lambda text: tonnes(text).replace("654000", "50")))  # 100 x


# --- every robot still loads ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["orthoglide", "fivebar", "delta", "ur5", "panda", "ur5_track", "ur5_positioner"])
def test_the_builtin_robots_load_without_a_warning(name):
    with warnings.catch_warnings():
        warnings.simplefilter("error", MasslessWarning)
        assert load_robot(name).massless_links == ()


def test_the_check_on_a_massless_robot_allowed_still_proves_the_model(massless_fivebar, capsys):
    with pytest.warns(MasslessWarning):
        assert main(["check", str(massless_fivebar), "--samples", "20", "--allow-massless"]) == 0
    out = capsys.readouterr().out
    assert "plausibility: 1 warning(s)" in out and "exact to round-off" in out


def massless_gepetto_fivebar(folder, closed: bool = False):
    """tests/data/gepetto_fivebar copied into ``folder`` without inertials; ``closed``: its loop closed at q = 0
    (the elbows' origins turned by the 0.08 and -0.05 rad it is open by), so that its robot.yaml loads as it is."""
    copied = folder / GEPETTO_FIVEBAR.name
    shutil.copytree(GEPETTO_FIVEBAR, copied)
    text = without_inertials((copied / "robot.urdf").read_text())
    if closed:
        text = text.replace('rpy="0 0 -1.515798931694258"', 'rpy="0 0 -1.595798931694258"')
        text = text.replace('rpy="0 0 1.545798931694258"', 'rpy="0 0 1.595798931694258"')
    (copied / "robot.urdf").write_text(text)
    return copied


def test_a_gepetto_robot_without_inertials_is_assembled_then_refused_until_its_sidecar_gives_them(tmp_path, capsys):
    folder = massless_gepetto_fivebar(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the estimates warning
        assert main(["assemble", str(folder), "--write"]) == 0
        assert "warning: 4 moving link(s) have no inertia (part_2, part_3, part_2_2, part_5)" in capsys.readouterr().out
        with pytest.raises(RobotFileError) as error:
            load_robot(folder)
    assert error.value.path == folder / "placement.yaml" and "under the sidecar's links" in str(error.value)


def test_a_gepetto_robot_yaml_without_inertials_is_told_to_fix_its_urdf(tmp_path):
    folder = massless_gepetto_fivebar(tmp_path, closed=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the estimates warning
        with pytest.raises(RobotFileError) as error:
            load_robot(folder)
    assert error.value.path == folder / "robot.yaml" and error.value.field == "urdf.link.part_2.inertial"
    assert "give an <inertial> for each in robot.urdf (or, once 'placement assemble" in str(error.value)
