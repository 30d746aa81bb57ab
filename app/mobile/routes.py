"""The mobile world's own routes (`serve --world mobile`): its page at /, its arena (what the page
draws) and the page's teleop, a twist the base follows as it follows /cmd_vel (within its limits,
until the watchdog stops it: the page sends it again while a key is held)."""

from __future__ import annotations

from fastapi import APIRouter, HTTPException, Request
from fastapi.responses import FileResponse
from pydantic import BaseModel, ConfigDict, Field

from app.api.system import STATIC
from app.mobile import commands


class DriveTwist(BaseModel):
    model_config = ConfigDict(strict=True, extra="forbid")
    linear_x: float = Field(
        allow_inf_nan=False, ge=-10.0, le=10.0, description="m/s forward (the base holds it to 0.22)"
    )
    angular_z: float = Field(allow_inf_nan=False, ge=-20.0, le=20.0, description="rad/s about z (held to 2.84)")


router = APIRouter(tags=["mobile"])


@router.get("/", include_in_schema=False)
def dashboard() -> FileResponse:
    return FileResponse(STATIC / "mobile.html")


@router.get("/mobile/arena", summary="The mobile world's arena, base and scanner (what the page draws)")
def arena(request: Request) -> dict:
    lab = request.app.state.lab
    if lab.graded:  # a graded program finds the obstacle with its scan, as on the robot
        raise HTTPException(403, "the arena is hidden from the program while a trial is graded")
    config = lab.world.config
    a = config.arena
    return {
        "half_size_xy": list(a.half_size_xy),
        "obstacles": [
            {"shape": o.shape, "center_xy": list(o.center_xy), "size": list(o.size), "yaw": o.yaw} for o in a.obstacles
        ],
        "footprint_radius": config.base.footprint_radius,
        "scan_offset_xy": list(config.lidar.offset_xy),
        "band": list(config.rules.band),
        "max_linear": config.base.max_linear,
        "max_angular": config.base.max_angular,
    }


@router.post("/mobile/drive", summary="Drive the base from the page (as a geometry_msgs/Twist on /cmd_vel)")
def drive(body: DriveTwist, request: Request) -> dict:
    request.app.state.lab.call(commands.drive, [body.linear_x, 0.0, 0.0, 0.0, 0.0, body.angular_z])
    return {"linear_x": body.linear_x, "angular_z": body.angular_z}


@router.post("/mobile/reset", summary="The base back at its start pose; odometry and the trial's monitor restarted")
def reset(request: Request) -> dict:
    lab = request.app.state.lab
    if lab.graded:  # a graded trial's verdict stands: its program may not start it over
        raise HTTPException(403, "a graded trial's world cannot be reset")
    lab.call(commands.reset)
    return {"successful": True}
