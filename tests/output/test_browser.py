"""The static 3-D scene opens offline in a real browser and shows the robot, cube and paths."""

import os

import numpy as np
import pytest
from PIL import Image

from placement.evaluation.evaluator import Evaluator
from placement.kinematics import joint_trajectory
from placement.output.palette import BEST_COLOR, CUBE_COLOR, WORST_COLOR
from placement.output.scene import Scene, find_browser, screenshot
from placement.path import load_path
from placement.placing.transform import transform_path_to_base
from tests.support.paths import EXAMPLE


def count_near(pixels: np.ndarray, color: int, tolerance: int) -> int:
    rgb = np.array([(color >> 16) & 255, (color >> 8) & 255, color & 255])
    return int((np.abs(pixels[..., :3].astype(int) - rgb).max(axis=-1) <= tolerance).sum())


@pytest.fixture(scope="module")
def shot(tmp_path_factory):
    if find_browser() is None:
        if os.environ.get("CI"):  # CI must show that the scene renders: .ci/run installs Chromium
            pytest.fail("no Chromium on the CI machine: the 3-D scene cannot be checked")
        pytest.skip("no Chromium on this machine (.ci/run installs Debian's chromium package)")
    from placement import load_robot

    robot = load_robot("orthoglide")
    evaluator = Evaluator(robot, load_path(EXAMPLE))
    best = evaluator.detail(np.zeros(6))
    worst = evaluator.detail(np.array([-0.095, -0.095, -0.11, np.pi / 4, 0.0, 0.0]))
    scene = Scene(robot)
    scene.add_workspace()
    scene.add_path("best", best.tool_position_m, BEST_COLOR, "least energy")
    scene.add_path("worst", worst.tool_position_m, WORST_COLOR, "most energy")
    task, _ = transform_path_to_base(best.samples, best.placement[None])
    scene.animate(joint_trajectory(robot, task).q, best.samples.t_s)
    folder = tmp_path_factory.mktemp("browser")
    page, image = folder / "scene.html", folder / "scene.png"
    page.write_text(scene.html("test scene"))
    if not screenshot(page, image, size=(900, 650)):
        pytest.fail(f"{find_browser()} wrote no screenshot")
    return np.asarray(Image.open(image).convert("RGB"))


def test_the_scene_is_rendered(shot):
    colors = np.unique(shot.reshape(-1, 3), axis=0)
    assert len(colors) > 200  # a rendered 3-D scene, not a blank or error page


def test_both_paths_and_the_cube_are_drawn(shot):
    assert count_near(shot, BEST_COLOR, 30) > 30
    assert count_near(shot, WORST_COLOR, 30) > 30
    assert count_near(shot, CUBE_COLOR, 30) > 30


def test_the_robot_is_drawn(shot):
    sliders = count_near(shot, 0x3366CC, 60)  # blue slider boxes, shaded
    bars = count_near(shot, 0xD98C1A, 60)  # orange parallelogram bars, shaded
    assert sliders > 500 and bars > 200


def test_show_serves_the_page_on_loopback_only_and_stops(monkeypatch, capsys):
    import io
    import socket
    import urllib.request

    from placement.cli import main
    from placement.output.scene import PageServer

    server = PageServer("<html>scene</html>")
    try:
        assert server.server.server_address[0] == "127.0.0.1"  # no other machine can connect
        with urllib.request.urlopen(server.url, timeout=10) as response:
            assert response.read() == b"<html>scene</html>"
    finally:
        server.close()
    with socket.socket() as probe:  # nothing listens there any more
        assert probe.connect_ex(("127.0.0.1", server.server.server_address[1])) != 0
    monkeypatch.setattr("sys.stdin", io.StringIO("\n"))  # the user presses Enter
    assert main(["--robot", "orthoglide", "--path", str(EXAMPLE), "--at", "x=0", "--time-step", "0.01", "--show"]) == 0
    assert "viewer at http://127.0.0.1:" in capsys.readouterr().out


def test_markup_from_input_files_is_inert_in_the_page(tmp_path):
    from placement import load_robot

    scene = Scene(load_robot("orthoglide"))
    scene.add_path("0_best", np.zeros((3, 3)), BEST_COLOR, "<img src=x onerror=alert(1)>")
    scene.add_label("</script><img src=x onerror=alert(2)>", np.zeros(3), 0)  # a named point's name, on the page
    page = scene.html("<script>alert('path name')</script>")
    assert "<script>alert(" not in page and "<img src=x" not in page and "</script><img" not in page
    assert "&lt;script&gt;alert(&#x27;path name&#x27;)&lt;/script&gt;" in page


def test_the_page_carries_the_answer_as_text(tmp_path, capsys):
    """--html's page shows each placement's energy, where it is and its tightest limit, and the gain, as the report
    prints them: the answer is in a screenshot of the page, not only in the terminal."""
    import html
    import json

    from placement.__main__ import main

    page, result = tmp_path / "scene.html", tmp_path / "result.json"
    assert main(["--robot", "orthoglide", "--path", str(EXAMPLE), "--generations", "6", "--population", "12",
                 "--html", str(page), "--json", str(result), "--quiet"]) == 0
    printed, text = capsys.readouterr().out, html.unescape(page.read_text())
    document = json.loads(result.read_text())
    for key in ("best", "worst"):
        energy = f"{key}: electric energy {document[key]['energy_J']:.4f} J"
        where = next(line.strip() for line in printed.split(f"{key} placement")[1].splitlines() if "x = " in line)
        assert energy in text and f"<div>  {where}</div>" in text
    assert f"gain: {document['gain'] * 100:.1f} % of the energy" in text
