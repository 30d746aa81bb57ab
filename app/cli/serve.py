"""`hri-lab serve`: the lab's server on 127.0.0.1 (embedded defaults; optional parameter file),
with the HTTP server's limits (app/serving/http.py).

One lab per port: a port already taken (`make run`'s lab on 8000, say) stops the start at once with
what to do, the lab's other port to take (`port_taken`), before anything is built."""

import argparse
import socket
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import uvicorn

from sim.controllers.plugin import PluginFactory

from app.api.access import is_loopback
from app.cli.controllers import loaded_factory
from app.ros.params import ParameterRefused, read_parameter_file
from app.serving.compose import create_app
from app.serving.http import server_config
from app.serving.worlds import DEFAULT, WORLDS
from app.tokens import TOKEN_ENV, token_problem
from app.worlds.contract import LabOptions
from app.worlds.port import LabPort


def load_parameter_file(lab: LabPort[Any], path: str) -> None:
    """Apply a `param dump` file at start (the seed's launch file); read-only ones too, as
    parameter overrides can at declaration. Any refusal stops the start with its reason."""
    results = lab.params.load(read_parameter_file(path), force=True)
    failed = [r for r in results if not r["successful"]]
    if failed:
        raise ParameterRefused("; ".join(f"/{r['node']}/{r['name']}: {r['reason']}" for r in failed))


def _bindable(host: str, port: int) -> bool:
    """A listening socket could be bound there now (as uvicorn binds it: SO_REUSEADDR)."""
    try:
        family = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0][0]
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            probe.bind((host, port))
        return True
    except OSError:
        return False


def port_taken(host: str, port: int) -> str | None:
    """What to do when `host:port` is taken (None when it is free): stop the lab there, or start
    this one beside it on the next free port, its clients pointed at it."""
    if _bindable(host, port):
        return None
    spare = next((p for p in range(port + 1, min(port + 100, 65536)) if _bindable(host, p)), None)
    beside = (
        f"or start this one beside it with --port {spare} (its clients: --url http://{host}:{spare}, "
        f"or HRI_LAB_URL=http://{host}:{spare})"
        if spare is not None
        else "or give this one a free port with --port"
    )
    return (
        f"hri-lab serve: {host}:{port} is in use, most likely by a lab already running (`make run` starts "
        f"one on 8000). One lab per port: stop that one first (Ctrl+C in its terminal), {beside}."
    )


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
    world: str | None = None,
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
    served = WORLDS[world or DEFAULT]
    lab = served.lab(LabOptions(controller=controller, arena_seed=arena_seed))
    lab.recordings_dir, lab.figures_dir = Path(output_dir) / "recordings", Path(output_dir) / "figures"
    if params_file:
        try:
            load_parameter_file(lab, params_file)
        except (OSError, ParameterRefused) as exc:
            print(f"hri-lab: cannot load parameters from {params_file}: {exc}", file=sys.stderr)
            return 2
    app = create_app(
        served, lab, view=view, view_host=host, view_port=view_port, token=token, exercises=exercises, replay=replay
    )
    server = AnnouncingServer(server_config(app, host, port))
    try:
        server.run()
    except KeyboardInterrupt:  # Ctrl+C: the server shut down first (uvicorn, or asyncio's runner, re-raises it)
        pass  # the lab stops as asked: no traceback in the terminal
    return 0 if server.started else 1


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
    simulation process at its first step), then the server until Ctrl+C; nothing when the port is
    taken (`port_taken`: what to do instead)."""
    taken = port_taken(args.host, args.port)
    if taken:
        print(taken, file=sys.stderr)
        return 1
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
