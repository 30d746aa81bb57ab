"""Grading the services exercises over HTTP, one test per handout service (the items and cases of
`hri-lab grade-services`, app/grading/services.py). An instructor points it at a lab started with
`hri-lab serve --exercises` and the student's node connected:

    HRI_LAB_URL=http://127.0.0.1:8000 HRI_LAB_GRADE_SEED=1234 .venv/bin/python -m pytest tests/exercises -v

Without HRI_LAB_URL it starts the lab's own server and grades the lab's own answers (how `make test`
checks the reference: every item passes)."""

import os

import pytest

from app.grading.services import Grading, LabClient


@pytest.fixture(scope="session")
def lab_url():
    url = os.environ.get("HRI_LAB_URL")
    if url:
        yield url.rstrip("/")
        return
    from app.serving.launch import running_server

    with running_server("--view", "none") as server:
        yield server.url


@pytest.fixture(scope="session")
def grading(lab_url):
    """One grading run: the lab reset, the cases drawn from $HRI_LAB_GRADE_SEED (default 0)."""
    lab = LabClient(lab_url, os.environ.get("HRI_LAB_TOKEN"))
    assert lab.call("reset_simulation").ok
    yield Grading(lab, int(os.environ.get("HRI_LAB_GRADE_SEED", "0")))
    lab.call("reset_simulation")
    lab.close()
