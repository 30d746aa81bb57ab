"""`hri-lab serve`: the lab's server on 127.0.0.1 (embedded defaults; optional parameter file).

Limits of the HTTP server (besides the body limit, app/security.py): a request must arrive
whole (headers and body) within READ_TIMEOUT_S of its first byte (or of the connection's
opening), an idle keep-alive connection is closed after KEEP_ALIVE_S, headers are at most 64 KiB
(h11/httptools), and a shutdown (Ctrl+C, SIGTERM) closes every connection and stream within
SHUTDOWN_S."""

import argparse
import asyncio
import sys
from dataclasses import replace
from pathlib import Path

import uvicorn
from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

from sim.controllers.plugin import PluginFactory
from sim.mobile.world import seeded_config

from app.api.access import is_loopback
from app.cli.compose import create_app
from app.cli.controllers import loaded_factory
from app.lab.lab import Lab
from app.mobile.lab import MobileLab
from app.ros.params import ParameterRefused, read_parameter_file
from app.rosbridge.protocol import MAX_FRAME
from app.tokens import TOKEN_ENV, token_problem


def load_parameter_file(lab: Lab | MobileLab, path: str) -> None:
    """Apply a `param dump` file at start (the seed's launch file); read-only ones too, as
    parameter overrides can at declaration. Any refusal stops the start with its reason."""
    results = lab.params.load(read_parameter_file(path), force=True)
    failed = [r for r in results if not r["successful"]]
    if failed:
        raise ParameterRefused("; ".join(f"/{r['node']}/{r['name']}: {r['reason']}" for r in failed))


def serve(
    host: str = "127.0.0.1",
    port: int = 8000,
    params_file: str | None = None,
    view: str = "full",
    view_port: int = 8080,
    controller=None,
    token: str | None = None,
    exercises: bool = False,
    output_dir: str = ".",
    world: str = "lifting",
    arena_seed: int | None = None,
    replay: bool = False,
    no_token: bool = False,
) -> int:
    if not is_loopback(host) and not token and not no_token:
        print(
            f"hri-lab: binding {host} (not this machine only) needs a token: --token or ${TOKEN_ENV} "
            "(inside a container whose port the host publishes on its loopback: --no-token)",
            file=sys.stderr,
        )
        return 2
    if token and token_problem(token):
        print(f"hri-lab: {token_problem(token)}", file=sys.stderr)
        return 2
    lab: Lab | MobileLab
    if world == "mobile":
        lab = MobileLab(seeded_config(arena_seed) if arena_seed is not None else None)
    else:
        lab = Lab(controller=controller)
    lab.recordings_dir, lab.figures_dir = Path(output_dir) / "recordings", Path(output_dir) / "figures"
    if params_file:
        try:
            load_parameter_file(lab, params_file)
        except (OSError, ParameterRefused) as exc:
            print(f"hri-lab: cannot load parameters from {params_file}: {exc}", file=sys.stderr)
            return 2
    app = create_app(
        lab, view=view, view_host=host, view_port=view_port, token=token, exercises=exercises, replay=replay
    )
    server = AnnouncingServer(server_config(app, host, port))
    try:
        server.run()
    except KeyboardInterrupt:  # Ctrl+C: the server shut down first (uvicorn, or asyncio's runner, re-raises it)
        pass  # the lab stops as asked: no traceback in the terminal
    return 0 if server.started else 1


READ_TIMEOUT_S = 10.0
KEEP_ALIVE_S = 5
WS_PING_TIMEOUT_S = 60.0  # a rosbridge client's pong may wait behind its backlog of a 1 kHz topic on a busy machine
SHUTDOWN_S = 3


def server_config(app, host: str, port: int, read_timeout_s: float = READ_TIMEOUT_S) -> uvicorn.Config:
    """uvicorn's configuration with the server's limits (see the module's docstring)."""
    protocol = type("TimedProtocol", (TimedHttpProtocol,), {"read_timeout_s": read_timeout_s})
    return uvicorn.Config(
        app,
        host=host,
        port=port,
        log_level="warning",
        access_log=False,
        http=protocol,
        timeout_keep_alive=KEEP_ALIVE_S,
        timeout_graceful_shutdown=SHUTDOWN_S,
        h11_max_incomplete_event_size=64 * 1024,
        ws_max_size=2 * MAX_FRAME,  # bytes; a longer rosbridge frame is refused by the session
        ws_ping_timeout=WS_PING_TIMEOUT_S,
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


class AnnouncingServer(uvicorn.Server):
    """Prints the URLs once the socket is bound (not before: the port may be taken)."""

    async def startup(self, sockets=None) -> None:
        await super().startup(sockets)
        if self.started:
            base = f"http://{self.config.host}:{self.config.port}"
            view = self.config.app.state.view  # type: ignore[union-attr]  # our FastAPI app, not an import string
            print(
                f"hri-lab is running: open {base}/\n"
                f"  API       {base}/services  {base}/params  {base}/topics  {base}/actions\n"
                f"  API docs  {base}/docs  {base}/redoc\n"
                f"  rosbridge ws://{self.config.host}:{self.config.port}/  (roslibpy.Ros('{self.config.host}', {self.config.port}))\n"
                + (f"  3D view   {view.url}\n" if view is not None else "")
                + "Press Ctrl+C to stop.",
                flush=True,
            )


def run(args: argparse.Namespace) -> int:
    """`hri-lab serve`: the controller chosen (a plug-in file loaded once now, then started in the
    simulation process at its first step), then the server until Ctrl+C."""
    factory = loaded_factory(args.controller)
    if isinstance(factory, PluginFactory):
        factory = replace(factory, eager=False)
    return serve(
        args.host,
        args.port,
        args.params,
        args.view,
        args.view_port,
        factory(),
        args.token,
        exercises=args.exercises,
        replay=args.replay,
        output_dir=args.output_dir,
        world=args.world,
        arena_seed=args.arena_seed,
        no_token=args.no_token,
    )
