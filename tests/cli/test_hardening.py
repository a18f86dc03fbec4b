"""Bad and hostile input: a clear message naming what is wrong and exit 2, never a traceback,
never exit 0 on nonsense; outputs never clobber inputs, links or devices."""

import os
import stat
import subprocess
import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from placement.cli import main
from tests.support.cli import run_command
from tests.support.paths import EXAMPLE
from tests.support.robot_copies import edited_copy

RECT = EXAMPLE.read_text()
QUICK = ["--robot", "orthoglide", "--time-step", "0.01", "--generations", "2", "--population", "6", "--quiet"]


def run(argv, capsys):
    """Exit code and standard error of the command line."""
    code, _, err = run_command(argv, capsys)
    return code, err


def laughs() -> str:
    lines = ['a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for previous, name in zip("abcdef", "bcdefg"):
        lines.append(f"{name}: &{name} [{', '.join(['*' + previous] * 9)}]")
    return "\n".join(lines) + "\nname: *g\nunits: mm\nshape: {type: circle, radius: 5}\nfeed_m_s: 0.1\n"


PATH_FILES = {
    "binary": (bytes(range(256)) * 8, "not a text file in UTF-8"),
    "latin-1": ("name: caf\xe9\n".encode("latin-1"), "not a text file in UTF-8"),
    "deep": (("a: " + "[" * 20000 + "]" * 20000).encode(), "nested too deeply"),
    "laughs": (laughs().encode(), "holds more than 1,000,000 values (counting each use of an & anchor)"),
    "huge width": (RECT.replace("width: 30", "width: 1e9").encode(), "would need more than 1,000,000 samples"),
    "slow feed": (RECT.replace("feed_m_s: 0.66", "feed_m_s: 1e-9").encode(), "would need more than"),
    "tiny step": (RECT.replace("time_step_s: 0.001", "time_step_s: 1e-12").encode(), "would need more than"),
    "tiny circle": (b"units: mm\nshape: {type: circle, radius: 1e-300}\nfeed_m_s: 0.1\n", "the path is shorter than 1"),
    "boolean width": (RECT.replace("width: 30", "width: true").encode(), "field 'shape.width': Input should be a valid number"),
    "duplicate key": (RECT.replace("units: mm", "units: mm\nunits: m").encode(), "the key 'units' appears twice"),
}


@pytest.mark.parametrize("case", PATH_FILES)
def test_bad_path_files_exit_2_with_the_reason(case, tmp_path, capsys):
    content, expected = PATH_FILES[case]
    file = tmp_path / "path.yaml"
    file.write_bytes(content)
    code, err = run(["--robot", "orthoglide", "--quiet", "--path", str(file)], capsys)  # the file's own time step
    assert code == 2 and expected in err, err
    assert len(err) < 1000  # never the expanded input


OPTIONS = {
    "--seed -1": (["--seed", "-1"], "argument --seed: expected a whole number from 0"),
    "--population huge": (["--population", "100000000"], "argument --population: expected a whole number from 1 to 10,000"),
    "--time-step inf": (["--time-step", "inf"], "argument --time-step: expected a finite number > 0"),
    "--time-step tiny": (["--time-step", "1e-9"], "would need more than 1,000,000 samples"),
    "--max-acceleration tiny": (["--timing", "realistic", "--max-acceleration", "1e-9"], "would need more than"),
    "--at twice": (["--at", "x=0,x=10"], "--at: x is given twice"),
    "--at empty": (["--at", ""], "--at: give at least one value"),
    "--free twice": (["--free", "x,y,x"], "--free: x is given twice"),
    "--free empty": (["--free", ""], "--free: expected names from x, y, z"),
}


@pytest.mark.parametrize("case", OPTIONS)
def test_bad_options_exit_2_naming_the_option(case, capsys):
    extra, expected = OPTIONS[case]
    code, err = run(QUICK + ["--path", str(EXAMPLE), *extra], capsys)
    assert code == 2 and expected in err, err


MAP = ["map", "--robot", "orthoglide", "--path", str(EXAMPLE), "--time-step", "0.01", "--quiet"]


@pytest.mark.parametrize(("extra", "expected"), [
    (["--grid", "x=-10:10:3,x=0:5:2"], "--grid: x is given twice"),
    (["--grid", "x=-10:10:3", "--fix", "x=5"], "--fix: x is also swept by --grid"),
    (["--grid", "x=nan:10:3"], "--grid: the start and stop of x must be finite numbers"),
    (["--grid", "x=-10:10:10000,y=-10:10:10000"], "--grid: more than 1,000,000 placements"),
    (["--grid", "x=-10:10:3", "--png", "map.png"], "--png draws maps over exactly two variables; --grid gives 1"),
])
def test_bad_map_requests_exit_2_before_any_work(extra, expected, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, err = run(MAP + ["--out", "map.npz", *extra], capsys)
    assert code == 2 and expected in err and not (tmp_path / "map.npz").exists()


def test_map_reports_the_file_it_writes(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(MAP + ["--grid", "x=-10:10:2", "--out", "mapfile"]) == 0
    assert "written to mapfile.npz" in capsys.readouterr().out and (tmp_path / "mapfile.npz").is_file()


@pytest.mark.parametrize("samples", ["0", "1"])
def test_check_needs_enough_samples(samples, capsys):
    code, err = run(["check", "orthoglide", "--samples", samples], capsys)
    assert code == 2 and "argument --samples: expected a whole number from 10" in err


def test_outputs_never_overwrite_inputs_links_or_devices(tmp_path, capsys):
    path = tmp_path / "rect.yaml"
    path.write_text(RECT)
    target = tmp_path / "target.json"
    target.write_text("keep")
    (tmp_path / "link.json").symlink_to(target)
    cases = [(["--json", str(path)], "is an input file"),
             (["--json", str(tmp_path / "a.json"), "--trace", str(tmp_path / "a.json")], "also the file of --json"),
             (["--json", str(tmp_path / "link.json")], "is a symbolic link"),
             (["--json", "/dev/null"], "is not a regular file")]
    (tmp_path / "hard.yaml").hardlink_to(path)
    cases.append((["--json", str(tmp_path / "hard.yaml")], "is an input file (another name of it)"))
    for extra, expected in cases:
        code, err = run(QUICK + ["--path", str(path), "--at", "x=0", *extra], capsys)
        assert code == 2 and expected in err, (extra, err)
    assert path.read_text() == RECT and target.read_text() == "keep"
    sidecar = edited_copy("orthoglide", tmp_path / "robot", lambda d: None)
    urdf = (sidecar.parent / "orthoglide.urdf").read_text()
    for option, file in (("--html", "orthoglide.urdf"), ("--trace", "closed_form.py"), ("--json", "orthoglide.yaml")):
        code, err = run(["--robot", str(sidecar), "--path", str(path), "--at", "x=0", option, str(sidecar.parent / file)],
                        capsys)
        assert code == 2 and "is an input file" in err, (option, err)
    assert (sidecar.parent / "orthoglide.urdf").read_text() == urdf


def test_an_existing_output_keeps_its_mode(tmp_path, capsys):
    out = tmp_path / "result.json"
    out.write_text("{}")
    out.chmod(0o600)
    assert main(QUICK + ["--path", str(EXAMPLE), "--at", "x=0", "--json", str(out)]) == 0
    assert stat.S_IMODE(out.stat().st_mode) == 0o600 and '"at"' in out.read_text()


@pytest.mark.parametrize(("edit", "expected"), [
    (lambda d: d.update(kinematics_plugin="../elsewhere.py"), "expected a .py file in the sidecar's own folder"),
    (lambda d: d.update(kinematics_plugin="/etc/passwd"), "expected a .py file in the sidecar's own folder"),
    (lambda d: d.update(kinematics_plugin="orthoglide.urdf"), "expected a .py file in the sidecar's own folder"),
    (lambda d: next(iter(d["drives"].values()))["motor"].update(model="nonesuch"),
     "field 'drives.sanyo_p30b06040d_ball_screw.motor': unknown motor model 'nonesuch', expected one of pmsm"),
])
def test_bad_robot_files_exit_2_naming_the_field(edit, expected, tmp_path, capsys):
    sidecar = edited_copy("orthoglide", tmp_path, edit)
    code, err = run(["check", str(sidecar)], capsys)
    assert code == 2 and f"{sidecar}, " in err and expected in err, err


def test_a_plugin_that_exits_or_a_truncated_urdf_is_an_error(tmp_path, capsys):
    sidecar = edited_copy("orthoglide", tmp_path, lambda d: None)
    (sidecar.parent / "closed_form.py").write_text("import sys\nsys.exit(0)\n")
    code, err = run(["check", str(sidecar)], capsys)
    assert code == 2 and "the kinematics plug-in failed to load: SystemExit" in err
    urdf = sidecar.parent / "orthoglide.urdf"
    urdf.write_text(urdf.read_text()[:2000])
    code, err = run(["check", str(sidecar)], capsys)
    assert code == 2 and "orthoglide.urdf: not an XML file" in err


def test_an_unexpected_error_is_one_line_and_debug_shows_it(monkeypatch, capsys):
    from placement.cli import robots

    def broken(args):
        raise RuntimeError("something\nunforeseen")

    monkeypatch.setattr(robots, "run", broken)
    code, err = run(["robots"], capsys)
    assert code == 2 and err == "error: unexpected RuntimeError: something unforeseen (run again with --debug to see where)\n"
    with pytest.raises(RuntimeError):
        main(["robots", "--debug"])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.dictionaries(st.sampled_from(["name", "units", "shape", "feed_m_s", "time_step_s", "timing", "process_forces_N"]),
                       st.recursive(st.none() | st.booleans() | st.floats() | st.integers() | st.text(max_size=20),
                                    lambda children: st.lists(children, max_size=4)
                                    | st.dictionaries(st.sampled_from(["type", "width", "radius", "mode", "x"]), children,
                                                      max_size=4), max_leaves=8), max_size=7))
def test_generated_path_files_never_crash(tmp_path_factory, capsys, document):
    import yaml

    file = tmp_path_factory.mktemp("generated") / "path.yaml"
    file.write_text(yaml.safe_dump(document))
    code = main(["--robot", "orthoglide", "--path", str(file), "--at", "x=0", "--time-step", "0.01"])
    err = capsys.readouterr().err
    assert code in (0, 2) and "Traceback" not in err and "unexpected" not in err
    assert code == 0 or err.startswith("error: ")


def test_yaml_errors_are_one_line_with_the_place(tmp_path, capsys):
    file = tmp_path / "p.yaml"
    for text, expected in (("units: mm\nshape: {type: circle, radius: 5\nfeed_m_s: 0.66\n", "at line 3, column 9"),
                           ("? [a, b]\n: 1\n", "a key must be a plain name or number at line 1"),
                           ('name: "a\\x1b[31mred"\nunits: mm\n', "field 'name': expected one line of printable text")):
        file.write_text(text)
        code, err = run(["--robot", "orthoglide", "--path", str(file)], capsys)
        assert code == 2 and expected in err and err.count("\n") == 1, err


def test_urdf_and_plugin_mistakes_name_the_file(tmp_path, capsys):
    def spherical(document):
        urdf = tmp_path / "a" / "fivebar" / "fivebar.urdf"
        urdf.write_text(urdf.read_text().replace('type="revolute"', 'type="spherical"', 1))

    sidecar = edited_copy("fivebar", tmp_path / "a", lambda d: None)
    spherical(None)
    code, err = run(["check", str(sidecar)], capsys)
    assert code == 2 and "fivebar.urdf: Pinocchio cannot build a model from it: Joint" in err and err.count("\n") == 1
    loop = edited_copy("fivebar", tmp_path / "b", lambda d: d.update(urdf="loop.urdf"))
    (loop.parent / "loop.urdf").symlink_to(loop.parent / "loop.urdf")
    code, err = run(["check", str(loop)], capsys)
    assert code == 2 and "field 'urdf': cannot follow 'loop.urdf'" in err
    plugin = edited_copy("orthoglide", tmp_path / "c", lambda d: None)
    (plugin.parent / "closed_form.py").write_text("def make_closed_form(model):\n    return None\n")
    code, err = run(["check", str(plugin)], capsys)
    assert code == 2 and "make_closed_form must return a function" in err
    compiled = edited_copy("orthoglide", tmp_path / "d", lambda d: None)
    plugin_file = compiled.parent / "closed_form.py"
    plugin_file.write_text(plugin_file.read_text() + "\n\ndef make_compiled_closed_form(model):\n    return None\n")
    code, err = run(["--robot", str(compiled), "--path", str(EXAMPLE), "--at", "x=0"], capsys)
    assert code == 2 and f"{compiled}, field 'kinematics_plugin': make_compiled_closed_form must return a function" in err


def test_a_missing_mesh_is_named_when_drawing(tmp_path, capsys):
    sidecar = edited_copy("fivebar", tmp_path, lambda d: None)
    urdf = sidecar.parent / "fivebar.urdf"
    urdf.write_text(urdf.read_text().replace("<geometry><box", '<geometry><mesh filename="missing.stl"/></geometry>'
                                             '<geometry><box', 1))
    code, err = run(["--robot", str(sidecar), "--path", str(EXAMPLE.with_name("circle.yaml")), "--at", "x=0",
                     "--html", str(tmp_path / "scene.html")], capsys)
    assert code == 2 and "fivebar.urdf, field 'urdf.link.base.visual': 'missing.stl' names " in err
    assert err.rstrip().endswith("missing.stl, which does not exist") and len(err.strip().splitlines()) == 1


def test_bad_calibration_logs_exit_2_naming_the_column(tmp_path, capsys):
    header = "t,x,y,z,power_slider_x,power_slider_y,power_slider_z\n"
    moving = "".join(f"{k * 0.01},{0.001 * k},0,0,1,1,1\n" for k in range(40))
    cases = {"twice.csv": ("t,x,x,y,z,power_slider_x,power_slider_y,power_slider_z\n" + moving, "'x': the column appears twice"),
             "huge.csv": (header + moving.replace("1,1,1\n", "1e308,1,1\n", 1), "values must be finite numbers below"),
             "still.csv": (header + "".join(f"{k * 0.01},0,0,0,1,1,1\n" for k in range(40)), "shows no motion"),
             "zero.csv": (header + moving.replace("1,1,1", "0,0,0"), "every power value is zero")}
    for name, (text, expected) in cases.items():
        (tmp_path / name).write_text(text)
        code, err = run(["calibrate", "orthoglide", "--log", str(tmp_path / name), "--fit", "resistance_ohm"], capsys)
        assert code == 2 and expected in err, (name, err)
    joints = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
    steady = ",".join(["t"] + [f"q_{j}" for j in joints] + [f"power_{j}" for j in joints]) + "\n" + "".join(
        ",".join(map(str, [k * 0.01] + [-1.0 + 0.001 * k] * 6 + [5.0] * 6)) + "\n" for k in range(40))
    (tmp_path / "steady.csv").write_text(steady)  # every joint at constant speed: nothing shows the rotors' inertia
    code, err = run(["calibrate", "ur5", "--log", str(tmp_path / "steady.csv"), "--fit", "rotor_inertia_kg_m2"], capsys)
    assert code == 2 and "the log does not determine size1.rotor_inertia_kg_m2, size3.rotor_inertia_kg_m2" in err, err
    code, err = run(["calibrate", "orthoglide", "--log", "/dev/zero", "--fit", "resistance_ohm"], capsys)
    assert code == 2 and "not a regular file" in err
    (tmp_path / "fit.svg").write_text(header + moving)
    code, err = run(["calibrate", "orthoglide", "--log", str(tmp_path / "fit.svg"), "--fit", "resistance_ohm",
                     "--png", str(tmp_path / "fit.png")], capsys)
    assert code == 2 and "--png: " in err and "is an input file" in err


def test_more_unclear_inputs_are_named(tmp_path, capsys):
    cases = [(["frobnicate"], "unknown command 'frobnicate': expected one of robots, check, map"),
             (["--robot", "orthoglide", "--path", ""], "empty file name"),
             (["--robot", "orthoglide", "--path", "/dev/zero"], "/dev/zero: not a regular file"),
             (QUICK + ["--path", str(EXAMPLE), "--at", "x=0", "--json", str(tmp_path / ("a" * 300))],
              "--json: the file name is too long"),
             (QUICK + ["--path", str(EXAMPLE), "--at", "x=0", "--show", "--show-host", ""],
              "--show-host: expected an address, got ''")]
    for argv, expected in cases:
        code, err = run(argv, capsys)
        assert code == 2 and expected in err, (argv, err)


def test_a_reader_that_stops_early_ends_the_command_quietly():
    """`placement robots | head -0`: the output's pipe is closed before a line is written; the command stops with
    the shell's code for it, 141, and no error message."""
    read, write = os.pipe()
    os.close(read)
    try:
        done = subprocess.run([sys.executable, "-m", "placement", "robots"], stdout=write, stderr=subprocess.PIPE,
                              text=True, timeout=120)
    finally:
        os.close(write)
    assert (done.returncode, done.stderr) == (141, "")
