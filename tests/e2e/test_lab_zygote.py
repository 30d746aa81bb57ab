"""The suite's labs forked from its zygote (tests/lab_zygote.py) are `hri-lab serve` as the command
starts it: the same banner, the same end on SIGTERM, the test's environment and working folder,
a process group of its own when asked, and the test run waits for it as for any child. A command
forked from it (`run_command`: grade, experiment, ...) prints and ends as `subprocess.run` of the
command itself."""

import os
import signal
import subprocess
import sys

import pytest

from app.serving.launch import ServerProcess, free_port, stop_group
from tests import lab_zygote
from tests.e2e.serving import running_server
from tests.http_client import http
from tests.lab_zygote import ForkedServer
from tests.waiting import child_named, process_gone, wait_for

TOKEN = "z9gote-z9gote-z9gote"


def banner(server) -> list[str]:
    """The lines it printed until ready, its port masked."""
    text = server.banner.replace(str(server.port), "PORT")
    return [line for line in text.splitlines() if line.strip()]


def test_a_forked_lab_prints_serves_and_ends_as_the_command_does():
    command = ServerProcess("--view", "none")
    try:
        forked = ForkedServer("--view", "none")
        try:
            assert banner(forked) == banner(command)
            assert http.get(f"{forked.url}/health").json()["loop_alive"] is True
            assert os.getppid() != forked.proc.pid and forked.proc.poll() is None
        finally:
            forked.stop()
    finally:
        command.stop()
    assert forked.proc.returncode == command.proc.returncode == -signal.SIGTERM


def test_the_tests_environment_and_folder_are_the_labs(tmp_path, monkeypatch):
    (tmp_path / "params.yaml").write_text("keytwist:\n  ros__parameters:\n    linear_speed: 0.3\n")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HRI_LAB_TOKEN", TOKEN)  # `serve --token`'s default
    with running_server("--view", "none", "--params", "params.yaml") as server:  # a path from the test's folder
        assert http.get(f"{server.url}/params/keytwist/linear_speed").json()["value"] == 0.3
        refused = http.post(f"{server.url}/services/add_two_ints", json={"a": 1, "b": 2})
        assert refused.status_code == 401
        answer = http.post(
            f"{server.url}/services/add_two_ints", json={"a": 1, "b": 2}, headers={"Authorization": f"Bearer {TOKEN}"}
        )
        assert answer.json() == {"sum": 3}


def test_a_zygote_started_from_a_tests_own_folder_serves_its_labs(tmp_path, monkeypatch):
    """A worker's first lab may come from a test that moved to a folder of its own (as the test above
    does): the zygote still starts from the checkout (it failed with `No module named 'tests'` when
    xdist gave that test a worker first), and the lab works in the test's folder."""
    lab_zygote.close()  # this worker's: the next lab starts another
    (tmp_path / "params.yaml").write_text("keytwist:\n  ros__parameters:\n    linear_speed: 0.3\n")
    monkeypatch.chdir(tmp_path)
    with running_server("--view", "none", "--params", "params.yaml") as server:
        assert http.get(f"{server.url}/params/keytwist/linear_speed").json()["value"] == 0.3


def test_a_lab_in_a_session_of_its_own_is_stopped_with_its_group():
    server = ForkedServer("--view", "none", own_session=True)
    try:
        assert os.getpgid(server.proc.pid) == server.proc.pid != os.getpgid(0)
        simulation = child_named(server.proc.pid, "hri-lab-sim")
        assert os.getpgid(simulation) == server.proc.pid
    finally:
        stop_group(server.proc, 10.0)
    assert server.proc.returncode is not None
    wait_for(lambda: process_gone(simulation))  # with its group


def test_the_zygote_ends_by_itself_when_the_run_closes_it():
    """At the session's end (tests/conftest.py) the zygote sees its requests end and exits 0, rather
    than being killed after close()'s bound: each worker's end waited that bound before."""
    running = lab_zygote.zygote()  # this worker's (the next lab starts another)
    lab_zygote.close()
    assert running.process.returncode == 0


@pytest.mark.parametrize(
    "arguments",
    [
        ("grade", "/nonexistent.py", "--quiet"),  # its refusal on stdout, its exit status 1
        ("experiment", "--trials", "0"),  # argparse's error on stderr, exit status 2
        ("experiment", "--trials", "1", "--participant", "calm", "--json", "--quiet"),  # a trial's JSON on stdout
    ],
)
def test_a_forked_command_prints_and_ends_as_the_command_does(arguments, tmp_path):
    """`run_command` as `subprocess.run` gives a command started itself: the same stdout, the same
    stderr apart from it and the same exit status, in the test's folder."""
    forked = lab_zygote.run_command(*arguments, timeout=120, cwd=tmp_path)
    started = subprocess.run(
        [sys.executable, "-m", "app.cli", *arguments], capture_output=True, text=True, timeout=120, cwd=tmp_path
    )
    assert (forked.returncode, forked.stdout, forked.stderr) == (started.returncode, started.stdout, started.stderr)
    assert forked.stdout or forked.stderr


def test_a_forked_command_past_its_bound_is_killed_as_subprocess_run_kills_it():
    """A command that never ends by itself (a lab) past `timeout`: TimeoutExpired, and the process
    gone (the run fails a test that leaves one behind)."""
    with pytest.raises(subprocess.TimeoutExpired):
        lab_zygote.run_command("serve", "--view", "none", "--port", str(free_port()), timeout=1.0)
