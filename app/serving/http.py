"""The HTTP server's limits, in uvicorn's configuration (besides the body limit, app/security.py): a
request must arrive whole (headers and body) within READ_TIMEOUT_S of its first byte (or of the
connection's opening), an idle keep-alive connection is closed after KEEP_ALIVE_S, headers are at most
64 KiB (h11/httptools), WebSocket messages go uncompressed as rosbridge_server sends them by default
(`use_compression` false: no permessage-deflate, whatever the client offers), and a shutdown (Ctrl+C,
SIGTERM) closes every connection and stream within SHUTDOWN_S. `hri-lab serve` and a graded wall
trial's lab serve with them."""

import asyncio

import uvicorn
from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

from app.rosbridge.protocol import MAX_FRAME

READ_TIMEOUT_S = 10.0
KEEP_ALIVE_S = 5
WS_PING_TIMEOUT_S = 60.0  # a rosbridge client's pong may wait behind its backlog of a 1 kHz topic on a busy machine
SHUTDOWN_S = 3


def server_config(
    app, host: str, port: int, read_timeout_s: float = READ_TIMEOUT_S, uds: str | None = None
) -> uvicorn.Config:
    """uvicorn's configuration with the server's limits (see the module's docstring); uds: served
    on that Unix socket instead of host:port (a graded trial's lab: app/grading/wall_trial.py)."""
    protocol = type("TimedProtocol", (TimedHttpProtocol,), {"read_timeout_s": read_timeout_s})
    return uvicorn.Config(
        app,
        host=host,
        port=port,
        uds=uds,
        log_level="warning",
        access_log=False,
        http=protocol,
        timeout_keep_alive=KEEP_ALIVE_S,
        timeout_graceful_shutdown=SHUTDOWN_S,
        h11_max_incomplete_event_size=64 * 1024,
        ws_max_size=2 * MAX_FRAME,  # bytes; a longer rosbridge frame is refused by the session
        ws_ping_timeout=WS_PING_TIMEOUT_S,
        ws_per_message_deflate=False,
    )


class TimedHttpProtocol(HttpToolsProtocol):
    """httptools' protocol with a read timeout: a request not received whole within read_timeout_s
    of its first byte (a new connection: of its opening) closes the connection (slow-loris)."""

    read_timeout_s = READ_TIMEOUT_S
    _read_timer: asyncio.TimerHandle | None = None

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]  # uvicorn's own signature
        super().connection_made(transport)
        self._read_timer = self.loop.call_later(self.read_timeout_s, self._read_timed_out)

    def on_message_begin(self) -> None:
        super().on_message_begin()
        if self._read_timer is None:
            self._read_timer = self.loop.call_later(self.read_timeout_s, self._read_timed_out)

    def on_message_complete(self) -> None:
        super().on_message_complete()
        self._cancel_read_timer()

    def handle_websocket_upgrade(self) -> None:
        self._cancel_read_timer()
        super().handle_websocket_upgrade()

    def connection_lost(self, exc: Exception | None) -> None:
        self._cancel_read_timer()
        super().connection_lost(exc)

    def _cancel_read_timer(self) -> None:
        if self._read_timer is not None:
            self._read_timer.cancel()
            self._read_timer = None

    def _read_timed_out(self) -> None:
        self._read_timer = None
        if self.cycle is not None and not self.cycle.response_complete:
            self.cycle.disconnected = True  # the route reading the body sees the client gone
            self.cycle.message_event.set()
        if not self.transport.is_closing():
            self.transport.close()
