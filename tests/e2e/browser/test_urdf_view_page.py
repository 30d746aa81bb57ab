"""`hri-lab urdf view` as a student uses it: the command started as typed, its page in a real browser
(Chromium), a slider moved with the keyboard as a person moves it, and the move read back from
`/joint_states` by a ROS client (roslibpy) on the view's rosbridge endpoint."""

import os
import subprocess
import sys
from pathlib import Path

import roslibpy

from app.serving.launch import free_port
from bench.page_responsiveness import ARGS, CHROMIUM
from tests.waiting import process_gone, wait_for

PAN_TILT = Path(__file__).resolve().parents[3] / "examples/urdf/pan_tilt.urdf"


def test_a_slider_moved_in_the_browser_reaches_joint_states():
    from playwright.sync_api import sync_playwright

    assert os.path.exists(CHROMIUM), "make test installs Debian's chromium-headless-shell"
    port = free_port()
    view = subprocess.Popen(
        [sys.executable, "-m", "app.cli", "urdf", "view", str(PAN_TILT), "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    received: list[dict] = []
    try:
        lines = []
        for line in view.stdout:  # ends when the process does
            lines.append(line)
            if "Ctrl+C" in line:
                break
        view_url = next(line.split()[-1] for line in lines if line.strip().startswith("3D view"))
        ros = roslibpy.Ros("127.0.0.1", port, transport="asyncio")
        ros.run(timeout=30)
        try:
            roslibpy.Topic(ros, "/joint_states", "sensor_msgs/JointState").subscribe(received.append)
            wait_for(lambda: received)
            assert received[-1]["position"] == [0.0, 0.0]
            with sync_playwright() as p:
                browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
                page = browser.new_page(viewport={"width": 900, "height": 600})
                page.set_default_timeout(60_000)
                page.goto(view_url)
                tilt = page.locator("[role=slider]").nth(1)  # pan_joint's, then tilt_joint's
                tilt.wait_for()
                tilt.focus()
                page.keyboard.press("End")  # to the top of the range, as a person drags it there
                wait_for(lambda: received[-1]["position"] == [0.0, 0.79], timeout=60)
                browser.close()
        finally:
            ros.close()
            ros.terminate()
    finally:
        view.terminate()
        view.wait(30)
        view.stdout.close()
    assert received[-1]["name"] == ["pan_joint", "tilt_joint"]
    assert process_gone(view.pid)
