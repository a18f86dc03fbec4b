"""The workbench page on the UR5 in a real browser: headless Chromium driven through WebDriver.

Typing "400" into x evaluates 400 mm and "1e3" is refused by its bound, the text kept; the page's
search finds the command line's best; an infeasible placement turns the workpiece red. A module of its
own, beside the Orthoglide's (test_workbench_browser.py), so that ``-n 2`` runs the two on two workers.
Without a browser the tests skip, except under CI (``CI`` set), where they fail.
"""

import pytest

from tests.support.workbench_page import (
    BUDGET_OPTIONS,
    at,
    cli_json,
    click,
    field_text,
    number_of,
    open_page,
    searched_json,
    start_workbench,
    text_of,
    type_into,
    wait_for,
)

pytestmark = pytest.mark.slow  # about a minute on a 2-core machine: starts first under -n 2


@pytest.fixture(scope="module")
def ur5():
    bench = start_workbench("ur5")
    try:
        driver = open_page(bench.url)
        try:
            yield bench, driver
        finally:
            driver.quit()
    finally:
        bench.close()


def ur5_json(tmp_path, *options: str) -> dict:
    return cli_json(tmp_path, "ur5", *options)


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


def test_optimise_on_the_ur5_finds_the_command_lines_best(ur5, tmp_path):
    _, driver = ur5
    click(driver, "Optimise")
    expected = searched_json(tmp_path, "ur5", *BUDGET_OPTIONS)["best"]["objective"]["value"]  # while the page searches
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
    wait_for(driver, lambda: workpiece_pixels(driver)[0] > 200,
             lambda: f"a red workpiece (red, magenta pixels: {workpiece_pixels(driver)})")
    type_into(driver, "--at", "x=400,y=100,z=250,phi=0,theta=0,psi=0")  # the middle of the bounds: feasible
    wait_for(driver, lambda: bench.reading is not None and bench.reading.feasible, "a feasible placement")
    click(driver, "Frame the workpiece")
    wait_for(driver, lambda: workpiece_pixels(driver)[0] < 20 and workpiece_pixels(driver)[1] > 200,
             lambda: f"the red gone, the workpiece magenta (red, magenta pixels: {workpiece_pixels(driver)})")
    assert (bench.path_line.colors == PATH_COLOR).all() and not bench.failing_mark.visible
