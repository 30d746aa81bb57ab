"""The simulation's process (app/runtime/process.py): stopped, its answers' reader ends before the
pipe it reads is closed (closed under a read, the reader's thread died of a TypeError: a busy
`make test` showed it as an unhandled thread exception)."""

from sim.world import World, WorldConfig

from app.runtime.process import SimulationProcess
from tests.waiting import wait_for


def test_stop_ends_the_answers_reader_before_it_closes_the_pipe():
    process = SimulationProcess(World(WorldConfig()))
    process.start()
    conn, reader = process._conn, process._receiver
    assert conn is not None
    reading_at_close = []
    close = conn.close

    def closing() -> None:
        reading_at_close.append(reader.is_alive())
        close()

    conn.close = closing  # type: ignore[method-assign]  # a spy
    try:
        wait_for(lambda: process.health().alive, timeout=60)
    finally:
        process.stop()
    assert reading_at_close == [False]
