"""Faults, concurrency and access: the server holds."""

import os
import random
import signal
import subprocess
import sys
import threading

import pytest

from app.api.access import is_loopback
from app.lab import commands as cmd
from tests.e2e.serving import running_server
from tests.http_client import http
from tests.waiting import wait_for


def test_concurrent_start_stop_and_parameter_writes_never_mix_the_state(client, lab):
    """8 threads start (with their own force), stop and change the band at random; every state the
    controller is ever in is one a single request could have left: running <=> f_n_min > 0, and
    f_n_max = f_n_min + f_n_band."""
    errors, seen = [], []
    stop = threading.Event()

    def worker(k: int) -> None:
        rng = random.Random(k)
        for _ in range(40):
            action = rng.random()
            if action < 0.4:
                r = client.post("/services/start_cooperative_lifting", json={"force": float(5 + k)})
            elif action < 0.8:
                r = client.post("/services/stop_cooperative_lifting")
            else:
                r = client.put("/params/cooperative_lifting/f_n_band", json={"value": float(rng.choice([3, 5, 8]))})
            if r.status_code != 200:
                errors.append(r.text)

    def watcher() -> None:
        while not stop.is_set():
            seen.append(lab.call(cmd.lifting_state))

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(8)]
    watch = threading.Thread(target=watcher)
    watch.start()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    stop.set()
    watch.join()
    assert not errors
    assert len(seen) > 10
    for running, f_min, band, f_max in seen:
        assert running == (f_min > 0), (running, f_min)
        assert f_min in {0.0} | {float(5 + k) for k in range(8)}
        assert f_max == f_min + band
    client.post("/services/stop_cooperative_lifting")
    client.put("/params/cooperative_lifting/f_n_band", json={"value": 5.0})


def _kill_the_loop_thread(world) -> None:
    """The next step raises SystemExit (which no `except Exception` catches), once."""

    def step() -> None:
        del world.step
        raise SystemExit("killed by a test")

    world.step = step


def test_a_dead_loop_thread_is_reported_and_restarted(client, lab):
    """Something escapes a step and ends the loop (SystemExit): /health reports why, and the
    supervisor starts a fresh simulation process."""
    lab.call(_kill_the_loop_thread)
    wait_for(lambda: lab.runtime.health().restarts >= 1)
    health = client.get("/health").json()
    assert health["loop_restarts"] >= 1
    assert "SystemExit: killed by a test" in health["last_loop_death"]
    t0 = client.get("/health").json()["sim_time"]
    wait_for(lambda: client.get("/health").json()["sim_time"] > t0 + 0.1)  # stepping again
    assert client.get("/health").json()["loop_alive"] is True


def test_a_killed_simulation_process_is_reported_and_restarted(client, lab):
    """The simulation runs in its own process: SIGKILL it (as a crash in native code would end it).
    /health says so, a fresh simulation process takes over and the API keeps answering."""
    pid = lab.runtime.pid
    os.kill(pid, signal.SIGKILL)
    wait_for(lambda: lab.runtime.pid not in (None, pid) and lab.runtime.health().alive)
    health = client.get("/health").json()
    assert health["last_loop_death"] == "simulation process killed by SIGKILL"
    assert health["loop_restarts"] >= 1
    assert health["loop_alive"] is True
    t0 = health["sim_time"]
    wait_for(lambda: client.get("/health").json()["sim_time"] > t0 + 0.1)  # the new process steps
    assert client.post("/services/start_cooperative_lifting", json={"force": 10}).status_code == 200
    assert lab.call(cmd.lifting_state)[:2] == (True, 10.0)
    client.post("/services/stop_cooperative_lifting")


def test_loopback_detection():
    assert is_loopback("127.0.0.1")
    assert is_loopback("127.3.4.5")
    assert is_loopback("::1")
    assert is_loopback("localhost")
    assert not is_loopback("0.0.0.0")
    assert not is_loopback("10.1.2.3")


def test_binding_another_address_needs_a_token():
    run = subprocess.run(
        [sys.executable, "-m", "app.cli", "serve", "--host", "0.0.0.0", "--port", "0", "--view", "none"],
        capture_output=True,
        text=True,
        timeout=60,
        env={k: v for k, v in __import__("os").environ.items() if k != "HRI_LAB_TOKEN"},
    )
    assert run.returncode == 2
    assert "needs a token" in run.stderr


@pytest.fixture(scope="module")
def guarded_server():
    with running_server("--view", "none", "--token", "s3cret-s3cret-s3cret") as server:
        yield server.url


def test_a_change_without_the_token_is_refused(guarded_server):
    url = guarded_server
    refused = http.post(f"{url}/services/start_cooperative_lifting", json={"force": 10})
    assert refused.status_code == 401
    assert "token" in refused.json()["detail"]
    assert http.put(f"{url}/params/keytwist/linear_speed", json={"value": 0.2}).status_code == 401
    wrong = http.post(f"{url}/services/add_two_ints", json={"a": 1, "b": 2}, headers={"Authorization": "Bearer nope"})
    assert wrong.status_code == 401
    assert http.get(f"{url}/topics/lifting_state").json()["started"] is False  # nothing changed
    # reading stays open; with the token, changes go through
    assert http.get(f"{url}/services").status_code == 200
    ok = http.post(
        f"{url}/services/start_cooperative_lifting",
        json={"force": 10},
        headers={"Authorization": "Bearer s3cret-s3cret-s3cret"},
    )
    assert ok.status_code == 200
    assert http.post(
        f"{url}/services/add_two_ints", json={"a": 1, "b": 2}, headers={"X-HRI-Lab-Token": "s3cret-s3cret-s3cret"}
    ).json() == {"sum": 3}
    # the CLI sends $HRI_LAB_TOKEN
    env = dict(__import__("os").environ, HRI_LAB_URL=url, HRI_LAB_TOKEN="s3cret-s3cret-s3cret")
    out = subprocess.run(
        [sys.executable, "-m", "app.cli", "param", "set", "/keytwist", "linear_speed", "0.2"],
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    assert out.stdout.strip() == "Set parameter successful"
