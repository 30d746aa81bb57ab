"""The FastAPI app: the lab's services, parameters and topics over HTTP, with the live loop."""
import math
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Literal

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse
from fastapi.staticfiles import StaticFiles
from pydantic import BaseModel, ConfigDict

from sim.robot.teleop import key_twist
from sim.world import World

from app.ros import params as params_api
from app.lab import robot_description as robot_model
from app.ros import topics as topics_api
from app.api.access import TokenMiddleware
from app.api.docs import add_offline_docs
from app.ros.actions import ActionServer
from app.lab.lab import Lab
from app.lab.actions import ACTIONS
from app.lab.services import SERVICES

STATIC = Path(__file__).resolve().parents[2] / "static"


def create_app(lab: Lab | None = None, view: str = "none", view_host: str = "127.0.0.1", view_port: int = 8080,
               token: str | None = None) -> FastAPI:
    """The app around `lab` (a new Lab if none); the loop runs while the app is served.
    view: "full" (visual meshes), "light" (collision meshes, no shadows) or "none" (no 3D view).
    token: when set, state-changing requests must carry it (app/access.py)."""
    lab = lab or Lab()

    @asynccontextmanager
    async def lifespan(app: FastAPI):
        lab.start()
        if view != "none":
            from app.view.view3d import LabView

            app.state.view = LabView(lab, app.state.actions, SERVICES, view_host, view_port, light=view == "light",
                                     controls=token is None)
            app.state.view.start()
        try:
            yield
        finally:
            if app.state.view is not None:
                app.state.view.stop()
            lab.stop()

    app = FastAPI(
        title="hri-lab",
        description="The simulated cooperative-lifting lab: ROS services, parameters and topics over HTTP.",
        version="0.1.0",
        lifespan=lifespan,
        docs_url=None,  # served offline below
        redoc_url=None,
    )
    add_offline_docs(app)
    app.state.lab = lab
    app.state.view = None
    if token:
        app.add_middleware(TokenMiddleware, token=token)

    @app.exception_handler(RequestValidationError)
    async def refuse(request: Request, exc: RequestValidationError) -> JSONResponse:
        """422 naming the field; the offending input is echoed JSON-safe (NaN/inf as text)."""
        return JSONResponse({"detail": json_safe(exc.errors())}, status_code=422)
    app.include_router(SERVICES.router(lab))
    app.include_router(params_api.router(lab.params))
    app.include_router(topics_api.router(lab))
    app.include_router(robot_model.router())
    app.state.actions = ActionServer(ACTIONS, lab)
    app.include_router(app.state.actions.router())

    @app.post("/teleop/key", tags=["teleop"], summary="Jog the EE with a key (w/s: +-x, a/d: +-yaw, q: stop)")
    def teleop(body: TeleopKey) -> JSONResponse:
        speeds = (lab.params.get("keytwist", "linear_speed"), lab.params.get("keytwist", "angular_speed"))
        twist = key_twist(body.key, *speeds)
        try:
            lab.call(World.start_jog, twist)
        except RuntimeError as exc:
            return JSONResponse({"successful": False, "reason": str(exc)}, status_code=409)
        return JSONResponse({"successful": True, "twist": twist.tolist()})

    @app.get("/health", tags=["system"], summary="Is the simulation loop running, and how well")
    def health() -> dict:
        stats = lab.loop.stats()
        snapshot = lab.snapshot()
        return {
            "loop_alive": stats.alive,
            "sim_time": snapshot.time,
            "ticks": stats.ticks,
            "rate_hz": stats.rate_hz,
            "lateness_p50_ms": stats.lateness_p50 * 1e3,
            "lateness_p99_ms": stats.lateness_p99 * 1e3,
            "overruns": stats.overruns,
            "realtime_priority": stats.realtime_priority,
            "step_errors": stats.step_errors,
            "last_step_error": stats.last_step_error,
            "loop_restarts": stats.restarts,
            "last_loop_death": stats.last_death,
            "error": snapshot.error,
        }

    @app.get("/", include_in_schema=False)
    def dashboard() -> FileResponse:
        return FileResponse(STATIC / "index.html")

    app.mount("/static", StaticFiles(directory=STATIC), name="static")

    @app.get("/view", tags=["system"], summary="Where the 3D view is served (viser)")
    def view_info() -> dict:
        if app.state.view is None:
            return {"url": None, "light": False}
        return {"url": app.state.view.url, "light": app.state.view.light}

    @app.get("/log", tags=["system"], summary="Recent log lines of the services (rosout)")
    def log() -> list[dict]:
        return list(lab.log)

    return app


class TeleopKey(BaseModel):
    model_config = ConfigDict(strict=True, extra="forbid")
    key: Literal["w", "s", "a", "d", "q"]


def json_safe(value):
    """value with non-finite floats as strings and anything else unknown as its repr."""
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, (str, int, bool)) or value is None:
        return value
    if isinstance(value, dict):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    return repr(value)
