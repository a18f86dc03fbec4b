"""The workbench page on the Orthoglide in a real browser: headless Chromium driven through WebDriver.

The page is set and read as a user would (tests/support/workbench_page.py). Its exact value equals
what ``--at`` prints, its search finds the command line's best, its comparison of two placements is
the difference of what ``--at`` prints at each, its export downloads the document ``--json --at``
writes, its map's best cell is the ``map`` command's and its Pareto front's members are
``--objectives``'; a foreign Origin or Host is refused and no share control is shown. The UR5's
page: test_workbench_browser_ur5.py (another module, so that ``-n 2`` runs the two on two workers).
Without a browser the tests skip, except under CI (``CI`` set), where they fail.
"""

import json
import shlex

import pytest

from tests.support.paths import EXAMPLE
from tests.support.workbench_page import (
    BUDGET_OPTIONS,
    REBOUND,
    at,
    click,
    field_of,
    field_text,
    go_to,
    number_of,
    open_folder,
    open_page,
    same_numbers,
    searched_json,
    start_workbench,
    text_of,
    type_into,
    wait_for,
)
from tests.support.workbench_page import cli_json as robot_json

pytestmark = pytest.mark.slow  # about a minute on a 2-core machine: starts first under -n 2

PLACEMENT = {"x": "12.5", "y": "-7", "z": "-20", "phi": "30"}  # mm, degrees


@pytest.fixture(scope="module")
def workbench():
    bench = start_workbench("orthoglide")
    try:
        yield bench
    finally:
        bench.close()


@pytest.fixture(scope="module")
def downloads(tmp_path_factory):
    return tmp_path_factory.mktemp("downloads")


@pytest.fixture(scope="module")
def browser(workbench, downloads):
    driver = open_page(workbench.url, downloads)
    try:
        yield driver
    finally:
        driver.quit()


def cli_json(tmp_path, *options: str) -> dict:
    return robot_json(tmp_path, "orthoglide", *options)


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
    import threading

    from placement.app.jobs import STARTING

    states: set[str | None] = set()  # what the search says it does, read as it goes
    cli_done = threading.Event()

    def read_states() -> None:  # the browser is read by this thread alone until the command line's search ends
        while not cli_done.wait(0.1):
            states.add(text_of(browser, "search-state"))

    click(browser, "Optimise")
    reader = threading.Thread(target=read_states)
    reader.start()
    try:
        expected = searched_json(tmp_path, "orthoglide", *BUDGET_OPTIONS)["best"]["objective"]["value"]  # while the page searches
    finally:
        cli_done.set()
        reader.join()

    def found() -> bool:
        states.add(text_of(browser, "search-state"))
        return text_of(browser, "best-value") is not None

    wait_for(browser, found, "the search's best", timeout_s=600)
    assert f"{STARTING}..." in states  # its stage before its first generation, not a silent 0 %
    assert any(state and state.endswith(" of 20 generations done") for state in states), states  # best and worst
    assert abs(number_of(browser, "best-value") - expected) <= 1e-9
    click(browser, "Go to best")
    wait_for(browser, lambda: abs(number_of(browser, "exact-value") - expected) <= 1e-9,
             f"the best placement's energy {expected!r} J after 'Go to best'")


OTHER = {"x": "-30", "y": "20", "z": "-10", "phi": "-15"}  # mm, degrees


def test_pinned_and_current_placements_differ_by_what_at_prints_at_each(browser, tmp_path):
    first = cli_json(tmp_path, "--at", at(PLACEMENT))["at"]
    second = cli_json(tmp_path, "--at", at(OTHER))["at"]
    go_to(browser, PLACEMENT, first["energy_J"])
    open_folder(browser, "Compare", "Pin this placement")
    click(browser, "Pin this placement")
    wait_for(browser, lambda: abs(number_of(browser, "compare-energy-pinned") - first["energy_J"]) <= 1e-9,
             "the pinned energy")
    go_to(browser, OTHER, second["energy_J"])
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
    go_to(browser, PLACEMENT, expected["at"]["energy_J"])
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
    open_folder(browser, "Front", "Search the front")
    click(browser, "Search the front")
    # while the page searches
    expected = searched_json(tmp_path, "orthoglide", "--objectives", "energy,dexterity", *BUDGET_OPTIONS)
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


NAMES = """const named = [];
for (const control of document.querySelectorAll('input:not([type=hidden]), textarea, [role=slider], button:not([hidden])')) {
  const box = control.getBoundingClientRect();
  if (box.width === 0 || box.height === 0) continue;  // not shown (a folded folder, the hidden settings)
  let name = (control.getAttribute('aria-label') || '').trim();
  const label = control.id ? document.querySelector(`label[for="${CSS.escape(control.id)}"]`) : null;
  if (!name && label !== null) name = label.textContent.trim();
  if (!name && control.tagName === 'BUTTON') name = control.textContent.trim();
  named.push([control.tagName, name]);
}
return named;"""


def test_every_control_has_a_name_and_the_cancel_buttons_differ(browser):
    """What a screen reader says: each field, slider and button shown has a name (the label in its row, its text,
    or its icon's), in every folder, and each Cancel button says what it cancels."""
    for title, control in (("Compare", "Pin this placement"), ("Export", "Export JSON"), ("Map", "Map"),
                           ("Front", "Search the front")):
        open_folder(browser, title, control)
    wait_for(browser, lambda: all(name for _, name in browser.execute_script(NAMES)),
             lambda: f"every control named (unnamed: {[c for c in browser.execute_script(NAMES) if not c[1]]})",
             timeout_s=10)
    names = [name for _, name in browser.execute_script(NAMES)]
    assert {"x (mm)", "--at", "points per variable", "time (s)"} <= set(names)  # fields by their labels
    cancels = [name for name in names if name.startswith("Cancel")]
    assert sorted(cancels) == ["Cancel front", "Cancel map", "Cancel search"]
