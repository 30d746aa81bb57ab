"""The dashboard page's responsiveness in a real browser with software WebGL (Debian's
chromium-headless-shell, SwiftShader), without and with the 3D view embedded: a service call's
click -> response on the page (the Services tab's /divide_ints form), p50 and max, with full and
light meshes (`serve --view`). Lifting runs during each series (the robot presses the box, the scene moves).

    .venv/bin/python -m bench.page_responsiveness [--clicks 20] [--view full light]

The browser test (tests/e2e/browser/test_page.py) drives the page with the same functions.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import tempfile
import time

import httpx

from app.serving.launch import free_port, running_server

# Chromium as Playwright runs it headless: its headless shell (Playwright >= 1.49 launches that build
# for headless operation; the full browser's --headless is its "new headless", slower there), Debian's
# chromium-headless-shell package. The same Blink, V8 and SwiftShader as the chromium package; the
# browser tests drive it with ~1/3 less CPU (docs/performance.md, 2026-12-08).
CHROMIUM = shutil.which("chromium-headless-shell") or "/usr/bin/chromium-headless-shell"
ARGS = [
    "--site-per-process",  # as desktop Chromium: a cross-site frame gets its own process
    "--no-sandbox",
    "--use-gl=swiftshader",
    "--enable-unsafe-swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
DIVIDE = ".service[data-name='/divide_ints']"


def click_round_trip(page, b: int) -> float:
    """Seconds from the click on /divide_ints (a = 1, b = 0 or 1) to its answer on the page. b
    alternates between calls so that each answer differs from the one before."""
    form = page.locator(DIVIDE)
    form.locator("input[name=a]").fill("1")
    form.locator("input[name=b]").fill(str(b))
    expected = "Division by zero!" if b == 0 else "Division ok."
    started = time.perf_counter()
    form.locator("button[type=submit]").click()
    page.wait_for_function(
        "([s, n]) => (document.querySelector(s)?.textContent || '').includes(n)",
        arg=[f"{DIVIDE} pre.response", expected],
    )
    return time.perf_counter() - started


def round_trips(page, clicks: int, pause: float = 0.0) -> list[float]:
    """`clicks` round trips (s), alternating b = 0, 1, ... after whatever the form showed last."""
    page.locator("nav button[data-tab=services]").click()
    shown = (
        page.locator(f"{DIVIDE} pre.response").inner_text() if page.locator(f"{DIVIDE} pre.response").count() else ""
    )
    first = 1 if "zero" in shown else 0
    times = []
    for k in range(clicks):
        times.append(click_round_trip(page, (first + k) % 2))
        time.sleep(pause)
    return times


CONTROL_PANEL_TAB = "[data-dock-tab='viser-control-panel']"  # viser's tab of its docked control panel


def embed_view(page):
    """Click "Show the 3D view here" and wait for the view (its control panel, collapsed to its tab
    at first: app/view/view3d.py): the view's frame locator."""
    page.locator("#view-embed").click()
    view = page.frame_locator("#view")
    view.locator(CONTROL_PANEL_TAB).wait_for(state="attached", timeout=180_000)
    return view


def open_controls(view) -> None:
    """Open the embedded view's control panel (one click on its tab) and wait for its controls."""
    view.locator(CONTROL_PANEL_TAB).click()
    view.get_by_text("Take over the palm").wait_for(state="attached", timeout=180_000)


def measure(view_mode: str, clicks: int, browser) -> dict[str, list[float]]:
    """Round trips (s) without and with the embedded view, a fresh server with `--view view_mode`."""
    with (
        tempfile.TemporaryDirectory() as output,
        running_server("--view", view_mode, "--view-port", str(free_port()), "--output-dir", output) as server,
    ):
        page = browser.new_page(viewport={"width": 1500, "height": 900})
        page.set_default_timeout(120_000)
        page.goto(server.url + "/")
        page.locator(f"{DIVIDE} button[type=submit]").wait_for()
        result = {}
        for phase in ("without", "embedded"):
            httpx.post(f"{server.url}/services/reset_simulation")
            httpx.post(f"{server.url}/services/start_cooperative_lifting", json={"force": 10})
            if phase == "embedded":
                embed_view(page)
                time.sleep(2.0)  # the meshes arrive and render
            round_trips(page, 2)  # warm-up, not counted
            result[phase] = round_trips(page, clicks, pause=0.2)
        page.close()
    return result


def describe(times: list[float]) -> str:
    return f"p50 {statistics.median(times) * 1e3:.0f} ms, max {max(times) * 1e3:.0f} ms"


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--clicks", type=int, default=20, help="round trips per series")
    parser.add_argument("--view", nargs="+", choices=("full", "light"), default=["full", "light"])
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    assert os.path.exists(CHROMIUM), "make bench installs Debian's chromium-headless-shell"
    print(
        f"page click -> response of /divide_ints, {args.clicks} clicks per series, Chromium with software WebGL "
        f"(SwiftShader), {os.cpu_count()} cores, lifting running"
    )
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        for mode in args.view:
            times = measure(mode, args.clicks, browser)
            print(
                f"  {mode:5} meshes: without the 3D view {describe(times['without'])}; "
                f"embedded (own process) {describe(times['embedded'])}",
                flush=True,
            )
        browser.close()


if __name__ == "__main__":
    main()
