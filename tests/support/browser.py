"""Headless Chromium for the browser tests, driven through WebDriver (selenium and Debian's chromium-driver).

Without a browser the tests skip, except under CI (``CI`` set: .ci/run installs chromium and chromium-driver),
where they fail: CI must show that the pages work.
"""

from __future__ import annotations

import os
import shutil

import pytest

FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
         "--proxy-server=127.0.0.1:9")  # any network request fails: pages must not need one


def unavailable(reason: str, what: str) -> None:
    """Fail under CI, skip elsewhere, saying what cannot be checked."""
    if os.environ.get("CI"):
        pytest.fail(f"{reason} on the CI machine: {what} cannot be checked in a browser")
    pytest.skip(f"{reason} on this machine (.ci/run installs Debian's chromium and chromium-driver)")


def chromium(window: tuple[int, int], what: str, flags: tuple[str, ...] = ()):
    """A WebDriver session of headless Chromium with a ``window`` (width, height) px and the command-line ``flags``
    besides :data:`FLAGS`; the caller quits it."""
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        unavailable("no selenium", what)
    binary = next((shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome") if shutil.which(n)), None)
    driver_path = shutil.which("chromedriver")
    if binary is None or driver_path is None:
        unavailable("no Chromium or no chromedriver", what)
    options = webdriver.ChromeOptions()
    options.binary_location = binary
    for flag in (*FLAGS, f"--window-size={window[0]},{window[1]}", *flags):
        options.add_argument(flag)
    return webdriver.Chrome(options=options, service=Service(driver_path))
