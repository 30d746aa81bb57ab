"""The server itself: the page at /, /health, /log (rosout) and /view (where the 3D view is)."""

from pathlib import Path
from typing import Literal

from fastapi import APIRouter, Query, Request
from fastapi.responses import FileResponse

from app.api.deps import LabDep
from app.api.view_relay import PATH as VIEW_RELAY
from app.ros.rosout import LEVELS
from app.security import proxy_secret

STATIC = Path(__file__).resolve().parents[2] / "static"

router = APIRouter(tags=["system"])


@router.get("/", include_in_schema=False)
def dashboard() -> FileResponse:
    return FileResponse(STATIC / "index.html")


@router.get("/favicon.ico", include_in_schema=False)
def favicon() -> FileResponse:
    """The lab's icon where browsers ask for it first (the page names it too: static/favicon.svg)."""
    return FileResponse(STATIC / "favicon.svg", media_type="image/svg+xml")


@router.get("/health", summary="Is the simulation loop running, and how well")
def health(lab: LabDep) -> dict:
    health = lab.runtime.health()
    stats = health.stats
    return {
        "loop_alive": health.alive,
        "sim_time": lab.snapshot().time,
        "ticks": stats.ticks,
        "rate_hz": stats.rate_hz,
        "lateness_p50_ms": stats.lateness_p50 * 1e3,
        "lateness_p99_ms": stats.lateness_p99 * 1e3,
        "overruns": stats.overruns,
        "batched_ticks": stats.batched,  # ticks stepped in idle batches (app/runtime/loop.py)
        "realtime_priority": stats.realtime_priority,
        "step_errors": stats.step_errors,
        "last_step_error": stats.last_step_error,
        "loop_restarts": health.restarts,
        "last_loop_death": health.last_death,
        "error": lab.snapshot().error,
    }


@router.get("/view", summary="Where the 3D view is served (viser)")
def view_info(request: Request) -> dict:
    """url: the viser server's own address; relay: the same view through this server's port, which the
    page embeds behind a JupyterHub (app/api/view_relay.py), where only that port is proxied."""
    view = request.app.state.view
    if view is None:
        return {"url": None, "light": False, "relay": None}
    return {"url": view.url, "light": view.light, "relay": VIEW_RELAY.lstrip("/") if proxy_secret() else None}


@router.get(
    "/log",
    summary="Recent lines of /rosout: the lab's and every node's (rqt_console)",
    description="Oldest first; `node` and `level` (DEBUG, INFO, WARN, ERROR, FATAL: that level and "
    "above) filter them, `after_seq` keeps the lines that came after the one of that `seq`.",
)
def log(
    lab: LabDep,
    node: str | None = None,
    level: Literal["DEBUG", "INFO", "WARN", "ERROR", "FATAL"] | None = None,
    after_seq: int = Query(0, ge=0, le=2**63 - 1),
) -> list[dict]:
    lines = lab.rosout.recent()
    if node:
        lines = [line for line in lines if line.node.strip("/") == node.strip("/")]
    if level:
        lines = [line for line in lines if LEVELS[line.level] >= LEVELS[level]]
    lines = [line for line in lines if line.seq > after_seq]
    return [line.as_dict() for line in lines]
