"""A hostile page on another local origin, in Chromium, tries to drive the lab (fetch, a form
POST, a WebSocket) while the student has the lab open: every attempt is refused and nothing
changes; the lab's own page keeps working."""

import threading
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import pytest

from tests.e2e.browser.test_page import ARGS, CHROMIUM
from tests.e2e.serving import running_server
from tests.http_client import http

ATTACK = """<!doctype html><title>evil</title>
<form id=f method=post action="{lab}/services/reset_simulation" enctype="text/plain" target=sink>
<input name=x value=y></form><iframe name=sink></iframe>
<script>
window.results = {{}};
const lab = "{lab}";
async function attack() {{
  const opts = {{method: "POST", mode: "no-cors"}};
  await fetch(lab + "/params/load", {{...opts, headers: {{"content-type": "text/plain"}},
      body: "keytwist:\\n  ros__parameters:\\n    linear_speed: 0.02\\n"}}).catch(() => null);
  await fetch(lab + "/services/start_cooperative_lifting", {{...opts, headers: {{"content-type": "text/plain"}},
      body: '{{"force": 20}}'}}).catch(() => null);
  await fetch(lab + "/params/keytwist/angular_speed", {{method: "PUT", headers: {{"content-type": "application/json"}},
      body: '{{"value": 0.05}}'}}).then(r => results.put = r.status).catch(e => results.put = "blocked");
  document.getElementById("f").submit();
  results.ws = await new Promise(done => {{
    const ws = new WebSocket(lab.replace("http", "ws") + "/topics/joint_states/stream?rate=10");
    ws.onopen = () => done("open"); ws.onerror = () => done("refused");
  }});
  results.done = true;
}}
attack();
</script>"""


@pytest.fixture(scope="module")
def lab():
    with running_server("--view", "none") as server:
        yield server.url


@pytest.fixture(scope="module")
def evil_site(lab):
    page = ATTACK.format(lab=lab).encode()

    class Handler(BaseHTTPRequestHandler):
        def do_GET(self):
            self.send_response(200)
            self.send_header("content-type", "text/html")
            self.end_headers()
            self.wfile.write(page)

        def log_message(self, *args):
            pass

    server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


def test_a_page_on_another_origin_cannot_drive_the_lab(lab, evil_site):
    from playwright.sync_api import sync_playwright

    http.post(f"{lab}/services/stop_cooperative_lifting")
    before = {
        name: http.get(f"{lab}/params/keytwist/{name}").json()["value"] for name in ("linear_speed", "angular_speed")
    }
    health = http.get(f"{lab}/health").json()
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            page = browser.new_page()
            page.set_default_timeout(60_000)
            page.goto(evil_site + "/")
            page.wait_for_function("window.results && window.results.done === true")
            results = page.evaluate("window.results")
            page.wait_for_timeout(500)  # let the form POST land
            assert results["ws"] == "refused"
            assert results["put"] in (403, "blocked")  # the preflighted PUT never gets through
            after = {name: http.get(f"{lab}/params/keytwist/{name}").json()["value"] for name in before}
            assert after == before
            assert http.get(f"{lab}/topics/lifting_state").json()["started"] is False
            now = http.get(f"{lab}/health").json()  # not reset: sim time ran on with the ticks (1 ms each)
            assert now["sim_time"] - health["sim_time"] == pytest.approx(
                (now["ticks"] - health["ticks"]) * 1e-3, abs=0.05
            )
            # the lab's own page: the same requests from its origin go through
            page.goto(lab + "/")
            status = page.evaluate("""async () => {
                const r = await fetch('/services/add_two_ints', {method: 'POST', headers: {'content-type': 'application/json'},
                                                                  body: JSON.stringify({a: 1, b: 2})});
                const ws = await new Promise(done => { const w = new WebSocket(location.origin.replace('http', 'ws') +
                    '/topics/joint_states/stream?rate=10'); w.onmessage = () => { w.close(); done('open'); };
                    w.onerror = () => done('refused'); });
                return [r.status, await r.json(), ws];
            }""")
            assert status == [200, {"sum": 3}, "open"]
        finally:
            browser.close()
