"""Grading the services exercises over HTTP. An instructor points it at a student's running server:

    HRI_LAB_URL=http://127.0.0.1:8000 .venv/bin/python -m pytest tests/grading -v

Without HRI_LAB_URL it starts the lab's own server (how `make test` checks the suite itself)."""
import os

import httpx
import pytest


@pytest.fixture(scope="session")
def lab_url():
    url = os.environ.get("HRI_LAB_URL")
    if url:
        yield url.rstrip("/")
        return
    from app.cli.launch import running_server

    with running_server("--view", "none") as server:
        yield server.url


@pytest.fixture(scope="session")
def call(lab_url):
    def call(service: str, body: dict | None = None) -> httpx.Response:
        return httpx.post(f"{lab_url}/services/{service.lstrip('/')}", json=body if body is not None else {}, timeout=10.0)

    return call
