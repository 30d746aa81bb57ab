"""The mobile world's page in a real browser (Chromium): its figures follow the robot, and a key
held down (W) drives the base through the page's teleop, as a person drives it; let go, it stops.
A wall-following trial's verdict, PASS or FAIL with its reason, shows beside the simulated time,
and the page keeps its two panels side by side at any verdict (screenshots in build/screenshots)."""

import math
import os
import threading
from pathlib import Path

import pytest

from bench.page_responsiveness import ARGS, CHROMIUM
from tests.e2e.serving import running_server
from tests.http_client import http
from tests.waiting import wait_for

SCREENSHOTS = Path(__file__).resolve().parents[3] / "build" / "screenshots"
CIRCLE_M = 0.7  # the circuit's radius about the standard arena's obstacle (a 0.4 m cylinder at 0, 0)


@pytest.fixture(scope="module")
def lab():
    with running_server("--view", "none", "--world", "mobile") as lab:
        yield lab


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    assert os.path.exists(CHROMIUM), "make test installs Debian's chromium-headless-shell"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield browser
        browser.close()


def open_page(lab, browser, width: int, height: int):
    page = browser.new_page(viewport={"width": width, "height": height})
    page.set_default_timeout(90_000)  # a loaded 2-core machine; waits end as soon as the page is there
    page.goto(lab.url + "/")
    return page


def test_the_page_shows_the_robot_and_its_teleop_drives_it(lab, browser):
    def twist():
        t = http.get(f"{lab.url}/topics/odom").json()["twist"]["twist"]
        return t["linear"]["x"], t["angular"]["z"]

    http.post(f"{lab.url}/mobile/reset")
    page = open_page(lab, browser, 1000, 700)
    try:
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
        page.close()


def drive_until_done(lab, steer) -> dict:
    """Twists from `steer(pose)` at 10 Hz (as a node's timer sends them) until the trial is done;
    the monitor's last /wall_following."""
    stop = threading.Event()

    def loop():
        while not stop.wait(0.1):
            linear, angular = steer(http.get(f"{lab.url}/topics/ground_truth_pose").json())
            http.post(f"{lab.url}/mobile/drive", json={"linear_x": linear, "angular_z": angular})

    thread = threading.Thread(target=loop, daemon=True)
    thread.start()
    try:
        return wait_for(lambda: (w := http.get(f"{lab.url}/topics/wall_following").json())["done"] and w, 180)
    finally:
        stop.set()
        thread.join()
        http.post(f"{lab.url}/mobile/drive", json={"linear_x": 0.0, "angular_z": 0.0})


def around_the_obstacle(pose: dict) -> tuple[float, float]:
    """Counter-clockwise on a circle of CIRCLE_M about the obstacle: the tangent's heading, bent in
    towards the circle by the radius' error."""
    bearing = math.atan2(pose["y"], pose["x"])
    heading = bearing + math.pi / 2 + max(-0.8, min(0.8, 2.0 * (math.hypot(pose["x"], pose["y"]) - CIRCLE_M)))
    error = math.remainder(heading - pose["theta"], 2 * math.pi)
    return (0.22 if abs(error) < 0.4 else 0.03), max(-2.5, min(2.5, 3.0 * error))


def into_the_obstacle(pose: dict) -> tuple[float, float]:
    return 0.2, 0.0  # the base starts facing it


def side_by_side(page) -> None:
    """The top view and the side panel in one row, neither stretched: the canvases at their sizes."""
    top, side = page.locator("#top").bounding_box(), page.locator("#side").bounding_box()
    assert side["x"] >= top["x"] + top["width"], (top, side)  # to its right, not below it
    assert abs(side["y"] - top["y"]) < 1, (top, side)
    assert side["y"] + side["height"] <= page.viewport_size["height"], side  # all of it on screen
    for canvas, size in (("#arena", 520), ("#polar", 320)):
        box = page.locator(canvas).bounding_box()
        assert abs(box["width"] - (size + 2)) < 1 and abs(box["height"] - (size + 2)) < 1, (canvas, box)  # its border


@pytest.mark.parametrize(
    ("width", "height", "steer", "head"),
    [(1920, 1080, around_the_obstacle, "PASS"), (1400, 900, into_the_obstacle, "FAIL")],
)
def test_a_verdict_shows_pass_or_fail_and_the_layout_holds(lab, browser, width, height, steer, head):
    http.post(f"{lab.url}/mobile/reset")
    page = open_page(lab, browser, width, height)
    try:
        page.wait_for_function("document.getElementById('f-trial').textContent.startsWith('no trial yet')")
        side_by_side(page)
        wall = drive_until_done(lab, steer)
        assert wall["passed"] == (head == "PASS"), wall
        trial = page.locator("#f-trial")
        page.wait_for_function(f"document.getElementById('f-trial').textContent.startsWith('{head}')")
        assert wall["verdict"] in trial.text_content()
        assert f"{wall['elapsed']:.1f} s" in trial.text_content()
        # the simulated time, as the lifting page's header shows it, and it runs on
        page.wait_for_function(
            "/simulation \\d+ Hz, t = \\d+\\.\\d s/.test(document.getElementById('health').textContent)"
        )
        shown = float(page.locator("#health").text_content().split("t = ")[1].removesuffix(" s"))
        # the page rounds to 0.1 s (toFixed(1)): what it shows is at most half a digit ahead
        assert 0 < shown <= http.get(f"{lab.url}/health").json()["sim_time"] + 0.05 + 1e-9
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SCREENSHOTS / f"mobile-{head.lower()}-{width}x{height}.png"))
        side_by_side(page)
    finally:
        page.close()
