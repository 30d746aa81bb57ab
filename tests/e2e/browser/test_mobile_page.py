"""The mobile world's page in a real browser (Chromium): its figures follow the robot, and a key
held down (W) drives the base through the page's teleop, as a person drives it; let go, it stops."""

import os

from app.serving.launch import running_server
from bench.page_responsiveness import ARGS, CHROMIUM
from tests.http_client import http
from tests.waiting import wait_for


def test_the_page_shows_the_robot_and_its_teleop_drives_it():
    from playwright.sync_api import sync_playwright

    assert os.path.exists(CHROMIUM), "make test installs Debian's chromium"
    with running_server("--view", "none", "--world", "mobile") as lab:

        def twist():
            t = http.get(f"{lab.url}/topics/odom").json()["twist"]["twist"]
            return t["linear"]["x"], t["angular"]["z"]

        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
            try:
                page = browser.new_page(viewport={"width": 1000, "height": 700})
                page.set_default_timeout(60_000)
                page.goto(lab.url + "/")
                page.wait_for_function("document.getElementById('f-pose').textContent.startsWith('x -1.00')")
                page.wait_for_function("document.getElementById('f-obstacle').textContent.startsWith('obstacle')")
                page.locator("#turn").fill("1.2")
                page.locator("body").click(position={"x": 5, "y": 5})
                page.keyboard.down("a")  # held: the page sends the twist again every 100 ms
                wait_for(lambda: twist() == (0.0, 1.2), timeout=60)
                page.keyboard.up("a")
                wait_for(lambda: twist() == (0.0, 0.0), timeout=60)  # let go: a zero twist, then the watchdog
                assert page.locator("#f-error").text_content() == ""
            finally:
                browser.close()
