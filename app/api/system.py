"""The server itself: the page at /, /health, /log (rosout) and /view (where the 3D view is)."""
from pathlib import Path

from fastapi import APIRouter, Request
from fastapi.responses import FileResponse

from app.api.deps import LabDep

STATIC = Path(__file__).resolve().parents[2] / "static"

router = APIRouter(tags=["system"])


@router.get("/", include_in_schema=False)
def dashboard() -> FileResponse:
    return FileResponse(STATIC / "index.html")


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
    view = request.app.state.view
    if view is None:
        return {"url": None, "light": False}
    return {"url": view.url, "light": view.light}


@router.get("/log", summary="Recent log lines of the services (rosout)")
def log(lab: LabDep) -> list[dict]:
    return list(lab.log)
