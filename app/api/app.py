"""The FastAPI app: one router per resource (services, parameters, topics, actions, system, files),
around one lab (any world's: app/worlds/port.py) whose simulation runs while the app is served, with
its world's own routes (the lifting world's teleop, robot and camera; the mobile world's page). It is
handed what it serves (the lab, its registries, its world's routes, the other front ends' routes and
what runs beside it) by the composition root, app/serving/compose.py; it builds none of them."""

from collections.abc import Sequence
from concurrent.futures import TimeoutError as CallTimeout
from contextlib import asynccontextmanager
from importlib.metadata import version as package_version
from typing import Any

from fastapi import APIRouter, FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from fastapi.staticfiles import StaticFiles

from sim.messages import Topic

from app.api import actions as actions_api
from app.api import files as files_api
from app.api import node_services as node_services_api
from app.api import params as params_api
from app.api import services as services_api
from app.api import system as system_api
from app.api import topics as topics_api
from app.api import view_relay
from app.api.access import TokenMiddleware
from app.api.docs import add_offline_docs
from app.api.openapi import document
from app.api.responses import SafeJSONResponse, json_safe
from app.ros.actions import Action, ActionServer
from app.ros.names import LAB_NODE
from app.ros.node_services import NodeServices
from app.runtime.process import SimulationRestarting
from app.security import SiteGuard
from app.worlds.contract import Running
from app.worlds.port import LabPort


def create_api(
    lab: LabPort[Any],
    nodes: NodeServices,
    actions: ActionServer,
    actions_declared: list[Action],
    topics_declared: list[Topic],
    *,
    world_routes: Sequence[APIRouter] = (),
    bound_host: str = "127.0.0.1",
    token: str | None = None,
    running: Sequence[Running] = (),
    routers: Sequence[APIRouter] = (),
) -> FastAPI:
    """The HTTP API of `lab` (app.state.lab) with its service registry `nodes` and its `actions`.
    world_routes: its world's own routes (its page at /, before the lifting page, and its panels).
    bound_host: the address the server is bound to; requests must name it (app/security.py).
    token: when set, state-changing requests must carry it (app/api/access.py).
    running: what runs while the app is served (the lab first); routers: the other front ends'
    routes (rosbridge's WebSocket at /), after the API's own."""
    services = nodes.registry

    @asynccontextmanager
    async def lifespan(app: FastAPI):
        started: list[Running] = []
        try:
            for part in running:
                part.start()
                started.append(part)
            yield
        finally:
            for part in reversed(started):
                part.stop()

    app = FastAPI(
        title="hri-lab",
        description="The simulated cooperative-lifting lab: ROS services, parameters, topics and actions over HTTP.",
        version=package_version("hri-lab"),  # pyproject.toml's, the one version source
        lifespan=lifespan,
        default_response_class=SafeJSONResponse,
        docs_url=None,  # served offline below
        redoc_url=None,
    )
    add_offline_docs(app)
    app.state.lab = lab
    app.state.view = None  # the 3D view, when the composition root makes one (app/api/system.py shows it)
    app.state.actions = actions
    if token:
        app.add_middleware(TokenMiddleware, token=token)
    app.add_middleware(SiteGuard, bound_host=bound_host)  # outermost: cross-site refusals come first

    @app.exception_handler(RequestValidationError)
    async def refuse(request: Request, exc: RequestValidationError) -> JSONResponse:
        """422 naming the field; the offending input is echoed JSON-safe (NaN/inf as text)."""
        return SafeJSONResponse({"detail": json_safe(exc.errors())}, status_code=422)

    @app.exception_handler(SimulationRestarting)
    async def restarting(request: Request, exc: SimulationRestarting) -> JSONResponse:
        """503: the simulation process died and is being restarted (call again)."""
        return SafeJSONResponse({"detail": str(exc)}, status_code=503, headers={"Retry-After": "1"})

    @app.exception_handler(CallTimeout)
    async def stuck(request: Request, exc: CallTimeout) -> JSONResponse:
        return SafeJSONResponse(
            {"detail": "the simulation did not answer in time; call again"},
            status_code=503,
            headers={"Retry-After": "1"},
        )

    for router in world_routes:  # first: a world's page at / comes before the lifting page
        app.include_router(router)
    app.include_router(system_api.router)
    app.include_router(services_api.router(services, lambda name: nodes.node_of(name) or LAB_NODE))
    app.include_router(node_services_api.router(nodes))  # after the typed routes: names added at run time
    app.include_router(params_api.router)
    app.include_router(topics_api.router(topics_declared))
    app.include_router(actions_api.router(actions_declared))
    app.include_router(files_api.router)
    app.include_router(view_relay.router)  # the 3D view through the lab's port (behind a JupyterHub)
    for router in routers:
        app.include_router(router)
    app.mount("/static", StaticFiles(directory=system_api.STATIC), name="static")
    document(app)
    return app
