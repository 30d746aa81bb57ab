"""The dashboard in a real browser (Debian's chromium driven by playwright), as a student uses it."""
import os
import shutil
import time
from pathlib import Path

import httpx
import pytest

from app.cli.launch import free_port, running_server

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
SCREENSHOTS = Path(__file__).resolve().parent.parent / "build" / "screenshots"
ARGS = ["--no-sandbox", "--use-gl=swiftshader", "--enable-unsafe-swiftshader", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--no-first-run"]


@pytest.fixture(scope="module")
def server():
    with running_server("--view", "light", "--view-port", str(free_port())) as server:
        yield server.url


@pytest.fixture(scope="module")
def page(server):
    from playwright.sync_api import sync_playwright

    assert os.path.exists(CHROMIUM), "make test installs Debian's chromium"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 1500, "height": 900})
        page.set_default_timeout(60_000)
        page.goto(server + "/")
        yield page
        browser.close()


def test_dashboard_in_chromium(server, page):
    # the service list, generated from the API, with the .srv text
    start = page.locator(".service[data-name='/start_cooperative_lifting']")
    start.wait_for()
    assert "float64 force\nstring controller  # '' keeps the current one; sp or patch\n---\nstring message" in start.locator("pre.srv").inner_text()

    # call divide_ints through its form
    divide = page.locator(".service[data-name='/divide_ints']")
    divide.locator("input[name=a]").fill("1")
    divide.locator("input[name=b]").fill("0")
    divide.locator("button[type=submit]").dispatch_event("click")
    page.wait_for_function("document.querySelector(\".service[data-name='/divide_ints'] pre.response\").textContent.includes('Division by zero!')")

    # a parameter set to a wrong type shows rclcpp's refusal
    page.locator("nav button[data-tab=params]").dispatch_event("click")
    mu = page.locator(".param[data-name='cooperative_lifting/mu']")
    mu.locator("input").fill("abc")
    mu.locator("button").dispatch_event("click")
    refusal = "Setting parameter failed: Wrong parameter type, parameter {mu} is of type {double}, setting it to {string} is not allowed."
    page.wait_for_function(f"document.querySelector(\".param[data-name='cooperative_lifting/mu'] .refused\")?.textContent === {refusal!r}")

    # start lifting from the 3D view's control (viser, in the embedded frame) with 12 N
    view = page.frame_locator("#view")
    force = view.get_by_label("Force (N)")
    force.fill("12")
    force.press("Enter")
    view.get_by_role("button", name="Start lifting").dispatch_event("click")
    deadline = time.monotonic() + 30
    state = {}
    while time.monotonic() < deadline:
        state = httpx.get(f"{server}/topics/lifting_state").json()
        if state["started"]:
            break
        time.sleep(0.2)
    assert (state["started"], state["f_n_min"], state["f_n_max"]) == (True, 12.0, 17.0)
    time.sleep(3)  # the robot presses the box; let the view draw it
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SCREENSHOTS / "dashboard.png"))
    assert (SCREENSHOTS / "dashboard.png").stat().st_size > 10_000

    # the controller comparison, as an action from the page: the table arrives in the goal's output
    page.locator("nav button[data-tab=actions]").dispatch_event("click")
    compare = page.locator(".action[data-name='/compare_controllers']")
    compare.locator("input[name=participants]").fill("calm")
    compare.locator("button[type=submit]").dispatch_event("click")
    page.wait_for_function("document.querySelector(\".action[data-name='/compare_controllers'] pre.feedback\")"
                           ".textContent.includes('succeeded: ')", timeout=180_000)
    output = compare.locator("pre.feedback").inner_text()
    assert '"controller":"patch","participant":"calm","trial":2,"of":2' in output
    table = output.split("table:\n", 1)[1]
    assert table.splitlines()[0].split() == ["participant", "sp", "|", "patch"] and "calm" in table
    compare.locator("pre.feedback").scroll_into_view_if_needed()
    page.screenshot(path=str(SCREENSHOTS / "compare.png"))
