"""The attack suite's figures (docs/operations.md, "Untrusted input"): what each hostile file or
frame of tests/ costs and how long it takes to its verdict, on this machine.

1. tests/controllers/fills_disk.py (100 files of 15 MiB into /tmp at import, then every other place,
   then memory files): the MiB it got written, and the wall time of its load;
2. tests/controllers/sleeper.py (2 s sleeps on 10 of every 250 steps): the wall time from its
   first step to the fault, and the reason;
3. the 2-byte call (`{"i":{}}`) of a client's service whose request nests a fixed-size array at the
   cap (interfaces/parser.py, MAX_DEFAULT_VALUES): the server's peak resident memory
   (VmHWM) before and after, and the call's wall time; and the refusal of 30 million items;
4. wide services (issue 44): one advertise_service of 4,600 fields (refused: the field cap), then
   clients advertising services of MAX_DEFINITION_FIELDS - 1 fields up to the lab's cap of services
   (app/rosbridge/protocol.py): the longest GET /health meanwhile, the server's resident memory
   (VmRSS) before, with them and after their clients left.

    .venv/bin/python -m bench.attack_figures
"""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import httpx
import numpy as np
from websockets.sync.client import connect

from sim.controllers.interface import ControllerFault, LiftingParams
from sim.controllers.plugin import PluginFactory

from app.rosbridge.protocol import MAX_CLIENT_SERVICES, MAX_SERVICES
from app.serving.launch import running_server
from interfaces.parser import MAX_DEFAULT_VALUES, MAX_DEFINITION_FIELDS

CONTROLLERS = Path(__file__).resolve().parents[1] / "tests" / "controllers"


def fills_disk() -> None:
    started = time.perf_counter()
    controller = PluginFactory(str(CONTROLLERS / "fills_disk.py"))()
    loaded = time.perf_counter() - started
    try:
        tmp, elsewhere, memfds = controller.step(np.zeros(6), np.eye(4), LiftingParams(), 1e-3)[:3]
    finally:
        controller.close()
    print(
        f"fills_disk.py: written {tmp:.0f} MiB in /tmp, {elsewhere:.0f} MiB elsewhere, {memfds:.0f} MiB in memory "
        f"files (1500 MiB asked of each); its load took {loaded:.1f} s wall"
    )


def sleeper() -> None:
    controller = PluginFactory(str(CONTROLLERS / "sleeper.py"))()
    params = LiftingParams()
    started = time.perf_counter()
    try:
        while True:
            controller.step(np.zeros(6), np.eye(4), params, 1e-3)
    except ControllerFault as fault:
        reason = str(fault)
    finally:
        controller.close()
    print(f"sleeper.py: stopped {time.perf_counter() - started:.1f} s wall after its first step: {reason}")


def _peak(pid: int) -> int:
    with open(f"/proc/{pid}/status") as handle:
        return next(int(line.split()[1]) << 10 for line in handle if line.startswith("VmHWM:"))


def _definition(items: int) -> str:
    return f"p/In i\n---\nint64 n\n{'=' * 80}\nMSG: p/In\nfloat64[{items}] v\n"


def two_byte_call() -> None:
    with running_server("--view", "none") as server, httpx.Client(timeout=60.0) as http:  # noqa: SIM117 - nested on purpose: the inner block's failure is the outer one's subject
        with connect(f"ws://127.0.0.1:{server.port}/", max_size=None) as ws:
            ws.send(
                json.dumps(
                    {
                        "op": "advertise_service",
                        "service": "/big",
                        "type": "p/Big",
                        "definition": _definition(30_000_000),
                    }
                )
            )
            refusal = json.loads(ws.recv(timeout=30))
            print(f"float64[30000000]: {refusal['level']}: {refusal['msg'][:160]}")
            ws.send(
                json.dumps(
                    {
                        "op": "advertise_service",
                        "service": "/at_cap",
                        "type": "p/AtCap",
                        "definition": _definition(MAX_DEFAULT_VALUES),
                    }
                )
            )
            while http.get(f"{server.url}/services/at_cap").status_code != 200:
                time.sleep(0.05)

            def answer() -> None:
                while True:
                    frame = json.loads(ws.recv(timeout=60))
                    if frame.get("op") == "call_service":
                        reply = {"op": "service_response", "id": frame["id"], "service": "/at_cap", "result": True}
                        ws.send(json.dumps({**reply, "values": {"n": 1}}))
                        return

            node = threading.Thread(target=answer)
            before = _peak(server.proc.pid)
            node.start()
            started = time.perf_counter()
            reply = http.post(
                f"{server.url}/services/at_cap", content=b'{"i":{}}', headers={"content-type": "application/json"}
            )
            took = time.perf_counter() - started
            node.join(60)
            after = _peak(server.proc.pid)
    print(
        f'{{"i":{{}}}} at the cap (float64[{MAX_DEFAULT_VALUES}]): HTTP {reply.status_code} in {took * 1e3:.0f} ms; '
        f"the server's peak resident memory {before / 2**20:.0f} MiB before, {after / 2**20:.0f} MiB after "
        f"(+{(after - before) / 2**20:.1f} MiB)"
    )


def _rss(pid: int) -> int:
    with open(f"/proc/{pid}/status") as handle:
        return next(int(line.split()[1]) << 10 for line in handle if line.startswith("VmRSS:"))


def _wide(fields: int) -> str:
    return "\n".join(f"int64 f{i}" for i in range(fields)) + "\n---\nbool ok\n"


def wide_services() -> None:
    with running_server("--view", "none") as server, httpx.Client(timeout=120.0) as http:
        url = f"ws://127.0.0.1:{server.port}/"
        with connect(url, max_size=None) as ws:
            ws.send(json.dumps({"op": "advertise_service", "service": "/w", "type": "p/W", "definition": _wide(4600)}))
            refusal = json.loads(ws.recv(timeout=60))
        print(f"4,600 fields: {refusal['level']}: {refusal['msg'][:160]}")
        longest, done = [0.0], threading.Event()

        def probe() -> None:
            while not done.is_set():
                started = time.perf_counter()
                http.get(f"{server.url}/health")
                longest[0] = max(longest[0], time.perf_counter() - started)
                time.sleep(0.05)

        before = _rss(server.proc.pid)
        prober = threading.Thread(target=probe)
        prober.start()
        clients = [connect(url, max_size=None) for _ in range(MAX_SERVICES // MAX_CLIENT_SERVICES)]
        started = time.perf_counter()
        for n, ws in enumerate(clients):
            for i in range(MAX_CLIENT_SERVICES):
                frame = {"op": "advertise_service", "service": f"/w{n}_{i}", "type": "p/W"}
                ws.send(json.dumps({**frame, "definition": _wide(MAX_DEFINITION_FIELDS - 1)}))
        while len([s for s in http.get(f"{server.url}/services").json() if s["name"].startswith("/w")]) < MAX_SERVICES:
            time.sleep(0.2)
        took = time.perf_counter() - started
        held = _rss(server.proc.pid)
        for ws in clients:
            ws.close()
        while any(s["name"].startswith("/w") for s in http.get(f"{server.url}/services").json()):
            time.sleep(0.2)
        time.sleep(1.0)
        done.set()
        prober.join()
        after = _rss(server.proc.pid)
    print(
        f"{MAX_SERVICES} services of {MAX_DEFINITION_FIELDS} fields from {len(clients)} clients: advertised in "
        f"{took:.1f} s, the longest GET /health meanwhile {longest[0] * 1e3:.0f} ms; the server's resident memory "
        f"{before / 2**20:.0f} MiB before, {held / 2**20:.0f} MiB with them, {after / 2**20:.0f} MiB after their "
        "clients left"
    )


def main() -> None:
    fills_disk()
    sleeper()
    two_byte_call()
    wide_services()


if __name__ == "__main__":
    main()
