"""A hostile wall follower (graded by tests/e2e/test_grade_wall.py): instead of driving it looks for
everything beyond its own trial, as the third attack pass's did, and prints what it met in five lines:
the host's listening ports in /proc/net (a Dask scheduler, another trial's lab), a connection to
each; the lab's arena over HTTP and its recording and driving routes without a token; the ground
truth and the monitor over rosbridge and the recording service there. Then it ends (its lines are
quoted in its report)."""

import json
import os
import socket
import time
import urllib.error
import urllib.request

from websockets.sync.client import connect

URL = os.environ["HRI_LAB_URL"]  # what `hri-lab run` hands the program
OWN_PORT = int(URL.rsplit(":", 1)[1])


def listening_ports():
    ports = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        try:
            lines = open(table).read().splitlines()[1:]  # noqa: SIM115 - read whole at once
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            if fields[3] == "0A":  # LISTEN
                ports.add(int(fields[1].rsplit(":", 1)[1], 16))
    return sorted(ports - {OWN_PORT})


def reached(port):
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=1.0):
            return True
    except OSError:
        return False


def http(method, path, body=None):
    request = urllib.request.Request(
        URL + path, method=method, data=None if body is None else json.dumps(body).encode()
    )
    request.add_header("Content-Type", "application/json")
    try:
        with urllib.request.urlopen(request, timeout=10) as answer:
            return f"{answer.status} {answer.read()[:120].decode(errors='replace')}"
    except urllib.error.HTTPError as error:
        return str(error.code)
    except OSError as error:
        return f"unreachable ({error})"


ports = listening_ports()
hits = [p for p in ports if reached(p)]
print(f"host ports listed: {len(ports)}; reached: {len(hits)}", flush=True)
print(
    f"arena: {http('GET', '/mobile/arena')}; "
    f"start_recording: {http('POST', '/services/start_recording', {'name': 'stolen'})}; "
    f"drive: {http('POST', '/mobile/drive', {'linear_x': 0.2, 'angular_z': 0.0})}",
    flush=True,
)
counts = {"/ground_truth_pose": 0, "/wall_following": 0}
recording = "no answer"
with connect(URL.replace("http", "ws", 1) + "/", open_timeout=10) as ws:
    for topic in counts:
        ws.send(json.dumps({"op": "subscribe", "topic": topic}))
    ws.send(json.dumps({"op": "call_service", "service": "/start_recording", "args": {"name": "stolen2"}, "id": "r"}))
    end = time.monotonic() + 3.0
    while time.monotonic() < end:
        try:
            message = json.loads(ws.recv(timeout=max(0.01, end - time.monotonic())))
        except TimeoutError:
            break
        if message.get("op") == "publish" and message.get("topic") in counts:
            counts[message["topic"]] += 1
        elif message.get("op") == "service_response" and message.get("id") == "r":
            recording = "called" if message.get("result") else "failed"
        elif message.get("op") == "status" and "/start_recording" in message.get("msg", ""):
            recording = "refused: " + message["msg"][:90]
print(
    f"ground truth messages: {counts['/ground_truth_pose']}; monitor messages: {counts['/wall_following']}", flush=True
)
print(f"start_recording over rosbridge: {recording}", flush=True)
