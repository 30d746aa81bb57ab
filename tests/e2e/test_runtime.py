"""The simulation process under its supervisor: a killed simulation is restarted, calls in the gap
are a 503 naming the restart, and the restarted process holds none of the server's sockets."""

import os
import signal
import stat
import time

import httpx

from tests.e2e.serving import running_server
from tests.waiting import child_named, wait_for


def _sockets(pid: int) -> int:
    count = 0
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            count += stat.S_ISSOCK(os.stat(f"/proc/{pid}/fd/{fd}").st_mode)
        except OSError:
            pass
    return count


def test_a_keep_alive_client_goes_on_across_a_restart_of_the_simulation():
    with running_server("--view", "none") as server, httpx.Client(base_url=server.url, timeout=20.0) as client:
        assert client.post("/services/add_two_ints", json={"a": 1, "b": 2}).json() == {"sum": 3}  # connection kept
        simulation = child_named(server.proc.pid, "hri-lab-sim")
        os.kill(simulation, signal.SIGKILL)
        statuses = []
        for _ in range(20):  # the same kept-alive connection, during and after the restart
            response = client.post("/services/start_cooperative_lifting", json={"force": 10})
            statuses.append(response.status_code)
            if response.status_code == 503:
                assert "restart" in response.json()["detail"]
            time.sleep(0.05)
        assert set(statuses) <= {200, 503}, statuses
        assert wait_for(lambda: client.get("/health").json()["loop_restarts"] >= 1)
        assert client.get("/health").json()["last_loop_death"] == "simulation process killed by SIGKILL"
        assert client.post("/services/start_cooperative_lifting", json={"force": 10}).status_code == 200
        restarted = child_named(server.proc.pid, "hri-lab-sim", other_than=simulation)
        assert _sockets(restarted) == 1  # its own pipe to the server, none of the server's sockets
        assert _sockets(server.proc.pid) > 1  # (the server's listening socket and connection, for contrast)


def _die(world) -> None:
    """A command that ends the simulation process the way a crash in native code would."""
    os.kill(os.getpid(), signal.SIGKILL)


def test_a_call_while_the_simulation_restarts_is_a_503_naming_the_restart(client, lab):
    """The call in flight when the simulation dies fails with the restart's reason; over HTTP that
    is a 503 with Retry-After, and the lab answers again once the fresh process runs."""
    from app.runtime.process import SimulationRestarting

    client.app.add_api_route("/test/die", lambda: lab.call(_die), methods=["POST"])
    response = client.post("/test/die")
    assert response.status_code == 503
    assert response.headers["retry-after"] == "1"
    assert response.json()["detail"] == "the simulation restarted (simulation process killed by SIGKILL); call again"
    wait_for(lambda: client.get("/params/cooperative_lifting/mu").status_code == 200)
    try:
        lab.call(_die)
    except SimulationRestarting as exc:
        assert "killed by SIGKILL" in str(exc)  # noqa: PT017 - the exception's text is the subject, checked where it is caught
    else:
        raise AssertionError("a call whose process died must fail")
    wait_for(lambda: client.get("/health").json()["loop_alive"])


def test_the_shared_snapshot_reads_back_what_was_written_also_after_another_writer():
    """The seqlock copy in shared memory: arrays, numbers, bools, ints and texts come back as
    written; a text longer than its slot is cut; an unchanged text is not written again, unless
    another writer (a forked, restarted simulation) wrote in between."""
    from dataclasses import dataclass, field

    import numpy as np

    from app.runtime.shared_snapshot import TEXT_SLOT, SharedSnapshot

    @dataclass
    class Inner:
        ok: bool = False
        count: int = 0
        note: str | None = None

    @dataclass
    class Record:
        time: float = 0.0
        q: np.ndarray = field(default_factory=lambda: np.zeros(7))
        pose: np.ndarray = field(default_factory=lambda: np.eye(4))
        error: str | None = None
        inner: Inner = field(default_factory=Inner)

    shared = SharedSnapshot(Record())
    shared.write(Record())
    record = Record(1.5, np.arange(7.0), np.arange(16.0).reshape(4, 4), "x" * (2 * TEXT_SLOT), Inner(True, 7, "é"))
    shared.write(record)
    got = shared.read()
    assert (got.time, got.inner) == (1.5, Inner(True, 7, "é"))
    assert np.array_equal(got.q, record.q)
    assert np.array_equal(got.pose, record.pose)
    assert got.error == "x" * (TEXT_SLOT - 2)
    shared.write(Record(2.0, error=None, inner=Inner(note=record.inner.note)))  # the same note object: kept
    assert (shared.read().error, shared.read().inner.note) == (None, "é")

    reader_end, writer_end = os.pipe()
    pid = os.fork()
    if pid == 0:  # another writer (a fork, as a restarted simulation is) writes other texts
        try:
            shared.write(Record(3.0, error=None, inner=Inner(note=None)))
        finally:
            os._exit(0)
    os.waitpid(pid, 0)
    os.close(reader_end), os.close(writer_end)
    shared.write(Record(4.0, error="stopped", inner=Inner(note="é")))  # this process's copy again
    got = shared.read()
    assert (got.time, got.error, got.inner.note) == (4.0, "stopped", "é")
