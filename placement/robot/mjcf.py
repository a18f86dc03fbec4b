"""MuJoCo's MJCF descriptions (``.xml``): Pinocchio's model of them, what their actuators bound, and their loops.

Pinocchio builds the model (``buildModelFromMJCF``: bodies, joints with ``compiler`` angle units and default
classes, inertias, from the geoms where a body gives no ``<inertial>``; sites become frames). What it leaves out,
this module reads from the XML, default classes and ``childclass`` resolved as MuJoCo resolves them:

- **Effort bounds** (N or N·m at the joint), which Pinocchio leaves infinite: a joint's ``actuatorfrcrange``;
  else the sum over the actuators of the joint of ``|gear|`` times the largest force the actuator gives: its
  ``forcerange``, or for a motor (``<motor>``, or ``<general>`` without bias) ``|gain|`` times its largest
  ``|ctrlrange|``. A range counts where it is limited (``forcelimited``/``ctrllimited``/``actuatorfrclimited``
  true, or ``auto`` with ``compiler autolimits``, MuJoCo's default). A joint that none of these bounds gets
  effort 0 (none given), as a URDF joint without ``<limit effort>``; MJCF gives no speed limits, so every
  joint gets velocity 0 (none given).
- **Armature, damping and friction loss** stay out of the model (Pinocchio reads them into ``armature``,
  ``damping`` and ``friction``): here the drives carry a joint's reflected rotor inertia and friction, as for a
  URDF. :func:`read_mjcf` gives them, so that an estimated drive carries them (``joints``).
- **Loops**: each active ``<equality><connect>`` (a point closure) and ``<weld>`` (a weld closure) between two
  bodies (``body1``/``body2``) or two sites (``site1``/``site2``) becomes a closure between two frames, added to
  the model and named ``NAME_1`` and ``NAME_2``, NAME the constraint's name (``connect0``, ``weld1``, ... by
  kind and order when it has none). Between bodies, both frames stand at ``anchor`` (in ``body1``'s frame for a
  connect, ``body2``'s for a weld, as MuJoCo reads it), oriented as that body, where it is at ``qpos0`` (every
  joint at its ``ref``, 0 by default), as MuJoCo defines the constraint: the loop is closed there. A weld's
  ``relpose``, a ``torquescale`` and equalities of other kinds (``joint``, ``tendon``, ``flex``) are not read.

Where Pinocchio 4.1's parser departs from MuJoCo, the model is put right: it follows no ``<include>`` and reads
only the first body of the worldbody (so Pinocchio reads a copy with the includes in and the worldbody's bodies
held in one jointless body), it subtracts a joint's ``ref`` from its range though not from its kinematics (added
back), and it leaves the lower speed bound infinite (set with the upper one). The model is checked against
MuJoCo's own in ``tests/robot/test_mjcf.py``.

A sidecar's ``links`` (inertials replacing the description's) do not apply to an MJCF: its ``<inertial>``
elements are where they go.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin

from placement.robot.exceptions import RobotFileError
from placement.robot.expanded import cached_description
from placement.robot.urdf import UrdfContents

SUFFIXES = (".xml", ".mjcf")
ACTUATOR_TAGS = ("general", "motor", "position", "velocity", "intvelocity", "damper", "cylinder", "muscle",
                 "adhesion")
UNBIASED = ("motor",)  # shortcuts whose force is gain times control
WORLD_BODY = "worldbody"  # the body without a joint that holds a worldbody's several bodies for Pinocchio
MERGED = ("default", "worldbody", "asset", "actuator", "equality", "contact", "tendon", "sensor", "keyframe")
EQUALITY_KINDS = {"connect": "point", "weld": "weld"}


def is_mjcf(path: Path) -> bool:
    """Whether ``path`` names an MJCF file (by its suffix)."""
    return path.suffix.lower() in SUFFIXES


@dataclass(frozen=True)
class MjcfJoint:
    """What an MJCF gives of one joint beyond Pinocchio's model (joint units: N or N·m, kg or kg·m², ...).

    Attributes:
        effort: The largest effort its actuators give (N or N·m), or None when nothing bounds it.
        effort_from: Where ``effort`` comes from, for the sources (``actuator 'm1': forcerange 87 x gear 1``).
        armature: Its reflected rotor inertia (kg or kg·m²).
        damping: Its viscous friction (N·s/m or N·m·s/rad).
        frictionloss: Its Coulomb friction (N or N·m).
        ref: Its value at qpos0, where the bodies stand as the file places them (rad or m; ``ref``).
    """

    effort: float | None
    effort_from: str
    armature: float
    damping: float
    frictionloss: float
    ref: float = 0.0


@dataclass(frozen=True)
class MjcfClosure:
    """A loop of the MJCF: its name, ``point`` or ``weld``, and the two frames that must coincide."""

    name: str
    kind: str
    frames: tuple[str, str]


@dataclass(frozen=True)
class MjcfContents(UrdfContents):
    """What loading reads of an MJCF besides Pinocchio's model: the names (its bodies under ``link``), the masses of
    the bodies that carry a joint (with the bodies welded to them, as Pinocchio merges them), its joints' data and
    its loops."""

    joints: dict[str, MjcfJoint] = field(default_factory=dict)
    closures: tuple[MjcfClosure, ...] = ()
    actuated: tuple[str, ...] = ()  # the joints its actuators drive, in the order of their first actuator


def mjcf_model(path: Path) -> pin.Model:
    """Pinocchio's model of the MJCF, with its joints' effort bounds, no speed limits (0: none given), no armature,
    damping or friction, and the frames of its loops (module docstring).

    Raises:
        RobotFileError: The file is not XML or not an MJCF, Pinocchio cannot build it, or a loop names what the
            model lacks.
    """
    root = _root(path)
    model = _built(_self_contained(path, root))
    joints = _joints(path, root)
    for j in range(1, model.njoints):
        v = model.joints[j].idx_v
        given = joints.get(model.names[j])
        model.effortLimit[v : v + model.joints[j].nv] = given.effort if given and given.effort is not None else 0.0
    model.velocityLimit[:] = 0.0
    if hasattr(model, "lowerVelocityLimit"):  # Pinocchio 4 keeps a bound per side, this one as a magnitude as well
        model.lowerVelocityLimit[:] = 0.0
        model.lowerEffortLimit[:] = -model.effortLimit
    model.armature[:] = 0.0
    model.damping[:] = 0.0
    model.friction[:] = 0.0
    for j in range(1, model.njoints):  # Pinocchio 4.1 reads a joint's range less its ref, against its own kinematics
        given = joints.get(model.names[j])
        if given is not None and given.ref != 0.0 and model.joints[j].nq == 1:
            model.lowerPositionLimit[model.joints[j].idx_q] += given.ref
            model.upperPositionLimit[model.joints[j].idx_q] += given.ref
    _add_closure_frames(path, root, model, qpos0(model, joints))
    return model


def qpos0(model: pin.Model, joints: Mapping[str, MjcfJoint]) -> np.ndarray:
    """The model's configuration at MuJoCo's qpos0: every one-coordinate joint at its ``ref`` (rad or m)."""
    q = pin.neutral(model)
    for j in range(1, model.njoints):
        given = joints.get(model.names[j])
        if given is not None and model.joints[j].nq == 1:
            q[model.joints[j].idx_q] = given.ref
    return q


def read_mjcf(path: Path, model: pin.Model | None = None) -> MjcfContents:
    """The bodies and joints of the MJCF by name, the masses of the bodies that carry a joint (kg), its joints' data
    and its loops (module docstring).

    Args:
        path: The MJCF file.
        model: Its model (:func:`mjcf_model`), if built already.

    Raises:
        RobotFileError: As :func:`mjcf_model`.
    """
    root = _root(path)
    model = model if model is not None else mjcf_model(path)
    bodies = {str(body.get("name")) for body in root.iter("body") if body.get("name")}
    joint_names = {str(joint.get("name")) for joint in _body_joints(root) if joint.get("name")}
    masses: dict[str, float] = {}
    weighed: set[int] = set()
    for frame in model.frames:  # the first body on each joint carries the joint's inertia
        if frame.type == pin.FrameType.BODY and frame.parentJoint > 0 and frame.parentJoint not in weighed:
            weighed.add(frame.parentJoint)
            masses[frame.name] = float(model.inertias[frame.parentJoint].mass)
    actuators = root.find("actuator")
    actuated = [str(element.get("joint")) for element in (actuators if actuators is not None else ())
                if element.tag in ACTUATOR_TAGS and element.get("joint")]
    return MjcfContents({"link": bodies, "joint": joint_names}, masses, _joints(path, root),
                        tuple(closure for closure, _ in _equalities(path, root)), tuple(dict.fromkeys(actuated)))


def mjcf_geometry(model: pin.Model, path: Path, kind: pin.GeometryType) -> pin.GeometryModel:
    """Pinocchio's geometry model of the MJCF's visual or collision geoms (``contype``/``conaffinity`` 0: visual), its
    meshes found as the file's ``compiler meshdir`` says.

    Raises:
        RobotFileError: A mesh cannot be found or read.
    """
    try:
        return pin.buildGeomFromMJCF(model, str(_self_contained(path, _root(path))), kind)
    except (ValueError, RuntimeError) as error:
        said = " ".join(str(error).split())
        raise RobotFileError(path, "", f"cannot build the geometry: {said[said.find('message:'):][:300]}") from None


def _root(path: Path) -> ElementTree.Element:
    """The MJCF's root element ``<mujoco>``."""
    try:
        root = ElementTree.parse(path).getroot()
    except (ElementTree.ParseError, UnicodeDecodeError, OSError) as error:
        raise RobotFileError(path, "", f"not an XML file: {str(error)[:200]}") from None
    if root.tag != "mujoco":
        raise RobotFileError(path, "", f"not an MJCF file: the root element is <{root.tag[:40]}>, expected <mujoco>")
    _include(path, root, path.parent, depth=0)
    for tag in MERGED:  # MuJoCo reads repeated sections (an included file's and the scene's) as one
        sections = root.findall(tag)
        for other in sections[1:]:
            sections[0].extend(list(other))
            root.remove(other)
    return root


def _include(path: Path, element: ElementTree.Element, folder: Path, depth: int) -> None:
    """Replace every ``<include file>`` under ``element`` by the children of the included file's root, in place, as
    MuJoCo does (its path relative to the main file's folder)."""
    for i, child in enumerate(list(element)):
        if child.tag != "include":
            _include(path, child, folder, depth)
            continue
        included = folder / child.get("file", "")
        try:
            inner = ElementTree.parse(included).getroot()
        except (ElementTree.ParseError, UnicodeDecodeError, OSError) as error:
            raise RobotFileError(path, f"include {child.get('file')}", f"cannot read {included}: {str(error)[:200]}") from None
        if depth > 20:
            raise RobotFileError(path, f"include {child.get('file')}", "includes nest more than 20 deep")
        _include(path, inner, folder, depth + 1)
        element.remove(child)
        for k, grandchild in enumerate(inner):
            element.insert(i + k, grandchild)


def _self_contained(path: Path, root: ElementTree.Element) -> Path:
    """The file Pinocchio reads for ``path``: itself, or the file its ``<include>`` elements make together (a
    Menagerie ``scene.xml``; ``root`` read by :func:`_root`), its asset folders made absolute, and its worldbody's
    bodies in one body without a joint (``WORLD_BODY``) when it has several: Pinocchio 4.1's parser follows no
    include and reads only the first body of the worldbody (and of repeated sections, such as two ``<default>``,
    only the first: :func:`_root` merges them). That file is written once to the cache folder of expanded
    descriptions."""
    worldbody = root.find("worldbody")
    bodies = worldbody.findall("body") if worldbody is not None else []
    if not _has_include(path) and len(bodies) < 2 and not _has_repeated_sections(path):
        return path
    if worldbody is not None and len(bodies) > 1:
        held = ElementTree.SubElement(worldbody, "body", name=WORLD_BODY)
        for body in bodies:
            worldbody.remove(body)
            held.append(body)
    folder = path.resolve().parent
    compilers = root.findall("compiler") or [ElementTree.SubElement(root, "compiler")]
    for compiler in compilers:
        for key in ("meshdir", "assetdir", "texturedir"):
            compiler.set(key, str(folder / compiler.get(key, "")))
    text = ElementTree.tostring(root, encoding="unicode")
    return cached_description(path.stem, text, ".xml")


def _has_repeated_sections(path: Path) -> bool:
    """Whether the MJCF file repeats a section its root holds (two ``<default>``, as onshape-to-robot writes an
    additional ``joints_properties.xml``): Pinocchio 4.1 reads the first only."""
    tags = [element.tag for element in ElementTree.parse(path).getroot() if element.tag in MERGED]
    return len(tags) > len(set(tags))


def _has_include(path: Path) -> bool:
    """Whether the MJCF file has an ``<include>`` element."""
    return any(element.tag == "include" for element in ElementTree.parse(path).getroot().iter())


def _built(path: Path) -> pin.Model:
    """Pinocchio's model of the file, its complaints (printed by C++) as the error's message."""
    with tempfile.TemporaryFile(mode="w+") as capture:
        saved = os.dup(2)
        os.dup2(capture.fileno(), 2)
        try:
            return pin.buildModelFromMJCF(str(path))
        except (ValueError, RuntimeError, IndexError) as error:  # IndexError: a name its maps lack
            os.dup2(saved, 2)
            capture.seek(0)
            said = [line.strip() for line in capture.read().splitlines() if line.strip()]
            reason = " ".join(str(error).split())
            reason = reason[reason.find("message:") + 8:].strip() if "message:" in reason else (said or [reason])[-1]
            raise RobotFileError(path, "", f"Pinocchio cannot build a model from it: {reason[:200]}") from None
        finally:
            os.dup2(saved, 2)
            os.close(saved)


class _Defaults:
    """The MJCF's default classes: each class's attributes by element kind (``joint``, ``actuator``), inherited."""

    def __init__(self, root: ElementTree.Element) -> None:
        self.classes: dict[str, dict[str, dict[str, str]]] = {}
        self.shortcut: dict[str, str] = {}  # the actuator shortcut a class's defaults were written with
        for top in root.findall("default"):
            self._read(top, {"joint": {}, "actuator": {}}, "general")

    def _read(self, element: ElementTree.Element, inherited: dict[str, dict[str, str]], shortcut: str) -> None:
        own = {kind: dict(values) for kind, values in inherited.items()}
        for child in element:
            if child.tag == "joint":
                own["joint"].update(child.attrib)
            elif child.tag in ACTUATOR_TAGS:
                own["actuator"].update(child.attrib)
                shortcut = child.tag
        name = element.get("class", "main")
        self.classes[name], self.shortcut[name] = own, shortcut
        for child in element.findall("default"):
            self._read(child, own, shortcut)

    def of(self, kind: str, element: ElementTree.Element, childclass: str | None) -> dict[str, str]:
        """The element's attributes with its class's defaults under them."""
        name = element.get("class") or childclass or "main"
        return {**self.classes.get(name, {}).get(kind, {}), **element.attrib}

    def shortcut_of(self, element: ElementTree.Element) -> str:
        """The kind of an actuator: its tag, or for ``<general>`` the shortcut its class's defaults use."""
        if element.tag != "general":
            return element.tag
        return self.shortcut.get(element.get("class") or "main", "general")


def _body_joints(root: ElementTree.Element) -> Iterator[ElementTree.Element]:
    """Every joint of the bodies (``joint``, ``freejoint``)."""
    worldbody = root.find("worldbody")
    if worldbody is None:
        return iter(())
    return (element for element in worldbody.iter() if element.tag in ("joint", "freejoint"))


def _joints_with_class(root: ElementTree.Element) -> Iterator[tuple[ElementTree.Element, str | None]]:
    """Every ``<joint>`` of the bodies, with the ``childclass`` it falls under (the nearest body's that gives one)."""

    def walk(element: ElementTree.Element, childclass: str | None) -> Iterator[tuple[ElementTree.Element, str | None]]:
        for child in element:
            if child.tag == "joint":
                yield child, childclass
            elif child.tag in ("body", "frame"):
                yield from walk(child, child.get("childclass") or childclass)

    worldbody = root.find("worldbody")
    return walk(worldbody, worldbody.get("childclass")) if worldbody is not None else iter(())


def _joints(path: Path, root: ElementTree.Element) -> dict[str, MjcfJoint]:
    """Every named joint's effort bound, armature, damping and friction loss (module docstring)."""
    defaults = _Defaults(root)
    compiler = root.find("compiler")
    degrees = (compiler.get("angle", "degree") if compiler is not None else "degree") == "degree"
    autolimits = (compiler.get("autolimits", "true") if compiler is not None else "true") == "true"
    actuated: dict[str, list[tuple[float | None, str]]] = {}
    actuators = root.find("actuator")
    for i, element in enumerate(actuators if actuators is not None else ()):
        values = defaults.of("actuator", element, None)
        joint = values.get("joint")
        if element.tag not in ACTUATOR_TAGS or joint is None:
            continue
        name = f"actuator '{values['name']}'" if values.get("name") else f"actuator {i} (of joint '{joint}')"
        gear = abs(_numbers(path, f"{name} gear", values.get("gear", "1"))[0])
        force = _range_bound(path, values, "forcerange", "forcelimited", autolimits, name)
        said = f"{name}: forcerange {force:g} x gear {gear:g}" if force is not None else ""
        if force is None and (defaults.shortcut_of(element) in UNBIASED or (
                element.tag == "general" and values.get("biastype", "none") == "none")):
            control = _range_bound(path, values, "ctrlrange", "ctrllimited", autolimits, name)
            gain = 1.0 if element.tag == "motor" else abs(_numbers(path, f"{name} gainprm", values.get("gainprm", "1"))[0])
            if control is not None:
                force, said = gain * control, f"{name}: ctrlrange {control:g} x gain {gain:g} x gear {gear:g}"
        actuated.setdefault(joint, []).append((None if force is None else gear * force, said))
    joints = {}
    for element, childclass in _joints_with_class(root):
        values, joint_name = defaults.of("joint", element, childclass), element.get("name")
        if not joint_name:
            continue
        own = _range_bound(path, values, "actuatorfrcrange", "actuatorfrclimited", autolimits, f"joint '{joint_name}'")
        bounds = actuated.get(joint_name, [])
        total = None if not bounds or any(b is None for b, _ in bounds) else sum(b for b, _ in bounds if b is not None)
        effort, said = (own, f"joint '{joint_name}': actuatorfrcrange {own:g}") if own is not None and (
            total is None or own <= total) else (total, "; ".join(text for _, text in bounds))
        armature, damping, frictionloss, ref = (_numbers(path, f"joint '{joint_name}' {key}", values.get(key, "0"))[0]
                                                for key in ("armature", "damping", "frictionloss", "ref"))
        if degrees and values.get("type", "hinge") == "hinge":
            ref = float(np.radians(ref))
        joints[joint_name] = MjcfJoint(effort, said if effort is not None else "", armature, damping, frictionloss, ref)
    return joints


def _range_bound(path: Path, values: Mapping[str, str], key: str, flag: str, autolimits: bool,
                 owner: str) -> float | None:
    """The largest magnitude of a limited range attribute (``forcerange``...), None when it does not limit."""
    limited = values.get(flag, "auto")
    if key not in values or limited == "false" or (limited == "auto" and not autolimits):
        return None
    low, high = _numbers(path, f"{owner} {key}", values[key], 2)
    if not low <= high:
        raise RobotFileError(path, f"{owner} {key}", f"expected its lower bound below its upper (got {low:g} {high:g})")
    return max(abs(low), abs(high)) if low < high else None


def _numbers(path: Path, field: str, text: str, count: int = 1) -> list[float]:
    """The first ``count`` numbers of an attribute."""
    try:
        numbers = [float(word) for word in text.split()]
    except ValueError:
        raise RobotFileError(path, field, f"expected numbers, got '{text[:60]}'") from None
    if len(numbers) < count or not all(np.isfinite(numbers)):
        raise RobotFileError(path, field, f"expected {count} finite number(s), got '{text[:60]}'")
    return numbers[:count]


def _equalities(path: Path, root: ElementTree.Element) -> Iterator[tuple[MjcfClosure, ElementTree.Element]]:
    """The active ``connect`` and ``weld`` equalities as closures, named (module docstring), and their elements."""
    counts = dict.fromkeys(EQUALITY_KINDS, 0)
    for equality in root.findall("equality"):
        for element in equality:
            if element.tag not in EQUALITY_KINDS:
                continue
            name = element.get("name") or f"{element.tag}{counts[element.tag]}"
            counts[element.tag] += 1
            if element.get("active", "true") == "false":
                continue
            for attribute in ("relpose", "torquescale"):
                if element.tag == "weld" and attribute in element.attrib:
                    raise RobotFileError(path, f"equality weld '{name}'", f"its {attribute} is not read here: weld "
                                         "the two bodies as they stand at qpos0 (leave it out), or write the closure "
                                         "in a sidecar")
            sites = element.get("site1"), element.get("site2")
            frames = (sites[0], sites[1]) if sites[0] and sites[1] else (f"{name}_1", f"{name}_2")
            yield MjcfClosure(name, EQUALITY_KINDS[element.tag], (str(frames[0]), str(frames[1]))), element


def _add_closure_frames(path: Path, root: ElementTree.Element, model: pin.Model, q0: np.ndarray) -> None:
    """Add to ``model`` the two frames of every loop between bodies, coinciding at qpos0 ``q0`` (module docstring)."""
    data = model.createData()
    pin.framesForwardKinematics(model, data, q0)
    for closure, element in _equalities(path, root):
        field_ = f"equality {element.tag} '{closure.name}'"
        if element.get("site1") and element.get("site2"):
            for site in (element.get("site1"), element.get("site2")):
                if not model.existFrame(str(site)):
                    raise RobotFileError(path, field_, f"no site '{site}' in the model")
            continue
        bodies = element.get("body1"), element.get("body2") or "world"
        ids = []
        for body in bodies:
            if body is None or not (body == "world" or model.existFrame(body, pin.FrameType.BODY)):
                raise RobotFileError(path, field_, f"expected body1 and body2 naming bodies (or site1 and site2), got "
                                     f"{bodies}")
            ids.append(0 if body == "world" else model.getFrameId(body, pin.FrameType.BODY))
        anchor = np.array(_numbers(path, f"{field_} anchor", element.get("anchor", "0 0 0"), 3))
        anchored = ids[1] if element.tag == "weld" else ids[0]  # a weld's anchor is in body2's frame, a connect's body1's
        world = data.oMf[anchored] * pin.SE3(np.eye(3), anchor)
        for suffix, frame_id in (("_1", ids[0]), ("_2", ids[1])):
            frame, name = model.frames[frame_id], closure.name + suffix
            placement = data.oMi[frame.parentJoint].actInv(world)
            if model.existFrame(name):
                raise RobotFileError(path, field_, f"its frame '{name}' would take the name of a frame of the model: "
                                     "rename the constraint")
            model.addFrame(pin.Frame(name, frame.parentJoint, frame_id, placement, pin.FrameType.OP_FRAME))

