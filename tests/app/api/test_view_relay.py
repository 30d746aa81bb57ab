"""app/api/view_relay.py: the 3D view's page fetched from the view's server through the lab's port
(here a plain HTTP server in a thread stands for viser's), and a lab's start without httpx, which
the relay imports when it relays (a start of `hri-lab serve` is ~0.25 s of CPU less)."""

import http.server
import subprocess
import sys
import threading
from pathlib import Path
from types import SimpleNamespace

from fastapi import FastAPI
from fastapi.testclient import TestClient

from app.api import view_relay

ROOT = Path(__file__).resolve().parents[3]


class _ViewPage(http.server.BaseHTTPRequestHandler):
    def do_GET(self):
        body = b"<html>viser</html>"
        self.send_response(200)
        self.send_header("Content-Type", "text/html")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, *args):
        pass


def test_the_views_page_is_relayed_and_a_404_when_the_view_is_off():
    view = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _ViewPage)
    threading.Thread(target=view.serve_forever, daemon=True).start()
    try:
        app = FastAPI()
        app.include_router(view_relay.router)
        client = TestClient(app)
        app.state.view = None
        off = client.get(view_relay.PATH)
        assert (off.status_code, off.json()) == (404, {"detail": "the 3D view is off"})
        app.state.view = SimpleNamespace(url=f"http://127.0.0.1:{view.server_address[1]}")
        page = client.get(view_relay.PATH)
        assert (page.status_code, page.text) == (200, "<html>viser</html>")
        assert page.headers["content-type"].startswith("text/html")
    finally:
        view.shutdown()
        view.server_close()


def test_the_servers_modules_import_without_httpx():
    program = "import sys, app.cli.serve, app.serving.serve; print('httpx' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert done.stdout.strip() == "False", done.stdout + done.stderr
