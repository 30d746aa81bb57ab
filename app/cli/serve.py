"""`hri-lab serve`: the lab's server on 127.0.0.1 (embedded defaults; optional parameter file),
with the HTTP server's limits (app/serving/http.py); the server itself is app/serving/serve.py.

Its refusals come before the server's modules are imported (a second or so of CPU): a server
reachable from other machines needs a token, and a token long enough; one lab per port: a port
already taken (`make run`'s lab on 8000, say) stops the start at once with what to do, the lab's
other port to take (`port_taken`)."""

import argparse
import socket
import sys
from dataclasses import replace

from app.api.access import is_loopback
from app.tokens import TOKEN_ENV, token_problem


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


def refusal(host: str, token: str | None, no_token: bool) -> str | None:
    """Why a server on `host` with `token` is not started (None: it is): one reachable from other
    machines needs a token (inside a container whose port the host publishes on its loopback:
    --no-token), and a token long enough."""
    if not is_loopback(host) and not token and not no_token:
        return (
            f"hri-lab: binding {host} (not this machine only) needs a token: --token or ${TOKEN_ENV} "
            "(inside a container whose port the host publishes on its loopback: --no-token)"
        )
    if token and token_problem(token):
        return f"hri-lab: {token_problem(token)}"
    return None


def run(args: argparse.Namespace) -> int:
    """`hri-lab serve`: nothing when the port is taken (`port_taken`: what to do instead) or the
    token is missing or short (`refusal`); otherwise the controller chosen (a plug-in file loaded
    once now, then started in the simulation process at its first step), then the server until Ctrl+C."""
    taken = port_taken(args.host, args.port)
    if taken:
        print(taken, file=sys.stderr)
        return 1
    refused = refusal(args.host, args.token, args.no_token)
    if refused:
        print(refused, file=sys.stderr)
        return 2
    # the server's modules (uvicorn, the API, the simulation: a second or so of CPU), once it will start
    from sim.controllers.plugin import PluginFactory

    from app.cli.controllers import loaded_factory
    from app.serving.serve import serve

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
    )
