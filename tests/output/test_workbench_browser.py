"""The workbench page in a real browser: headless Chromium driven through WebDriver (selenium, chromium-driver).

The page is set and read as a user would: numbers typed into its fields, buttons clicked, values
read from the page's text. Its exact value equals what ``--at`` prints, its search finds the
command line's best, its comparison of two placements is the difference of what ``--at`` prints
at each, its export downloads the document ``--json --at`` writes, its map's best cell is the
``map`` command's and its Pareto front's members are ``--objectives``'. Without a browser the
tests skip, except under CI (``CI`` set), where they fail.
"""

import dataclasses
import json
import os
import shlex
import shutil
import time

import pytest

from tests.support.paths import EXAMPLE

pytestmark = pytest.mark.slow  # about a minute on a 2-core machine: starts first under -n 2

PLACEMENT = {"x": "12.5", "y": "-7", "z": "-20", "phi": "30"}  # mm, degrees
# The page's searches and the command line's run on this smaller budget than the default (48 x 80): they must
# find the same placements and fronts whatever the budget.
BUDGET = {"population": 24, "max_generations": 10}
BUDGET_OPTIONS = ("--population", str(BUDGET["population"]), "--generations", str(BUDGET["max_generations"]))


REBOUND = "rebound.example"  # a foreign name the browser resolves to this machine, as DNS rebinding would


def _unavailable(reason: str) -> None:
    if os.environ.get("CI"):  # CI must show the workbench works: .ci/run installs chromium and chromium-driver
        pytest.fail(f"{reason} on the CI machine: the workbench cannot be checked in a browser")
    pytest.skip(f"{reason} on this machine (.ci/run installs Debian's chromium and chromium-driver)")


@pytest.fixture(scope="module")
def workbench():
    pytest.importorskip("viser") if not os.environ.get("CI") else None
    from placement.cli import app, build_command_parser
    from placement.search.optimize import SearchSettings

    args = build_command_parser().parse_args(["app", "--robot", "orthoglide", "--path", str(EXAMPLE)])
    bench = app.start(args)
    assert bench.bench.search_settings == SearchSettings(seed=0)  # the command line's defaults
    bench.bench.search_settings = dataclasses.replace(bench.bench.search_settings, **BUDGET)
    try:
        yield bench
    finally:
        bench.close()


@pytest.fixture(scope="module")
def downloads(tmp_path_factory):
    return tmp_path_factory.mktemp("downloads")


def open_page(url: str, downloads=None):
    """Headless Chromium on ``url``, its first exact value shown (downloads into ``downloads``)."""
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        _unavailable("no selenium")
    chromium = next((shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome") if shutil.which(n)), None)
    driver_path = shutil.which("chromedriver")
    if chromium is None or driver_path is None:
        _unavailable("no Chromium or no chromedriver")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
                 "--use-angle=swiftshader", "--window-size=1400,1000", "--proxy-server=127.0.0.1:9",
                 f"--host-resolver-rules=MAP {REBOUND} 127.0.0.1", f"--proxy-bypass-list={REBOUND}"):
        options.add_argument(flag)
    driver = webdriver.Chrome(options=options, service=Service(driver_path))
    if downloads is not None:
        driver.execute_cdp_cmd("Browser.setDownloadBehavior", {"behavior": "allow", "downloadPath": str(downloads)})
    driver.get(url)
    try:
        wait_for(driver, lambda: text_of(driver, "exact-value") is not None, "the page's first exact value")
    except BaseException:
        driver.quit()
        raise
    return driver


@pytest.fixture(scope="module")
def browser(workbench, downloads):
    driver = open_page(workbench.url, downloads)
    try:
        yield driver
    finally:
        driver.quit()


def text_of(driver, element_id: str) -> str | None:
    """The element's text, read at once in the page (never a stale element: the page replaces its panels)."""
    return driver.execute_script("const found = document.getElementById(arguments[0]);"
                                 "return found === null ? null : found.textContent.trim();", element_id)


def wait_for(driver, condition, what: str, timeout_s: float = 120.0) -> None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            if condition():
                return
        except Exception:  # an element replaced while it was read: read again
            pass
        time.sleep(0.2)
    pytest.fail(f"the page never showed {what}")


def field_of(driver, label: str):
    from selenium.webdriver.common.by import By

    return driver.find_element(By.XPATH, f"//label[normalize-space()='{label}']/following::input[1]")


def type_into(driver, label: str, text: str) -> None:
    """Type ``text`` into the field labelled ``label`` and press Enter, all keys at once, faster than any person.

    viser's page (1.1) sends the GUI's messages through one sender that keeps only the latest message of each
    50 ms: the last keys and the Enter reach the server as the Enter alone. The page reads the typed text
    from the tab when it acts (:mod:`placement.app.shown`), so every test typing this way shows it.
    """
    from selenium.webdriver.common.keys import Keys

    field = field_of(driver, label)
    field.click()
    field.send_keys(Keys.CONTROL, "a", Keys.NULL, Keys.BACKSPACE, text, Keys.ENTER)


def click(driver, text: str) -> None:
    from selenium.webdriver.common.by import By

    driver.find_element(By.XPATH, f'//button[normalize-space()="{text}"]').click()


def open_folder(driver, title: str, control: str) -> None:
    """Unfold the page's folder ``title`` unless its button ``control`` is in sight already."""
    from selenium.webdriver.common.by import By

    button = f"//button[normalize-space()='{control}']"
    if not any(found.is_displayed() for found in driver.find_elements(By.XPATH, button)):
        driver.find_element(By.XPATH, f"//div[contains(@class, 'mantine-Paper-root') and normalize-space(text())="
                                      f"'{title}']").click()
    wait_for(driver, lambda: driver.find_element(By.XPATH, button).is_displayed(), f"the {title} folder open")


def number_of(driver, element_id: str) -> float:
    """A number the page shows, in full: its element's ``data-value`` (the page writes five significant digits)."""
    return float(driver.execute_script("return document.getElementById(arguments[0]).dataset.value;", element_id))


def set_placement(driver, placement: dict[str, str], expected_J: float) -> None:
    for name, value in placement.items():
        type_into(driver, f"{name} ({'deg' if name in ('phi', 'theta', 'psi') else 'mm'})", value)
    wait_for(driver, lambda: abs(number_of(driver, "exact-value") - expected_J) <= 1e-9,
             f"the --at energy {expected_J!r} J (last read: {text_of(driver, 'exact-value')})")


def at(placement: dict[str, str]) -> str:
    return ",".join(f"{k}={v}" for k, v in placement.items())


def same_numbers(page, cli, where: str = "") -> None:
    """Two JSON documents alike: the same keys and texts, numbers equal to 1e-9."""
    if isinstance(cli, dict):
        assert isinstance(page, dict) and set(page) == set(cli), where
        for key in cli:
            same_numbers(page[key], cli[key], f"{where}.{key}")
    elif isinstance(cli, list):
        assert isinstance(page, list) and len(page) == len(cli), where
        for k, (a, b) in enumerate(zip(page, cli)):
            same_numbers(a, b, f"{where}[{k}]")
    elif isinstance(cli, float) and not isinstance(cli, bool):
        assert page == pytest.approx(cli, abs=1e-9), where
    else:
        assert page == cli, where


def cli_json(tmp_path, *options: str) -> dict:
    from placement.cli import main

    out = tmp_path / "out.json"
    assert main(["--robot", "orthoglide", "--path", str(EXAMPLE), "--quiet", "--json", str(out), *options]) == 0
    return json.loads(out.read_text())


def test_a_placement_typed_in_the_page_reads_the_energy_at_prints(browser, tmp_path):
    expected = cli_json(tmp_path, "--at", ",".join(f"{k}={v}" for k, v in PLACEMENT.items()))["at"]["energy_J"]
    for name, value in PLACEMENT.items():
        type_into(browser, f"{name} ({'deg' if name == 'phi' else 'mm'})", value)
    wait_for(browser, lambda: abs(number_of(browser, "exact-value") - expected) <= 1e-9,
             f"the --at energy {expected!r} J (last read: {text_of(browser, 'exact-value')})")
    assert text_of(browser, "exact-at") == "at x=12.5,y=-7,z=-20,phi=30,theta=0,psi=0"  # every value typed was read
    assert "feasible" in (text_of(browser, "live-value") or "")


def test_values_typed_across_the_fields_at_once_are_all_read(browser, tmp_path):
    """x, Tab, y, Tab, z, Tab, phi and Enter in one burst of keys: each field's last keys are followed within
    50 ms by the next field's (viser's page sends the latter alone), yet the page evaluates every value typed."""
    from selenium.webdriver.common.keys import Keys

    typed = {"x": "-25.5", "y": "14", "z": "-1e1", "phi": "-12.25"}
    expected = cli_json(tmp_path, "--at", at({**typed, "z": "-10"}))["at"]["energy_J"]
    keys = []
    for name in typed:
        keys += [Keys.CONTROL, "a", Keys.NULL, Keys.BACKSPACE, typed[name], Keys.TAB]
    field = field_of(browser, "x (mm)")
    field.click()
    field.send_keys(*keys[:-1], Keys.ENTER)
    wait_for(browser, lambda: text_of(browser, "exact-at") == "at x=-25.5,y=14,z=-10,phi=-12.25,theta=0,psi=0",
             f"every value typed evaluated (last: {text_of(browser, 'exact-at')})")
    assert abs(number_of(browser, "exact-value") - expected) <= 1e-9
    assert [field_text(browser, f"{name} ({'deg' if name == 'phi' else 'mm'})") for name in typed] == list(typed.values())


def test_bad_input_is_answered_in_the_page(browser):
    type_into(browser, "--at", "x=abc")
    click(browser, "Evaluate")
    wait_for(browser, lambda: "not a number" in (text_of(browser, "message") or ""), "a message about 'abc'")
    type_into(browser, "--at", "x=1e6")  # far outside the workspace: said, not evaluated
    click(browser, "Evaluate")
    wait_for(browser, lambda: "outside the bounds" in (text_of(browser, "message") or ""), "a message about the bounds")
    type_into(browser, "x (mm)", "5")  # the page still answers (5 mm: a new value, whatever ran before)
    wait_for(browser, lambda: not text_of(browser, "message"), "the message cleared by a valid value")


def test_optimise_in_the_page_finds_the_command_lines_best(browser, tmp_path):
    expected = cli_json(tmp_path, *BUDGET_OPTIONS)["best"]["objective"]["value"]
    click(browser, "Optimise")
    wait_for(browser, lambda: text_of(browser, "best-value") is not None, "the search's best", timeout_s=600)
    assert abs(number_of(browser, "best-value") - expected) <= 1e-9
    click(browser, "Go to best")
    wait_for(browser, lambda: abs(number_of(browser, "exact-value") - expected) <= 1e-9,
             f"the best placement's energy {expected!r} J after 'Go to best'")


OTHER = {"x": "-30", "y": "20", "z": "-10", "phi": "-15"}  # mm, degrees


def test_pinned_and_current_placements_differ_by_what_at_prints_at_each(browser, tmp_path):
    first = cli_json(tmp_path, "--at", at(PLACEMENT))["at"]
    second = cli_json(tmp_path, "--at", at(OTHER))["at"]
    set_placement(browser, PLACEMENT, first["energy_J"])
    open_folder(browser, "Compare", "Pin this placement")
    click(browser, "Pin this placement")
    wait_for(browser, lambda: abs(number_of(browser, "compare-energy-pinned") - first["energy_J"]) <= 1e-9,
             "the pinned energy")
    set_placement(browser, OTHER, second["energy_J"])
    wait_for(browser, lambda: abs(number_of(browser, "compare-energy-current") - second["energy_J"]) <= 1e-9,
             "the current energy beside the pinned one")
    expected = {"energy": second["energy_J"] - first["energy_J"],
                "cycle-time": second["cycle_time_s"] - first["cycle_time_s"],
                "margin": 100 * (min(m["margin"] for m in second["margins"]) - min(m["margin"] for m in first["margins"])),
                **{f"energy-{joint}": second["energy_per_actuator_J"][joint] - first["energy_per_actuator_J"][joint]
                   for joint in first["energy_per_actuator_J"]}}
    for key, difference in expected.items():
        assert number_of(browser, f"compare-{key}-difference") == pytest.approx(difference, abs=1e-9), key
    assert expected["energy"] != pytest.approx(0.0, abs=1e-3)  # two placements that differ
    percent = 100 * expected["energy"] / first["energy_J"]
    assert number_of(browser, "compare-energy-percent") == pytest.approx(percent, abs=1e-9)
    assert text_of(browser, "compare-energy-percent") == format(percent, ".3g")  # in %, to three digits
    assert text_of(browser, "compare-energy-current") == format(second["energy_J"], ".5g")  # five digits


def test_export_downloads_what_json_at_writes(browser, downloads, tmp_path):
    expected = cli_json(tmp_path, "--at", at(PLACEMENT))
    set_placement(browser, PLACEMENT, expected["at"]["energy_J"])
    open_folder(browser, "Export", "Export JSON")
    click(browser, "Export JSON")
    file = downloads / "placement.json"
    wait_for(browser, lambda: file.is_file() and json.loads(file.read_text()), "the downloaded placement.json")
    same_numbers(json.loads(file.read_text()), expected)
    same_numbers(json.loads(text_of(browser, "export-json")), expected)


def test_the_maps_best_cell_is_the_map_commands(browser, tmp_path):
    import numpy as np

    from placement.cli import main
    from placement.search.sweep import SweepResult

    open_folder(browser, "Map", "Map")
    type_into(browser, "points per variable", "7")
    click(browser, "Map")
    wait_for(browser, lambda: text_of(browser, "map-state") == "done", "the map done", timeout_s=600)
    command = text_of(browser, "map-command").split("--path FILE", 1)[1]
    out = tmp_path / "map.npz"
    assert main(["map", "--robot", "orthoglide", "--path", str(EXAMPLE), *shlex.split(command), "--out", str(out),
                 "--quiet"]) == 0
    cli = SweepResult.load(out)
    assert cli.value.shape == (7, 7)
    value = np.where(cli.feasible, cli.value, np.inf)
    best = int(np.argmin(value))  # least energy among the feasible placements
    assert np.isfinite(value.flat[best])
    assert number_of(browser, "map-best-value") == pytest.approx(value.flat[best], abs=1e-9)
    click(browser, "Go to the map's best")
    wait_for(browser, lambda: abs(number_of(browser, "exact-value") - value.flat[best]) <= 1e-9,
             "the map's best placement's energy after 'Go to the map's best'")


def test_the_fronts_members_are_those_of_objectives(browser, tmp_path):
    expected = cli_json(tmp_path, "--objectives", "energy,dexterity", *BUDGET_OPTIONS)
    open_folder(browser, "Front", "Search the front")
    click(browser, "Search the front")
    wait_for(browser, lambda: (text_of(browser, "front-state") or "").startswith("done"), "the front", timeout_s=900)
    members = expected["members"]
    assert text_of(browser, f"front-{len(members) - 1}-0") is not None and text_of(browser, f"front-{len(members)}-0") is None
    for i, member in enumerate(members):
        for k, name in enumerate(expected["objectives"]):
            assert number_of(browser, f"front-{i}-{k}") == pytest.approx(member["values"][name], abs=1e-9), (i, name)
    click(browser, "Go to member")  # the knee, chosen at first
    knee = members[expected["knee"]]["values"]["energy"]
    wait_for(browser, lambda: abs(number_of(browser, "exact-value") - knee) <= 1e-9, f"the knee's energy {knee!r} J")


WEBSOCKET_OPENS = """const done = arguments[arguments.length - 1];
const socket = new WebSocket(arguments[0]);
socket.onopen = () => { socket.close(); done("open"); };
socket.onerror = () => done("refused");"""


def test_a_foreign_origin_or_host_is_refused_in_the_browser(browser, workbench, tmp_path):
    """A page of another origin on this machine (same site: the session cookie goes with its requests) cannot open
    the workbench's websocket, and a foreign name resolved to this machine (DNS rebinding) gets no page, token
    or not; the workbench's own page opens it."""
    import functools
    import http.server
    import threading

    from selenium.webdriver.common.by import By

    port = workbench.server.get_port()
    assert browser.execute_async_script(WEBSOCKET_OPENS, f"ws://127.0.0.1:{port}/") == "open"  # its own page
    (tmp_path / "index.html").write_text("<html><body>another page</body></html>")
    other = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(
        http.server.SimpleHTTPRequestHandler, directory=str(tmp_path)))
    threading.Thread(target=other.serve_forever, daemon=True).start()
    before = len(workbench.gate.refused)
    browser.execute_script("window.open(arguments[0], '_blank')", f"http://127.0.0.1:{other.server_port}/")
    browser.switch_to.window(browser.window_handles[-1])
    try:
        wait_for(browser, lambda: "another page" in browser.find_element(By.TAG_NAME, "body").text, "the other page")
        assert browser.execute_async_script(WEBSOCKET_OPENS, f"ws://127.0.0.1:{port}/") == "refused"
        assert f"Origin 'http://127.0.0.1:{other.server_port}' is not this server's page" in workbench.gate.refused[before:]
        browser.get(workbench.url.replace("127.0.0.1", REBOUND))  # with the token
        wait_for(browser, lambda: "is not this server's" in browser.find_element(By.TAG_NAME, "body").text,
                 "the foreign Host refused")
        assert f"Host '{REBOUND}:{port}' is not this server's" in workbench.gate.refused[before:]
    finally:
        browser.close()
        browser.switch_to.window(browser.window_handles[0])
        other.shutdown()


def test_the_page_has_no_share_control_and_is_refused_without_its_token(browser, workbench):
    from selenium.webdriver.common.by import By

    labelled = browser.find_elements(By.XPATH, "//*[contains(translate(normalize-space(.), 'SHARE', 'share'), 'share')"
                                               " and (self::button or self::a)] | //*[contains(@aria-label, 'hare') or "
                                               "contains(@title, 'hare')]")
    assert not [element for element in labelled if element.is_displayed()]
    assert browser.find_elements(By.XPATH, "//button[normalize-space()='Optimise']")  # the page's own buttons are found
    url = workbench.url.split("?")[0]
    browser.execute_script("window.open(arguments[0], '_blank')", url.replace("127.0.0.1", "localhost"))
    browser.switch_to.window(browser.window_handles[-1])
    try:  # another host name of this machine, no token (its cookie is 127.0.0.1's): refused, saying why
        wait_for(browser, lambda: "no session token" in browser.find_element(By.TAG_NAME, "body").text, "the refusal")
    finally:
        browser.close()
        browser.switch_to.window(browser.window_handles[0])


@pytest.fixture(scope="module")
def ur5(downloads):
    from placement.cli import app, build_command_parser

    args = build_command_parser().parse_args(["app", "--robot", "ur5", "--path", str(EXAMPLE)])
    bench = app.start(args)
    bench.bench.search_settings = dataclasses.replace(bench.bench.search_settings, **BUDGET)
    try:
        driver = open_page(bench.url)
        try:
            yield bench, driver
        finally:
            driver.quit()
    finally:
        bench.close()


def ur5_json(tmp_path, *options: str) -> dict:
    from placement.cli import main

    out = tmp_path / "ur5.json"
    assert main(["--robot", "ur5", "--path", str(EXAMPLE), "--quiet", "--json", str(out), *options]) == 0
    return json.loads(out.read_text())


def test_typing_400_into_the_ur5s_x_evaluates_400_mm_and_1e3_is_refused_by_its_bound(ur5, tmp_path):
    from placement.app.evaluations import shown_value
    from placement.placing.transform import VARIABLES

    bench, driver = ur5
    current = {name: format(shown_value(name, value), ".12g") for name, value in zip(VARIABLES, bench.placement)}
    expected = ur5_json(tmp_path, "--at", at({**current, "x": "400"}))["at"]["energy_J"]
    type_into(driver, "x (mm)", "400")
    wait_for(driver, lambda: abs(number_of(driver, "exact-value") - expected) <= 1e-9,
             f"the energy at x = 400 mm, {expected!r} J (last read: {text_of(driver, 'exact-value')})")
    assert bench.placement[0] == 0.4 and field_text(driver, "x (mm)") == "400"
    type_into(driver, "x (mm)", "1e3")
    wait_for(driver, lambda: "x = 1e3 mm is above its upper bound 600 mm" in (text_of(driver, "message") or ""),
             "the bound named")
    assert field_text(driver, "x (mm)") == "1e3" and bench.placement[0] == 0.4  # the text kept, nothing moved
    type_into(driver, "x (mm)", "400")
    wait_for(driver, lambda: not text_of(driver, "message"), "the message cleared")


def field_text(driver, label: str) -> str:
    return field_of(driver, label).get_attribute("value")


def test_optimise_on_the_ur5_finds_the_command_lines_best(ur5, tmp_path):
    _, driver = ur5
    expected = ur5_json(tmp_path, *BUDGET_OPTIONS)["best"]["objective"]["value"]
    click(driver, "Optimise")
    wait_for(driver, lambda: text_of(driver, "best-value") is not None, "the search's best", timeout_s=900)
    assert abs(number_of(driver, "best-value") - expected) <= 1e-9


def workpiece_pixels(driver) -> tuple[int, int]:
    """(red, magenta) pixels of a screenshot: the workpiece infeasible, and feasible."""
    import io

    import numpy as np
    from PIL import Image

    image = np.asarray(Image.open(io.BytesIO(driver.get_screenshot_as_png())).convert("RGB")).astype(int)
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return int(((r > 170) & (g < 70) & (b < 70)).sum()), int(((r > 170) & (g < 70) & (b > 140)).sum())


def test_an_infeasible_placement_turns_the_ur5s_workpiece_red(ur5):
    import numpy as np

    from placement.app.page import PATH_COLOR

    bench, driver = ur5
    corners = [{"x": "600", "y": "400", "z": "450"}, {"x": "250", "y": "-200", "z": "50"}, {"x": "600", "y": "-200", "z": "50"}]
    for corner in corners:
        type_into(driver, "--at", at(corner))
        wait_for(driver, lambda corner=corner: np.isclose(bench.placement[0], float(corner["x"]) / 1e3), "the corner")
        if not bench.reading.feasible:
            break
    assert not bench.reading.feasible
    click(driver, "Frame the workpiece")
    wait_for(driver, lambda: workpiece_pixels(driver)[0] > 200, f"a red workpiece (red, magenta: {workpiece_pixels(driver)})")
    type_into(driver, "--at", "x=400,y=100,z=250,phi=0,theta=0,psi=0")  # the middle of the bounds: feasible
    wait_for(driver, lambda: bench.reading is not None and bench.reading.feasible, "a feasible placement")
    click(driver, "Frame the workpiece")
    wait_for(driver, lambda: workpiece_pixels(driver)[0] < 20, f"the red gone (red, magenta: {workpiece_pixels(driver)})")
    assert (bench.path_line.colors == PATH_COLOR).all() and not bench.failing_mark.visible
