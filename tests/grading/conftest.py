"""Grading the services exercises over HTTP. An instructor points it at a student's running server:

    HRI_LAB_URL=http://127.0.0.1:8000 .venv/bin/python -m pytest tests/grading -v

Without HRI_LAB_URL it starts the lab's own server (how `make test` checks the suite itself)."""
import os
import socket
import subprocess
import sys
import time

import httpx
import pytest


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="session")
def lab_url():
    url = os.environ.get("HRI_LAB_URL")
    if url:
        yield url.rstrip("/")
        return
    port = _free_port()
    proc = subprocess.Popen([sys.executable, "-m", "app.cli", "serve", "--port", str(port), "--view", "none"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    url = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + 90
    while time.monotonic() < deadline:
        try:
            if httpx.get(f"{url}/health", timeout=1.0).status_code == 200:
                break
        except httpx.HTTPError:
            time.sleep(0.2)
    yield url
    proc.terminate()
    proc.wait(timeout=10)


@pytest.fixture(scope="session")
def call(lab_url):
    def call(service: str, body: dict | None = None) -> httpx.Response:
        return httpx.post(f"{lab_url}/services/{service.lstrip('/')}", json=body if body is not None else {}, timeout=10.0)

    return call
