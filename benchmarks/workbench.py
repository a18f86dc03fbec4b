"""How live the workbench is: one evaluation while the path is dragged, and the exact one on release.

Run: ``python benchmarks/workbench.py [--repeats N]``. For the Orthoglide groove and the UR5 on the
same path (examples/rect.yaml), it prints the median and the slowest time of the live reading
(:meth:`placement.app.evaluations.Bench.live`: the search's coarse sampling, feasibility, tightest limit,
per-actuator energy and the robot's pose at every sample) and of the exact value (``--at``'s), on
placements drawn at random within the search's bounds, as dragging visits them. The targets are
50 ms (Orthoglide) and 100 ms (UR5) for a live reading; nothing here is asserted.

``--browser PNG`` also serves the Orthoglide's page, opens it in headless Chromium (selenium and
chromium-driver), times the round trip from a value typed in a field to the new exact value shown
in the page, pins the placement it ends at (the Compare panel), runs Optimise, goes to the best
placement and saves the page as PNG.

``--screenshots DIR`` saves the UR5's page as the documentation shows it (``docs/images``): at first load
(``workbench-first-load.png``), after Optimise and Go to best (``workbench-optimise.png``), on a map
(``workbench-map.png``), and at first load 390 px wide (``workbench-narrow.png``).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from placement import load_robot
from placement.app.evaluations import Bench
from placement.path.load import load_path

EXAMPLE = Path(__file__).parents[1] / "examples" / "rect.yaml"
TARGETS_MS = {"orthoglide": 50.0, "ur5": 100.0}


def timings(call, placements: np.ndarray) -> np.ndarray:
    """Milliseconds of ``call`` at each placement."""
    out = []
    for placement in placements:
        start = time.perf_counter()
        call(placement)
        out.append((time.perf_counter() - start) * 1e3)
    return np.array(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=50, help="placements timed per robot (default 50)")
    parser.add_argument("--browser", metavar="PNG", help="also time the page in headless Chromium and save it as PNG")
    parser.add_argument("--screenshots", metavar="DIR", help="only save the UR5 page's screenshots into DIR")
    args = parser.parse_args()
    if args.screenshots:
        screenshots(Path(args.screenshots))
        return
    rng = np.random.default_rng(0)
    path = load_path(EXAMPLE)
    for name, target in TARGETS_MS.items():
        bench = Bench(load_robot(name), path)
        space = bench.space
        placements = space.full(space.lower + rng.random((args.repeats, len(space.free))) * (space.upper - space.lower))
        bench.live(placements[0])  # compiles and warms what a first call loads
        bench.exact(placements[0])
        live = timings(bench.live, placements)
        feasible = sum(bench.live(p).feasible for p in placements)
        at_zero = timings(bench.live, np.repeat(bench.clamp(np.zeros(6))[None], max(5, args.repeats // 5), axis=0))
        exact = timings(bench.exact, placements[: max(5, args.repeats // 5)])
        samples = len(bench.live_evaluator.samples)
        print(f"{name:<11s} live ({samples} samples): median {np.median(live):6.1f} ms, slowest {live.max():6.1f} ms "
              f"(target {target:.0f} ms: {'met' if live.max() <= target else 'MISSED'}; {feasible}/{len(live)} feasible; "
              f"at 0: median {np.median(at_zero):.1f} ms); exact "
              f"({len(bench.exact_evaluator.samples)} samples): median {np.median(exact):6.1f} ms")
        bench.close()
    if args.browser:
        browser(args.browser)


def browser(png: str) -> None:
    """The page's round trip in headless Chromium, then its screenshot after a pin, Optimise and Go to best."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    from placement.cli import app, build_command_parser

    workbench = app.start(build_command_parser().parse_args(["app", "--robot", "orthoglide", "--path", str(EXAMPLE)]))
    options = webdriver.ChromeOptions()
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
                 "--use-angle=swiftshader", "--window-size=1500,1000", "--proxy-server=127.0.0.1:9"):
        options.add_argument(flag)
    driver = webdriver.Chrome(options=options, service=Service("/usr/bin/chromedriver"))
    try:
        driver.get(workbench.url)
        exact = "const e = document.getElementById('exact-value'); return e === null ? null : e.dataset.value;"
        while driver.execute_script(exact) is None:
            time.sleep(0.05)
        field = driver.find_element(By.XPATH, "//label[normalize-space()='x (mm)']/following::input[1]")
        trips = []
        for k in range(10):
            before = driver.execute_script(exact)
            field.send_keys(Keys.CONTROL, "a", Keys.BACKSPACE)
            start = time.perf_counter()
            field.send_keys(str(k + 1))  # one keystroke: one update
            while driver.execute_script(exact) == before:
                time.sleep(0.002)
            trips.append((time.perf_counter() - start) * 1e3)
        print(f"page round trip (typed value -> exact value shown, through viser's websocket): median "
              f"{np.median(trips):.0f} ms, slowest {max(trips):.0f} ms")
        driver.find_element(By.XPATH, "//div[contains(@class, 'mantine-Paper-root') and normalize-space(text())="
                                      "'Compare']").click()
        time.sleep(1)
        driver.find_element(By.XPATH, "//button[normalize-space()='Pin this placement']").click()
        while not driver.find_elements(By.ID, "compare-energy-pinned"):
            time.sleep(0.2)
        driver.find_element(By.XPATH, "//button[normalize-space()='Optimise']").click()
        while not driver.find_elements(By.ID, "best-value"):
            time.sleep(0.5)
        driver.find_element(By.XPATH, "//button[normalize-space()='Go to best']").click()
        time.sleep(4)
        for button in driver.find_elements(By.XPATH, "//button[contains(@class, 'CloseButton')]"):
            button.click()  # the note that WebGL runs in software
        driver.execute_script("document.getElementById('compare').scrollIntoView({block: 'end'})")  # beside the best
        time.sleep(1)
        driver.save_screenshot(png)
        print(f"page after Optimise and Go to best: {png}")
    finally:
        driver.quit()
        workbench.close()



def _chromium(width: int, height: int):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
                 "--use-angle=swiftshader", f"--window-size={width},{height}", "--proxy-server=127.0.0.1:9"):
        options.add_argument(flag)
    return webdriver.Chrome(options=options, service=Service("/usr/bin/chromedriver"))


def _wait(driver, script: str, timeout_s: float = 600.0):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(0.2)
    raise TimeoutError(script)


def _click(driver, label: str) -> None:
    from selenium.webdriver.common.by import By

    driver.find_element(By.XPATH, f"//button[normalize-space()=\"{label}\"]").click()


def _first_load(driver, url: str) -> None:
    from selenium.webdriver.common.by import By

    driver.get(url)
    _wait(driver, "return document.getElementById('exact-value') !== null")
    time.sleep(2)
    for button in driver.find_elements(By.XPATH, "//button[contains(@class, 'CloseButton')]"):
        button.click()  # the note that WebGL runs in software


def screenshots(directory: Path) -> None:
    """The UR5's page at first load, after Optimise and Go to best, on a map, and 390 px wide."""
    from selenium.webdriver.common.by import By

    from placement.cli import app, build_command_parser

    directory.mkdir(parents=True, exist_ok=True)
    workbench = app.start(build_command_parser().parse_args(["app", "--robot", "ur5", "--path", str(EXAMPLE)]))
    try:
        driver = _chromium(800, 900)
        try:  # a phone's width (a desktop Chromium's window is at least 500 px wide)
            driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                                   {"width": 390, "height": 844, "deviceScaleFactor": 1, "mobile": True})
            _first_load(driver, workbench.url)
            driver.save_screenshot(str(directory / "workbench-narrow.png"))
        finally:
            driver.quit()
        driver = _chromium(1400, 900)
        try:
            _first_load(driver, workbench.url)
            _click(driver, "Frame the workpiece")
            time.sleep(2)
            driver.save_screenshot(str(directory / "workbench-first-load.png"))
            _click(driver, "Optimise")
            _wait(driver, "return document.getElementById('best-value') !== null")
            _click(driver, "Go to best")
            time.sleep(3)
            driver.execute_script("document.getElementById('best-value').scrollIntoView({block: 'center'})")
            time.sleep(1)
            driver.save_screenshot(str(directory / "workbench-optimise.png"))
            driver.find_element(By.XPATH, "//div[contains(@class, 'mantine-Paper-root') and normalize-space(text())="
                                          "'Map']").click()
            time.sleep(1)
            _click(driver, "Map")
            _wait(driver, "const e = document.getElementById('map-state'); return e !== null && "
                          "e.textContent.trim() === 'done'")
            time.sleep(2)
            driver.execute_script("document.getElementById('map-best-value').scrollIntoView({block: 'end'})")
            time.sleep(1)
            driver.save_screenshot(str(directory / "workbench-map.png"))
        finally:
            driver.quit()
    finally:
        workbench.close()
    print(f"screenshots in {directory}")


if __name__ == "__main__":
    from results import recorded  # this run's section of benchmarks/RESULTS.md

    with recorded("workbench"):
        main()
