"""Limits and timeouts: no input crashes or stalls the server (body size, YAML, echoes, stream
rates, long-polls, half-sent requests, shutdown, tokens)."""

import json
import signal
import socket
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import httpx
import pytest
import uvicorn
from starlette.websockets import WebSocketDisconnect

from app.api.access import Throttle
from app.ros.actions import Action, ActionServer, GoalStatus
from app.ros.messages import Empty
from app.security import MAX_BODY_BYTES
from app.serving.compose import create_app
from app.serving.http import server_config
from tests.e2e.serving import running_server
from tests.http_client import http

YAML = {"content-type": "application/yaml"}


def test_a_body_beyond_the_limit_is_a_413(client):
    big = b"[" + b"1," * (MAX_BODY_BYTES // 2) + b"1]"
    r = client.post("/services/echo", content=big, headers={"content-type": "application/json"})
    assert r.status_code == 413
    assert str(MAX_BODY_BYTES) in r.json()["detail"]

    def chunks():  # no Content-Length: counted while it arrives
        for _ in range(MAX_BODY_BYTES // 1000 + 2):
            yield b" " * 1000

    r = client.post("/services/echo", content=chunks(), headers={"content-type": "application/json"})
    assert r.status_code == 413


def test_refusals_echo_little_and_never_fail_on_what_they_echo(client):
    # a lone UTF-16 surrogate (JSON can carry it, UTF-8 cannot): a clean 422 naming the field
    for path, body in (
        ("/services/echo", b'{"in": "\\ud800"}'),
        ("/services/login", b'{"username": "\\udfff", "magic_number": 1}'),
        ("/services/add_two_ints", b'{"a": "\\ud800", "b": 1}'),
    ):
        r = client.post(path, content=body, headers={"content-type": "application/json"})
        assert r.status_code == 422, (path, r.text)
        assert r.json()["detail"][0]["loc"][:2] == [
            "body",
            json.loads(body).popitem()[0] if path.endswith("echo") else r.json()["detail"][0]["loc"][1],
        ]
    r = client.put(
        "/params/human/profile", content=b'{"value": "\\ud800"}', headers={"content-type": "application/json"}
    )
    assert r.status_code in (422, 200)
    assert r.status_code < 500
    # a huge input is echoed cut short
    r = client.post("/services/add_two_ints", json={"a": "x" * 500_000, "b": list(range(10_000))})
    assert r.status_code == 422
    assert len(r.content) < 5_000
    assert "500000 characters" in r.text


def test_parameter_files_are_parsed_within_limits(client):
    before = client.get("/params/keytwist/linear_speed").json()["value"]
    deep = "a: " + "[" * 5000 + "]" * 5000
    r = client.post("/params/load", content=deep, headers=YAML)
    assert r.status_code == 422
    assert "nests at most" in r.json()["reason"]
    big = "# " + "x" * 100_000 + "\n"
    r = client.post("/params/load", content=big, headers=YAML)
    assert r.status_code == 422
    assert "at most 65536 bytes" in r.json()["reason"]
    bomb = "a: &a [1, 1]\nb: &b [*a, *a]\nc: [*b, *b]\n"
    assert client.post("/params/load", content=bomb, headers=YAML).status_code == 422
    for broken in ("{not: [yaml", "keytwist: {ros__parameters: {linear_speed: 2001-02-30}}", "\t- :"):
        assert client.post("/params/load", content=broken, headers=YAML).status_code == 422, broken
    assert client.get("/params/keytwist/linear_speed").json()["value"] == before


def test_stream_rates_are_bounded(client):
    for rate in ("1e-9", "0.05", "0", "1001", "nan", "inf"):
        with pytest.raises(WebSocketDisconnect):  # noqa: SIM117 - nested on purpose: the inner block's failure is the outer one's subject
            with client.websocket_connect(f"/topics/joint_states/stream?rate={rate}") as ws:
                ws.receive_json()
    with client.websocket_connect("/topics/joint_states/stream?rate=0.1") as ws:
        assert "position" in ws.receive_json()  # the first message at once; the client then goes


def test_the_goal_store_trims_past_a_running_goal():
    release = threading.Event()

    def block(lab, goal, handle):
        release.wait(10)
        return Empty()

    slow = Action("/slow", "t/Slow", Empty, Empty, Empty, block)
    quick = Action("/quick", "t/Quick", Empty, Empty, Empty, lambda lab, goal, handle: Empty())
    server = ActionServer([slow, quick], lab=None)
    running = server.send_goal(slow, Empty())
    for _ in range(3 * server.keep_goals):
        handle = server.send_goal(quick, Empty())
        deadline = time.monotonic() + 5
        while handle.status not in (GoalStatus.SUCCEEDED, GoalStatus.ABORTED) and time.monotonic() < deadline:
            handle.wait_for_update(0, 0.05)
    assert len(server.goals) <= server.keep_goals + 1
    assert running.id in server.goals  # the oldest, still running, stays
    release.set()


def test_wrong_tokens_are_slowed_down():
    now = [0.0]
    throttle = Throttle(clock=lambda: now[0])
    delays = [throttle.fail("10.0.0.1") for _ in range(8)]
    assert delays[:5] == [0.1, 0.2, 0.4, 0.8, 1.6]
    assert delays[-1] == 2.0
    assert throttle.fail("10.0.0.2") == 0.1  # per client
    throttle.succeed("10.0.0.1")
    assert throttle.fail("10.0.0.1") == 0.1
    now[0] += 61.0
    assert throttle.fail("10.0.0.2") == 0.1  # forgotten after a minute


def test_a_short_token_is_refused_at_start():
    with pytest.raises(ValueError, match="at least 16"):
        create_app(token="short")


TOKEN = "s3cret-s3cret-s3cret"
AUTH = {"authorization": f"Bearer {TOKEN}"}


@pytest.fixture(scope="module")
def server():
    with running_server("--view", "none", "--token", TOKEN) as server:
        yield server


def test_long_polls_hold_no_thread(server):
    """60 long-polls (more than the thread pool's 40) wait on a goal; a service call meanwhile is
    answered before any of them returns."""
    url = server.url
    goal = http.post(f"{url}/actions/count/goals", json={"count": 30}, headers=AUTH).json()["goal_id"]
    try:
        poll = f"{url}/actions/count/goals/{goal}"
        # one client, 60 connections (60 clients of their own would cost a loaded machine seconds of CPU)
        with (
            ThreadPoolExecutor(60) as pool,
            httpx.Client(limits=httpx.Limits(max_connections=64), timeout=90) as polling,
        ):
            polls = [pool.submit(polling.get, poll, params={"after": 1000, "wait": 30}) for _ in range(60)]
            time.sleep(1.0)  # let them arrive (none returns before the goal ends or 30 s pass)
            assert http.post(
                f"{url}/services/add_two_ints", json={"a": 1, "b": 2}, headers=AUTH, timeout=30
            ).json() == {"sum": 3}
            ended = [p.result().json() for p in polls if p.done()]
            assert not ended, ended[:1]
            http.post(f"{poll}/cancel", headers=AUTH)  # ends the goal: every long-poll answers
            assert {p.result().json()["status"] for p in polls} <= {"preempting", "preempted"}
    finally:
        http.post(f"{url}/actions/count/goals/{goal}/cancel", headers=AUTH)


def test_a_non_ascii_token_is_a_401_and_shutdown_is_bounded(server):
    from websockets.sync.client import connect

    for token in ("Bearer \xe9t\xe9".encode("latin-1"), "Bearer \u00e9t\u00e9".encode("utf-8"), b"Bearer \xff\xfe"):
        r = http.post(f"{server.url}/services/add_two_ints", json={"a": 1, "b": 2}, headers={"authorization": token})
        assert r.status_code == 401
    # shutdown is bounded whatever is connected: a 0.1 Hz stream and a 30 s long-poll are open
    ws = connect(server.url.replace("http", "ws") + "/topics/joint_states/stream?rate=0.1")
    assert "Sec-WebSocket-Extensions" not in ws.response.headers  # deflate offered, not taken (app/serving/http.py)
    ws.recv()
    goal = http.post(f"{server.url}/actions/count/goals", json={"count": 60}, headers=AUTH).json()["goal_id"]
    with ThreadPoolExecutor(1) as pool:
        poll = pool.submit(
            httpx.get, f"{server.url}/actions/count/goals/{goal}", params={"after": 1000, "wait": 30}, timeout=60
        )
        time.sleep(0.5)
        server.proc.send_signal(signal.SIGTERM)
        server.proc.wait(timeout=20)  # SHUTDOWN_S = 3 s, then the simulation stops
        assert poll.exception(timeout=5) is not None or poll.result().status_code < 500
    ws.close()


def _tiny_app():
    async def app(scope, receive, send):
        if scope["type"] == "lifespan":
            while (await receive())["type"] != "lifespan.shutdown":
                await send({"type": "lifespan.startup.complete"})
            return await send({"type": "lifespan.shutdown.complete"})
        more = True
        while more:
            message = await receive()
            more = message.get("more_body", False)
        await send({"type": "http.response.start", "status": 200, "headers": []})
        await send({"type": "http.response.body", "body": b"ok"})

    return app


def test_half_sent_requests_are_closed():
    """Slow-loris: connections that never finish their headers, or their body, are closed after
    the read timeout (0.5 s here; the server's is READ_TIMEOUT_S); whole requests are served."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = uvicorn.Server(server_config(_tiny_app(), "127.0.0.1", port, read_timeout_s=0.5))
    thread = threading.Thread(target=server.run)
    thread.start()
    try:
        while not server.started:
            time.sleep(0.02)
        partial = [
            b"",
            b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n",
            b"POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 100\r\n\r\nabc",
        ]
        sockets = []
        for data in partial * 2:
            c = socket.create_connection(("127.0.0.1", port))
            c.sendall(data)
            c.settimeout(30)
            sockets.append(c)
        assert http.get(f"http://127.0.0.1:{port}/").text == "ok"
        for c in sockets:
            try:
                received = c.recv(1000)
            except ConnectionResetError:
                received = b""
            assert received == b""  # closed by the server (a timeout here raises instead)
            c.close()
    finally:
        server.should_exit = True
        thread.join(10)
