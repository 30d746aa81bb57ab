"""The attack suite's definitions (docs/operations.md): what a client's carried .srv text can cost
the lab. A 2-byte call of a service whose request nests a fixed-size array made the server build
every default item (30 million: +830 MB, /health blocked 3.4 s); now a definition's default holds
at most MAX_DEFAULT_VALUES values, refused with its line at advertise_service, and a call at the cap
leaves the server's peak memory within PEAK_BOUND."""

import json
import threading

from websockets.sync.client import connect

from interfaces.parser import MAX_DEFAULT_VALUES, MAX_FIXED_ARRAY
from tests.e2e.serving import served_lab
from tests.http_client import http
from tests.waiting import wait_for

lab = served_lab()

PEAK_BOUND = 64 << 20  # bytes the server's peak resident memory may grow by for one call at the cap


def _definition(items: int) -> str:
    return f"p/In i\n---\nint64 n\n================================================================================\nMSG: p/In\nfloat64[{items}] v\n"


def _peak(pid: int) -> int:
    """The process's peak resident memory (VmHWM), bytes."""
    with open(f"/proc/{pid}/status") as handle:
        return next(int(line.split()[1]) << 10 for line in handle if line.startswith("VmHWM:"))


def _status(ws) -> dict:
    while True:
        frame = json.loads(ws.recv(timeout=30))
        if frame.get("op") == "status":
            return frame


def test_a_fixed_array_beyond_the_cap_is_refused_with_its_line(lab):
    with connect(f"ws://127.0.0.1:{lab.port}/") as ws:
        ws.send(json.dumps({"op": "set_level", "level": "error"}))
        ws.send(
            json.dumps(
                {"op": "advertise_service", "service": "/big", "type": "p/Big", "definition": _definition(30_000_000)}
            )
        )
        status = _status(ws)
    assert status["level"] == "error"
    assert f"line 1: a fixed-size array of at most {MAX_FIXED_ARRAY} items, got 30000000" in status["msg"]
    assert http.get(f"{lab.url}/services/big").status_code == 404


def test_a_two_byte_call_at_the_cap_leaves_the_servers_peak_memory_bounded(lab):
    """{"i":{}} at the cap: the lab builds the default (MAX_DEFAULT_VALUES floats), checks it and
    sends it to the node, which answers; the server's peak memory grows by less than PEAK_BOUND."""
    before = _peak(lab.proc.pid)
    received: list[int] = []
    with connect(f"ws://127.0.0.1:{lab.port}/", max_size=None) as ws:
        definition = _definition(MAX_DEFAULT_VALUES)
        ws.send(
            json.dumps({"op": "advertise_service", "service": "/at_cap", "type": "p/AtCap", "definition": definition})
        )
        wait_for(lambda: http.get(f"{lab.url}/services/at_cap").status_code == 200)

        def answer() -> None:
            while True:
                frame = json.loads(ws.recv(timeout=60))
                if frame.get("op") == "call_service":
                    received.append(len(frame["args"]["i"]["v"]))
                    ws.send(
                        json.dumps(
                            {
                                "op": "service_response",
                                "id": frame["id"],
                                "service": "/at_cap",
                                "result": True,
                                "values": {"n": 1},
                            }
                        )
                    )
                    return

        node = threading.Thread(target=answer)
        node.start()
        reply = http.post(
            f"{lab.url}/services/at_cap", content=b'{"i":{}}', headers={"content-type": "application/json"}, timeout=60
        )
        node.join(timeout=60)
    assert reply.status_code == 200, reply.text
    assert reply.json() == {"n": 1}
    assert received == [MAX_DEFAULT_VALUES]
    assert _peak(lab.proc.pid) - before < PEAK_BOUND
