"""The workbench's page in headless Chromium (tests/support/browser.py), set and read as a user would.

Numbers are typed into the page's fields, buttons clicked, values read from the page's text; each wait is
on a condition the page shows, never a fixed sleep. Used by the Orthoglide's and the UR5's browser tests,
two modules so that ``-n 2`` gives them to two workers.
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.support.browser import chromium
from tests.support.paths import EXAMPLE

# The page's searches and the command line's run on this smaller budget than the default (48 x 80): they must
# find the same placements and fronts whatever the budget.
BUDGET = {"population": 24, "max_generations": 10}
BUDGET_OPTIONS = ("--population", str(BUDGET["population"]), "--generations", str(BUDGET["max_generations"]))
REBOUND = "rebound.example"  # a foreign name the browser resolves to this machine, as DNS rebinding would
# Wide enough for the scene beside the panel (about 380 px), small enough that software WebGL draws it fast.
WINDOW = (1000, 700)
WHAT = "the workbench"


def start_workbench(robot: str):
    """A workbench on ``robot`` and the example path, its searches (the command line's) on the small budget; the
    caller closes it."""
    from placement.cli import app, build_command_parser
    from placement.search.optimize import SearchSettings

    args = build_command_parser().parse_args(["app", "--robot", robot, "--path", str(EXAMPLE)])
    bench = app.start(args)
    assert bench.bench.search_settings == SearchSettings(seed=0)  # the command line's defaults
    bench.bench.search_settings = dataclasses.replace(bench.bench.search_settings, **BUDGET)
    return bench


def open_page(url: str, downloads: Path | None = None, window: tuple[int, int] = WINDOW):
    """Headless Chromium on ``url``, its first exact value shown (downloads into ``downloads``); the caller quits it."""
    driver = chromium(window, WHAT, (f"--host-resolver-rules=MAP {REBOUND} 127.0.0.1", f"--proxy-bypass-list={REBOUND}"))
    if downloads is not None:
        driver.execute_cdp_cmd("Browser.setDownloadBehavior", {"behavior": "allow", "downloadPath": str(downloads)})
    driver.get(url)
    try:
        wait_for(driver, lambda: text_of(driver, "exact-value") is not None, "the page's first exact value")
    except BaseException:
        driver.quit()
        raise
    return driver


def text_of(driver, element_id: str) -> str | None:
    """The element's text, read at once in the page (never a stale element: the page replaces its panels)."""
    return driver.execute_script("const found = document.getElementById(arguments[0]);"
                                 "return found === null ? null : found.textContent.trim();", element_id)


def wait_for(driver, condition, what: str | Callable[[], str], timeout_s: float = 120.0) -> None:
    """Poll ``condition`` every 0.1 s until it holds; fail saying ``what`` (or what it returns, then) was never
    shown."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            if condition():
                return
        except Exception:  # an element replaced while it was read: read again
            pass
        time.sleep(0.1)
    pytest.fail(f"the page never showed {what if isinstance(what, str) else what()}")


def field_of(driver, label: str):
    from selenium.webdriver.common.by import By

    return driver.find_element(By.XPATH, f"//label[normalize-space()='{label}']/following::input[1]")


def field_text(driver, label: str) -> str:
    return field_of(driver, label).get_attribute("value")


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

    button = driver.find_element(By.XPATH, f'//button[normalize-space()="{text}"]')
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'});", button)  # not under the panel's edge
    button.click()


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


def at(placement: dict[str, str]) -> str:
    return ",".join(f"{k}={v}" for k, v in placement.items())


def go_to(driver, placement: dict[str, str], expected_J: float) -> None:
    """Evaluate a placement typed as ``--at`` takes it (one evaluation, where the fields would take one each) and
    wait for its exact energy."""
    type_into(driver, "--at", at(placement))
    wait_for(driver, lambda: abs(number_of(driver, "exact-value") - expected_J) <= 1e-9,
             f"the --at energy {expected_J!r} J (last read: {text_of(driver, 'exact-value')})")


def cli_json(tmp_path: Path, robot: str, *options: str) -> dict:
    """The document ``placement --robot ROBOT --path EXAMPLE --json`` writes with ``options``."""
    from placement.cli import main

    out = tmp_path / f"{robot}.json"
    assert main(["--robot", robot, "--path", str(EXAMPLE), "--quiet", "--json", str(out), *options]) == 0
    return json.loads(out.read_text())


def searched_json(tmp_path: Path, robot: str, *options: str) -> dict:
    """As :func:`cli_json`, for a search, run as a user runs it: a process of its own. The search's last digits
    depend on how its batches are split among threads, and a test process that has run Pinocchio's RNEA on OpenMP
    threads searches both directions in turn on every thread, where a fresh command line (and the page's job) gives
    each direction a process on one thread; a search's optimum can then move by 5e-7 along a crease of the energy."""
    out = tmp_path / f"{robot}-searched.json"
    subprocess.run([sys.executable, "-m", "placement", "--robot", robot, "--path", str(EXAMPLE), "--quiet", "--json",
                    str(out), *options], check=True, capture_output=True)
    return json.loads(out.read_text())


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
