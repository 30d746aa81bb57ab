"""The FastAPI app: one router per resource (services, parameters, topics, actions, teleop, robot,
system), around one Lab whose simulation runs while the app is served."""

from concurrent.futures import TimeoutError as CallTimeout
from contextlib import asynccontextmanager
from importlib.metadata import version as package_version

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from fastapi.staticfiles import StaticFiles

from app.api import actions as actions_api
from app.api import camera as camera_api
from app.api import files as files_api
from app.api import mobile as mobile_api
from app.api import node_services as node_services_api
from app.api import params as params_api
from app.api import robot as robot_api
from app.api import services as services_api
from app.api import system as system_api
from app.api import teleop as teleop_api
from app.api import topics as topics_api
from app.api.access import TokenMiddleware
from app.api.docs import add_offline_docs
from app.api.openapi import document
from app.api.responses import SafeJSONResponse, json_safe
from app.lab.actions import ACTIONS
from app.lab.events import LAB_NODE
from app.lab.lab import Lab
from app.lab.services import EXERCISES, SERVICES
from app.lab.topics import TOPICS
from app.mobile.lab import MobileLab
from app.mobile.services import SERVICES as MOBILE_SERVICES
from app.ros.actions import ActionServer
from app.rosbridge import server as rosbridge
from app.rosbridge.internal.node_services import NodeServices
from app.rosbridge.internal.state import Bridge
from app.runtime.process import SimulationRestarting
from app.security import SiteGuard
from app.tokens import token_problem


def create_app(
    lab: Lab | MobileLab | None = None,
    view: str = "none",
    view_host: str = "127.0.0.1",
    view_port: int = 8080,
    token: str | None = None,
    exercises: bool = False,
    replay: bool = False,
) -> FastAPI:
    """The app around `lab` (a new Lab if none); the simulation runs while the app is served.
    view: "full" (visual meshes), "light" (collision meshes, no shadows) or "none" (no 3D view).
    view_host: the address the server (API and view) is bound to; requests must name it
    (app/security.py). token: when set, state-changing requests must carry it (app/api/access.py).
    exercises: the handout's exercise services are left to the students' nodes (rosbridge).
    replay: the simulation publishes no topic over rosbridge: a bag played into the lab publishes them
    (app/rosbridge/internal/state.py, docs/recording.md)."""
    if token and token_problem(token):
        raise ValueError(token_problem(token))
    lab = lab or Lab()
    lifting = isinstance(lab, Lab)  # else the mobile world (app/mobile/lab.py): it declares topics only
    if isinstance(lab, Lab):
        services_declared, actions_declared, topics_declared = SERVICES, ACTIONS, TOPICS
    else:
        services_declared, actions_declared, topics_declared = MOBILE_SERVICES, [], lab.topics
    nodes = NodeServices(services_declared, lab, EXERCISES if exercises and lifting else ())  # declared + nodes'
    services = nodes.registry

    @asynccontextmanager
    async def lifespan(app: FastAPI):
        lab.start()
        if view != "none" and isinstance(lab, MobileLab):
            from app.view.mobile_view import MobileView  # viser only when a view is asked for

            app.state.view = MobileView(lab, view_host, view_port, light=view == "light")
            app.state.view.start()
        elif view != "none":
            from app.view.view3d import LabView

            app.state.view = LabView(
                lab, app.state.actions, services, view_host, view_port, light=view == "light", controls=token is None
            )
            app.state.view.start()
        try:
            yield
        finally:
            if app.state.view is not None:
                app.state.view.stop()
            lab.stop()

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
    app.state.view = None
    app.state.actions = ActionServer(actions_declared, lab)
    if token:
        app.add_middleware(TokenMiddleware, token=token)
    app.add_middleware(SiteGuard, bound_host=view_host)  # outermost: cross-site refusals come first

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

    if not lifting:  # its page at / (before the lifting page's), its arena, the page's teleop
        app.include_router(mobile_api.router)
    app.include_router(system_api.router)
    app.include_router(services_api.router(services, lambda name: nodes.node_of(name) or LAB_NODE))
    app.include_router(node_services_api.router(nodes))  # after the typed routes: names added at run time
    app.include_router(params_api.router)
    app.include_router(topics_api.router(topics_declared))
    app.include_router(actions_api.router(actions_declared))
    if lifting:  # the arm's teleop, its model and its camera
        app.include_router(teleop_api.router)
        app.include_router(robot_api.router)
        app.include_router(camera_api.router)
    app.include_router(files_api.router)
    app.state.bridge = Bridge(lab, nodes, app.state.actions, token, replay=replay)
    app.include_router(rosbridge.router(app.state.bridge))  # rosbridge v2: WebSocket at /
    app.mount("/static", StaticFiles(directory=system_api.STATIC), name="static")
    document(app)
    return app
