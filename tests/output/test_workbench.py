"""The workbench's model without a page: live readings, the exact value, bounds, choices, a search cancelled."""

import time

import numpy as np
import pytest

from placement import load_robot
from placement.app.evaluations import Bench, Choices
from placement.evaluation.evaluator import Evaluator
from placement.exceptions import PlacementError
from placement.path import load_path
from tests.support.paths import EXAMPLE

AT = np.array([0.0125, -0.007, -0.02, np.radians(30), 0.0, 0.0])


@pytest.fixture(scope="module")
def bench():
    bench = Bench(load_robot("orthoglide"), load_path(EXAMPLE))
    yield bench
    bench.close()


def test_the_exact_value_is_the_at_evaluators(bench):
    expected = Evaluator(bench.robot, load_path(EXAMPLE)).detail(AT)
    assert bench.exact(AT).value == pytest.approx(expected.value, abs=1e-9)


def test_the_live_reading_is_on_the_search_sampling_and_poses_the_robot(bench):
    reading = bench.live(AT)
    assert reading.reachable and reading.feasible
    assert len(reading.t_s) < len(bench.exact_evaluator.samples)  # coarser
    assert reading.configuration.shape == (len(reading.t_s), bench.robot.model.nq)
    assert abs(reading.value - bench.exact(AT).value) / bench.exact(AT).value < 0.05
    assert reading.tightest[0] and np.isfinite(reading.tightest[1])


def test_an_unreachable_placement_says_where_it_fails(bench):
    reading = bench.live(np.array([0.5, 0.5, 0.5, 0.0, 0.0, 0.0]))
    assert not reading.reachable and not reading.feasible and reading.first_unreachable[0] == 0
    assert np.isnan(reading.energy_per_actuator_J).all()
    assert not bench.exact(np.array([0.5, 0.5, 0.5, 0.0, 0.0, 0.0])).reachable


def test_clamp_keeps_the_free_variables_in_their_bounds_and_the_others_fixed(bench):
    clamped = bench.clamp(np.array([1.0, -1.0, 0.0, 4.0, 0.3, 0.2]))
    space = bench.space
    assert np.all(clamped[space.indices] <= space.upper) and np.all(clamped[space.indices] >= space.lower)
    assert clamped[4] == 0.0 and clamped[5] == 0.0  # theta and psi are not free on the Orthoglide


def test_bad_input_raises_placement_error_and_changes_nothing(bench):
    with pytest.raises(PlacementError):
        bench.live(np.array([np.nan, 0, 0, 0, 0, 0]))
    with pytest.raises(PlacementError):
        bench.choose(Choices(regeneration="no such policy"))
    assert bench.choices == Choices()


def test_a_search_is_cancelled_at_once(bench):
    search = bench.search(best=True, worst=False)
    search.cancel()
    assert search.poll() and search.result is None and search.error == "cancelled"
    assert not search.process.is_alive()


def test_the_app_serves_on_loopback_only_prints_its_address_and_stops(monkeypatch, capsys):
    import io
    import socket
    import urllib.request

    from placement.cli import app, build_command_parser, main

    workbench = app.start(build_command_parser().parse_args(["app", "--robot", "orthoglide", "--path", str(EXAMPLE)]))
    try:
        assert workbench.server.get_host() == "127.0.0.1"  # no other machine can connect
        with urllib.request.urlopen(workbench.url, timeout=30) as response:
            assert response.status == 200 and b"<html" in response.read().lower()
    finally:
        workbench.close()
    with socket.socket() as probe:  # nothing listens there any more
        assert probe.connect_ex(("127.0.0.1", workbench.server.get_port())) != 0
    monkeypatch.setattr("sys.stdin", io.StringIO("\n"))  # the user presses Enter
    assert main(["app", "--robot", "orthoglide", "--path", str(EXAMPLE)]) == 0
    assert "workbench at http://127.0.0.1:" in capsys.readouterr().out
    assert main(["app", "--robot", "orthoglide", "--path", str(EXAMPLE), "--host", " "]) == 2
    assert "--host: expected an address" in capsys.readouterr().err


def test_the_gizmo_is_held_to_the_free_variables_and_read_in_the_placement_angles_and_unreachable_is_said():
    from types import SimpleNamespace

    from placement.app.drawing import wxyz_of
    from placement.app.page import Workbench
    from placement.placing.transform import rotation_zyx

    workbench = Workbench(Bench(load_robot("orthoglide"), load_path(EXAMPLE)))
    try:
        workbench.gizmo.position = (0.0125, -0.007, -0.02)
        workbench.gizmo.wxyz = tuple(wxyz_of(rotation_zyx(np.radians(30), np.radians(10), 0.0)))  # theta is fixed at 0
        workbench._gizmo_event(SimpleNamespace(phase="end"))  # let go
        assert np.allclose(workbench.placement, AT, atol=1e-12)
        assert np.allclose(workbench.gizmo.position, AT[:3]) and np.allclose(
            workbench.gizmo.wxyz, wxyz_of(rotation_zyx(np.radians(30), 0.0, 0.0)))  # the gizmo is put back
        assert workbench.exact_detail is not None and workbench.exact_detail.value == pytest.approx(bench_value(AT), abs=1e-9)
        assert float(workbench.fields["phi"].value) == pytest.approx(30.0)
        workbench.gizmo.position = (5.0, 0.0, 0.0)  # far beyond the workspace: held at its bound
        workbench._gizmo_event(SimpleNamespace(phase="update"))
        assert workbench.placement[0] == workbench.bench.space.upper[0]
        for _ in range(600):  # the live reading of that drag is shown by the page's own thread: wait for it
            if workbench.reading is not None and np.array_equal(workbench.reading.placement, workbench.placement):
                break
            time.sleep(0.05)
        assert np.array_equal(workbench.reading.placement, workbench.placement)
        far = np.array([0.5, 0.5, 0.5, 0.0, 0.0, 0.0])  # (beyond the bounds too, as a cell's robot may be)
        workbench._show_live(workbench.bench.live(far))
        workbench._show_exact(workbench.bench.exact(far))
        assert "unreachable" in workbench.live_html.content and "sample 0" in workbench.live_html.content
        assert "unreachable" in workbench.exact_html.content
    finally:
        workbench.close()


def bench_value(placement: np.ndarray) -> float:
    return Evaluator(load_robot("orthoglide"), load_path(EXAMPLE)).detail(placement).value


def test_an_objective_that_needs_the_optimal_law_takes_it_as_the_command_line_does():
    bench = Bench(load_robot("orthoglide"), load_path(EXAMPLE), choices=Choices(objective="cycle_time"))
    try:
        assert bench.path.timing.mode == "optimal" and "optimal" in (bench.note or "")
        reading = bench.live(np.zeros(6))
        assert reading.feasible and 0 < reading.value < bench.exact(np.zeros(6)).value * 1.05
        with pytest.raises(PlacementError, match="optimal"):
            bench.choose(Choices(objective="cycle_time", timing="paper"))
        assert bench.choices.objective == "cycle_time"  # unchanged
    finally:
        bench.close()


def test_the_live_reading_keeps_the_margin_as_the_command_line_does(bench):
    from placement.cli import build_command_parser

    tightest = bench.live(AT).tightest[1]  # the live reading's tightest margin, without a margin asked for
    assert 0.05 < tightest < 0.95
    for margin, feasible in ((tightest - 0.03, True), (tightest + 0.03, False)):
        kept = Bench(load_robot("orthoglide"), load_path(EXAMPLE), margin=margin)
        try:
            assert kept.live(AT).feasible is feasible
            assert kept.live(AT).value == bench.live(AT).value  # the margin changes the verdict, not the value
        finally:
            kept.close()
    args = build_command_parser().parse_args(["app", "--robot", "orthoglide", "--path", str(EXAMPLE), "--margin", "30"])
    assert args.margin == 30.0


def test_a_map_or_a_front_asked_wrongly_is_refused_before_any_work(bench):
    for variables, points in ((("x", "x"), 5), (("x", "theta"), 5), (("x", "y"), 1), (("x", "y"), 102)):
        with pytest.raises(PlacementError, match="map:"):
            bench.map(variables, points, AT)
    with pytest.raises(PlacementError, match="front:"):
        bench.front(("energy", "energy"))


def test_a_map_and_a_front_are_cancelled_at_once(bench):
    job, _ = bench.map(("x", "y"), 51, AT)
    front = bench.front(("energy", "dexterity"))
    for running in (job, front):
        running.cancel()
        assert running.poll() and running.result is None and running.error == "cancelled"
        assert not running.process.is_alive()


def test_the_app_started_with_no_input_serves_until_terminated(tmp_path):
    """In the background (no input: nohup, a service) the workbench keeps serving instead of stopping at once, and a
    terminate signal stops it cleanly."""
    import signal
    import subprocess
    import sys
    import urllib.request

    server = subprocess.Popen([sys.executable, "-m", "placement", "app", "--robot", "orthoglide", "--path", str(EXAMPLE)],
                              stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = server.stdout.readline()
        while line and "workbench at" not in line:
            line = server.stdout.readline()
        url = line.split("workbench at ", 1)[1].split()[0]
        time.sleep(3)  # the input has ended long since
        assert server.poll() is None
        with urllib.request.urlopen(url, timeout=30) as response:
            assert response.status == 200
        server.send_signal(signal.SIGTERM)
        assert server.wait(timeout=60) == 0
    finally:
        server.kill()
        server.communicate()


@pytest.fixture(scope="module")
def served():
    """A workbench served on loopback (its gate's token known to the test, as the printed address gives it)."""
    from placement.app.page import Workbench

    workbench = Workbench(Bench(load_robot("orthoglide"), load_path(EXAMPLE)))
    try:
        yield workbench
    finally:
        workbench.close()


def _status(port: int, host: str, origin: str | None = None, cookie: str | None = None, path: str = "/",
            websocket: bool = False) -> int:
    """The HTTP status a raw request (or websocket handshake) with these headers gets."""
    import socket

    lines = [f"GET {path} HTTP/1.1", f"Host: {host}"]
    lines += [f"Origin: {origin}"] if origin else []
    lines += [f"Cookie: {cookie}"] if cookie else []
    if websocket:
        lines += ["Upgrade: websocket", "Connection: Upgrade", "Sec-WebSocket-Version: 13",
                  "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==", "Sec-WebSocket-Protocol: viser-v0"]
    with socket.create_connection(("127.0.0.1", port), timeout=30) as connection:
        connection.sendall(("\r\n".join(lines) + "\r\n\r\n").encode())
        return int(connection.recv(256).split(b" ", 2)[1])


def test_only_this_machines_page_with_the_token_is_served(served):
    port, token = served.server.get_port(), served.gate.token
    own, cookie = f"127.0.0.1:{port}", f"{served.gate.cookie}={token}"
    assert _status(port, own, path=f"/?token={token}") == 200  # the printed address
    assert _status(port, f"localhost:{port}", path=f"/?token={token}") == 200
    assert _status(port, own) == 403  # no token
    assert _status(port, own, path="/?token=guess") == 403
    assert _status(port, f"evil.example:{port}", path=f"/?token={token}") == 403  # DNS rebinding
    assert _status(port, own, origin="http://evil.example", path=f"/?token={token}") == 403
    assert _status(port, own, origin=f"http://{own}", cookie=cookie, websocket=True) == 101  # the page's own socket
    assert _status(port, own, origin="http://evil.example", cookie=cookie, websocket=True) == 403
    assert _status(port, f"evil.example:{port}", origin=f"http://evil.example:{port}", cookie=cookie,
                   websocket=True) == 403
    assert _status(port, own, origin=f"http://{own}", websocket=True) == 403  # no cookie: another local page
    assert any("Origin 'http://evil.example'" in why for why in served.gate.refused)


def test_every_answer_forbids_framing_and_sniffing(served):
    import urllib.request

    with urllib.request.urlopen(served.url, timeout=30) as response:
        headers = response.headers
        assert headers["X-Frame-Options"] == "DENY" and "frame-ancestors 'none'" in headers["Content-Security-Policy"]
        assert headers["X-Content-Type-Options"] == "nosniff" and headers["Referrer-Policy"] == "no-referrer"
        assert "HttpOnly" in headers["Set-Cookie"] and "SameSite=Strict" in headers["Set-Cookie"]


def test_a_share_request_is_refused_and_a_malformed_frame_logged_in_one_line(served, caplog):
    import logging

    import msgspec
    import viser
    from websockets.exceptions import ConnectionClosedError
    from websockets.sync.client import connect

    from placement.app.guard import GuardedServer

    own = f"127.0.0.1:{served.server.get_port()}"
    before = GuardedServer.share_refusals
    with caplog.at_level(logging.WARNING):
        with connect(f"ws://{own}/", origin=f"http://{own}", subprotocols=[f"viser-v{viser.__version__}"],
                     additional_headers={"Cookie": f"{served.gate.cookie}={served.gate.token}"}) as socket:
            socket.send(msgspec.msgpack.encode({"type": "ShareUrlRequest"}))
            for _ in range(100):
                if GuardedServer.share_refusals > before:
                    break
                time.sleep(0.1)
            socket.send(b"\xc1 not a message")
            with pytest.raises(ConnectionClosedError):  # the server closes the connection
                for _ in range(1000):
                    socket.recv(timeout=30)
    assert GuardedServer.share_refusals == before + 1
    assert served.server._share_tunnel is None  # no tunnel was opened
    assert any("share" in record.getMessage() for record in caplog.records)
    failed = [record for record in caplog.records if "connection handler failed" in record.getMessage()]
    assert failed and all("\n" not in record.getMessage() and record.exc_info is None for record in failed)


def test_typed_values_are_read_literally_on_enter_and_a_bound_is_named_with_the_text_kept(served):
    from types import SimpleNamespace

    start = served.placement.copy()
    x_upper = served.bench.space.upper[served.bench.space.free.index("x")] * 1e3
    served.fields["x"].value = "1e3"  # 1000 mm: beyond the Orthoglide's x bound
    with pytest.raises(PlacementError, match=f"x = 1e3 mm is above its upper bound {x_upper:.6g} mm"):
        served._fields_given()
    assert served.fields["x"].value == "1e3" and np.array_equal(served.placement, start)  # kept, not moved
    served.fields["x"].value = "1.25e1"
    served._fields_given()  # Enter
    assert served.placement[0] == 0.0125 and served.fields["x"].value == "1.25e1"  # read as typed, not written back
    assert served.exact_detail.value == pytest.approx(bench_value(served.placement), abs=1e-9)
    served.fields["y"].value = "abc"
    with pytest.raises(PlacementError, match="y: 'abc' is not a number of mm"):
        served._fields_given()
    served.set_placement(served.placement, exact=False)  # the page writes the fields back (a drag, Go to best)
    served._typed(SimpleNamespace(client=object()))  # a key: read once typing pauses, never written back
    assert served._typing is not None
    served._fields_given()
    served.at_text.value = "z=-20"  # --at: the values left out keep the current ones
    served._at_given()
    assert np.allclose(served.placement, [0.0125, start[1], -0.02, *start[3:]], atol=1e-15)


def test_an_infeasible_placement_turns_the_workpiece_red_and_marks_its_failing_sample(served):
    from placement.app.page import FAILING_COLOR, PATH_COLOR

    served.set_placement(AT, exact=False)
    assert served.reading.feasible and np.all(served.path_line.colors == PATH_COLOR)
    assert not served.failing_mark.visible
    far = served.bench.clamp(np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]))  # a corner of the bounds
    served.set_placement(far, exact=False)
    reading = served.reading
    assert not reading.feasible and np.all(served.path_line.colors == FAILING_COLOR) and served.failing_mark.visible
    sample = reading.first_unreachable[0] if not reading.reachable else reading.tightest_sample
    assert np.allclose(served.failing_mark.position, reading.tool_position_m[sample])
    served.set_placement(AT, exact=False)
    assert np.all(served.path_line.colors == PATH_COLOR) and not served.failing_mark.visible


def test_a_value_typed_back_to_what_the_page_wrote_before_is_read(served):
    served.set_placement(AT, exact=False)  # the page writes x = 12.5
    served.fields["x"].value = "-30"
    served._fields_given()
    assert served.placement[0] == -0.03
    served.fields["x"].value = "12.5"  # the text the page wrote before, typed again
    served._fields_given()
    assert served.placement[0] == 0.0125


def test_a_number_is_shown_to_five_significant_digits_with_its_full_value_kept():
    from placement.app.compare import relative_change_percent
    from placement.app.numbers import number_html, readable

    value = 4.801071042626315
    assert readable(value) == "4.8011" and readable(-0.00123456789) == "-0.0012346" and readable(np.nan) == "-"
    shown = number_html("exact-value", value, "J")
    full = shown.split('data-value="')[1].split('"')[0]
    assert float(full) == value and shown.endswith(">4.8011</span> J")  # the full value survives the page
    assert relative_change_percent(4.0, 5.0) == pytest.approx(25.0, abs=1e-12)
    assert relative_change_percent(-4.0, -5.0) == pytest.approx(-25.0, abs=1e-12)  # of the pinned value's size
    assert np.isnan(relative_change_percent(0.0, 1.0))


def test_a_map_the_placement_left_is_marked_stale_and_a_panels_error_is_said_beside_it(served):
    from types import SimpleNamespace

    panel = served.map
    served.set_placement(AT, exact=False)
    panel.has_result, panel.through, panel.plane = True, served.placement.copy(), ("x", "y")  # a map over x, y
    served.set_placement(AT + [0.001, -0.001, 0, 0, 0, 0], exact=False)  # within the map's plane
    assert "stale" not in panel.state.content
    served.set_placement(AT + [0, 0, 0.001, 0, 0, 0], exact=False)  # off it
    assert "stale: the placement left the plane of this map (z moved)" in panel.state.content
    panel.points.value = "1"
    served.message.content = ""
    served.acted(SimpleNamespace(client=None), panel._start, beside=panel)
    assert "points per variable" in panel.state.content and "color:#c00" in panel.state.content
    assert served.message.content == "" and panel.job is None  # said beside the Map panel, nothing started
    panel.points.value = "21"


def test_a_search_says_what_it_does_before_its_first_generation(bench):
    """The page's Optimise says its stage (never a silent 0 %): the kernels warming, then the first population's
    scan with the time it expects, both before the first generation is counted."""
    from placement.app.jobs import WARMING, search_task
    from placement.search.optimize import SearchSettings

    said: list[str] = []
    settings = SearchSettings(best=True, worst=False, population=8, max_generations=2)
    search_task(bench.robot, bench.path, bench.space, bench.settings, settings,
                progress=lambda steps: said.append(f"{steps} generation"), stage=said.append)
    assert said[0] == WARMING and said[1].startswith("scanning the first population (about ")
    assert said[2:] == ["1 generation"] * (len(said) - 2) and len(said) >= 3


def test_a_jobs_stage_is_read_from_its_process(bench):
    from placement.app.jobs import STARTING, WARMING

    job, _ = bench.map(("x", "y"), 2, AT)
    assert job.stage == STARTING  # before its process says anything
    job.wait()
    assert job.result is not None and job.stage == WARMING.split(" and ")[0]  # the map's last word before its steps


def test_a_short_pass_is_played_slowed_down_to_a_few_seconds():
    from fractions import Fraction

    from placement.app.motion import PASS_SHOWN_S, playback_speed

    assert playback_speed(0.27) == Fraction(1, 16)  # 4.3 s; at 1/8 it would last 2.2 s
    assert playback_speed(10.0) == 1 and playback_speed(1e-3) == Fraction(1, 64)
    for duration_s in (0.01, 0.27, 0.5, 1.0, 2.9, 3.0, 7.0):
        speed = playback_speed(duration_s)
        assert duration_s / speed >= PASS_SHOWN_S or speed == Fraction(1, 64)
        assert speed == 1 or duration_s / (2 * speed) < PASS_SHOWN_S  # the fastest that is slow enough


def test_the_power_plot_shows_the_time_as_a_cursor_and_each_curve_unchanged(served):
    from placement.app.motion import power_with_cursor

    detail = served.exact_detail
    t_s, power_W = np.asarray(detail.samples.t_s, dtype=float), np.asarray(detail.power_W, dtype=float)
    now_s = 0.4 * t_s[-1]
    times, *curves, cursor = power_with_cursor(t_s, power_W, now_s)
    assert np.all(np.diff(times) >= 0) and len(curves) == power_W.shape[1]
    drawn = np.flatnonzero(np.isfinite(cursor))  # two points, one above the other: a vertical line
    assert len(drawn) == 2 and times[drawn[0]] == times[drawn[1]] == t_s[np.searchsorted(t_s, now_s)]
    assert cursor[drawn].tolist() == [np.nanmin(power_W), np.nanmax(power_W)]
    unique = np.delete(np.arange(len(times)), drawn[1])  # the repeated sample taken out: the curves as computed
    assert np.array_equal(times[unique], t_s)
    for i, curve in enumerate(curves):
        assert np.array_equal(curve[unique], power_W[:, i], equal_nan=True)
    served.time.value = now_s
    served.guard(served._show_time)  # the page's plot: the same data, the cursor at the time shown
    shown = served.power_plot.data
    assert np.array_equal(shown[-1], cursor, equal_nan=True) and np.array_equal(shown[0], times)
    low, high = served.power_plot.scales["y"]["range"]  # fixed (uPlot ranges no axis over NaN), every curve within
    assert low < np.nanmin(power_W) and np.nanmax(power_W) < high


def test_a_drag_snaps_to_whole_millimetres_and_degrees_when_asked(served):
    from types import SimpleNamespace

    from placement.app.drawing import wxyz_of
    from placement.placing.transform import rotation_zyx

    served.snap.value = True
    try:
        served.gizmo.position = (0.01234, -0.00678, -0.0201)
        served.gizmo.wxyz = tuple(wxyz_of(rotation_zyx(np.radians(30.4), 0.0, 0.0)))
        served._gizmo_event(SimpleNamespace(phase="end"))
    finally:
        served.snap.value = False
    snapped = np.array([0.012, -0.007, -0.020, np.radians(30.0), 0.0, 0.0])
    assert np.allclose(served.placement, snapped, rtol=0, atol=1e-15)
    assert served.exact_detail.value == pytest.approx(bench_value(snapped), abs=1e-9)  # evaluated where it snapped
    assert served.fields["x"].value == "12" and served.fields["phi"].value == "30"


def test_undo_goes_back_through_the_placements_evaluated(served):
    from placement.app.page import UNDO_DEPTH

    placements = [np.array([x, 0.0, -0.02, 0.0, 0.0, 0.0]) for x in (-0.01, 0.0, 0.01)]
    for placement in placements:
        served.set_placement(placement, exact=True)
    served.undo()
    assert np.array_equal(served.placement, placements[1])
    assert served.exact_detail.value == pytest.approx(bench_value(placements[1]), abs=1e-9)
    served.undo()
    assert np.array_equal(served.placement, placements[0])
    for k in range(UNDO_DEPTH + 5):
        served.set_placement(np.array([0.001 * k, 0.0, -0.02, 0.0, 0.0, 0.0]), exact=True)
    assert len(served.history) == UNDO_DEPTH  # the last ones kept
    served.history.clear()
    served.guard(served.undo)
    assert "nothing to undo" in served.message.content


def test_the_map_is_drawn_in_the_scene_and_a_cell_clicked_goes_to_its_placement(served):
    from placement.search.sweep import sweep

    through = np.array([0.0, 0.0, -0.02, 0.0, 0.0, 0.0])
    served.set_placement(through, exact=True)
    axes = {"x": np.linspace(-0.03, 0.03, 4), "y": np.linspace(-0.02, 0.02, 3)}
    result = sweep(served.bench.robot, served.bench.path, axes, {"z": -0.02, "phi": 0.0, "theta": 0.0, "psi": 0.0},
                   evaluation=served.bench.settings)
    heat_map = served.map.heat_map
    served.map.finished(result)
    assert heat_map.result is result and "click a cell" in served.map.best_html.content
    # cells one grid step apart in the scene (m), in the flattened order of the map's placements
    assert np.linalg.norm(heat_map.steps, axis=1) == pytest.approx([0.02, 0.02], abs=1e-12)
    colors = heat_map.cells.batched_colors
    best = result.best()
    assert colors[best].tolist() == [0, 34, 78]  # cividis' navy end: the least energy
    assert (colors[~result.feasible.ravel()] == 190).all()
    assert np.allclose(heat_map.best_mark.position, heat_map.origins[best]) and heat_map.best_mark.visible
    assert heat_map.current_mark.visible  # the current placement is on the map's plane
    normal = np.cross(*heat_map.steps) / np.linalg.norm(np.cross(*heat_map.steps))
    cell = 7  # x index 2, y index 1
    aim = heat_map.origins[cell] + 0.3 * heat_map.steps[0] - 0.3 * heat_map.steps[1]  # inside the cell, off centre
    heat_map.clicked(tuple(aim + 0.5 * normal), tuple(-normal))
    assert np.array_equal(served.placement, result.placements()[cell])
    assert served.exact_detail.value == pytest.approx(result.value.ravel()[cell], abs=1e-9)  # the map's own value
    assert heat_map.cell_at(heat_map.origins[0] - heat_map.steps[0] + 0.5 * normal, -normal) is None  # off the map
    served.set_placement(np.array([0.0, 0.0, -0.01, 0.0, 0.0, 0.0]), exact=True)  # off the plane: unmarked
    assert not heat_map.current_mark.visible
    angled = sweep(served.bench.robot, served.bench.path, {"x": axes["x"], "phi": np.radians([-10.0, 10.0])},
                   {"y": 0.0, "z": -0.02, "theta": 0.0, "psi": 0.0}, evaluation=served.bench.settings)
    served.map.finished(angled)  # over an angle: no plane of the scene
    assert heat_map.cells is None and "drawn here only" in served.map.best_html.content


def _ghost_result(served, placements):
    """An Optimise result whose best and worst are these placements, each evaluated as --at evaluates it."""
    from placement.search.optimize import Optimum, PlacementResult

    def optimum(placement):
        return Optimum(Evaluator(served.bench.robot, load_path(EXAMPLE)).detail(placement), 0.0, 0.0, "", 1)

    return PlacementResult(optimum(placements["best"]), optimum(placements["worst"]), served.bench.space, "energy",
                           served.bench.choices.regeneration)


def test_an_optimise_result_is_drawn_as_ghosts_at_its_best_and_worst_each_hidden_by_its_toggle(served):
    import pinocchio as pin

    from placement.app.drawing import wxyz_of
    from placement.placing.transform import placement_pose

    robot = served.bench.robot
    placements = {"best": AT, "worst": np.array([-0.01, 0.008, -0.03, np.radians(-20), 0.0, 0.0])}
    served.optimise.finished(_ghost_result(served, placements))
    ghosts = served.optimise.ghosts
    data, visual = robot.model.createData(), ghosts.drawings["best"].visual
    geometry_data = visual.createData()
    for key, placement in placements.items():
        drawing, path = ghosts.drawings[key], ghosts.paths[key]
        assert drawing.visible and path.visible and ghosts.toggles[key].visible
        rotation, origin = placement_pose(placement, robot.plane)
        expected = Evaluator(robot, load_path(EXAMPLE)).detail(placement)  # as --at evaluates it
        start = rotation[0] @ expected.samples.position_m[0] + origin[0]  # the path's start, placed
        q = expected.configuration[0]
        pin.framesForwardKinematics(robot.model, data, q)
        assert np.allclose(data.oMf[robot.end_effector_frame_id].translation, start, atol=1e-9)  # the tool on it
        pin.updateGeometryPlacements(robot.model, data, visual, geometry_data)
        for k, handle in drawing.handles:  # every body of the ghost where the robot's kinematics put it there
            assert np.allclose(handle.position, geometry_data.oMg[k].translation, atol=1e-9)
            assert abs(abs(np.dot(handle.wxyz, wxyz_of(geometry_data.oMg[k].rotation))) - 1) < 1e-9
        assert np.allclose(path.points[0, 0], start, atol=1e-6)  # float32 in viser
        assert not np.allclose(drawing.handles[-1][1].position, served.drawing.handles[-1][1].position)  # not the live one
    ghosts.toggles["worst"].value = False
    ghosts._apply("worst")  # as the checkbox's callback does
    assert not ghosts.drawings["worst"].visible and not ghosts.paths["worst"].visible
    assert ghosts.drawings["best"].visible and ghosts.paths["best"].visible
    served.optimise.forget()  # the choices changed: the optima no longer answer them
    assert not ghosts.drawings["best"].visible and not ghosts.paths["best"].visible
    assert not ghosts.toggles["best"].visible
    ghosts.toggles["worst"].value = True


def test_a_serial_arm_is_drawn_in_the_palettes_blue_more_opaque_than_a_parallel_robot():
    import viser

    from placement.app.drawing import ARM_OPACITY, PARALLEL_OPACITY, RobotDrawing
    from placement.output.palette import ARM_COLOR, BEST_COLOR, WORST_COLOR, rgb_255

    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        drawing = RobotDrawing(server, load_robot("ur5_track"))  # a serial arm with a tool (no shape of its own)
        assert {tuple(handle.color) for _, handle in drawing.handles} == {rgb_255(ARM_COLOR)}  # the URDF's white
        assert {handle.opacity for _, handle in drawing.handles} == {ARM_OPACITY} and ARM_OPACITY > PARALLEL_OPACITY
        assert rgb_255(ARM_COLOR) not in {(230, 0, 200), rgb_255(BEST_COLOR), rgb_255(WORST_COLOR)}
    finally:
        server.stop()
