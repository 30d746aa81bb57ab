"""The numbered scripts of examples/ run as a user runs them (against a real server where they need one)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.e2e.serving import running_server

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def lab_url():
    with running_server("--view", "none") as server:
        yield server.url


def run(name: str, url: str | None = None) -> str:
    env = {**os.environ, "PYTHONPATH": str(EXAMPLES.parent)} | ({"HRI_LAB_URL": url} if url else {})
    done = subprocess.run([sys.executable, str(EXAMPLES / name)], capture_output=True, text=True, timeout=300, env=env)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def test_every_example_is_tested():
    tested = {"01_call_a_service.py", "02_stream_f_ext.py", "03_run_a_trial.py", "04_grade_a_file.py"}
    assert {p.name for p in EXAMPLES.glob("*.py")} == tested


# 03 and 04 need no server: they run first, so the server of 01 and 02 lives only while they run
def test_03_run_a_trial():
    out = run("03_run_a_trial.py")
    assert out.startswith("success: True")
    assert "slip in the palm" in out


def test_04_grade_a_file():
    """The untouched template, sandboxed: its probes run and most fail (it commands zero twist)."""
    out = run("04_grade_a_file.py")
    assert "hri-lab grade (controller):" in out
    assert "probe: " in out
    assert "FAIL" in out
    assert '"max_score": 5' in out


def test_01_call_a_service(lab_url):
    out = run("01_call_a_service.py", lab_url)
    assert "int64 a\nint64 b\n---\nint64 sum" in out
    assert "sum: 42" in out
    assert "refused: 422 a" in out
    assert "band: [10, 15] N, started: True" in out
    assert "stopped" in out


def test_02_stream_f_ext(lab_url):
    lines = [line for line in run("02_stream_f_ext.py", lab_url).splitlines() if line.startswith("t = ")]
    assert len(lines) == 40
    stamps = [float(line.split()[2]) for line in lines]
    assert stamps == sorted(stamps)
    assert stamps[-1] > stamps[0]
