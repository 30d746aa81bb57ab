"""/teleop: jog the end effector with a key, like the keytwist node."""

from typing import Literal

from fastapi import APIRouter
from fastapi.responses import JSONResponse
from pydantic import BaseModel, ConfigDict

from sim.robot.teleop import key_twist

from app.api.deps import LabDep
from app.lab import commands


class TeleopKey(BaseModel):
    model_config = ConfigDict(strict=True, extra="forbid")
    key: Literal["w", "s", "a", "d", "q"]


router = APIRouter(tags=["teleop"])


@router.post("/teleop/key", summary="Jog the EE with a key (w/s: +-x, a/d: +-yaw, q: stop)")
def teleop(body: TeleopKey, lab: LabDep) -> JSONResponse:
    speeds = (lab.params.number("keytwist", "linear_speed"), lab.params.number("keytwist", "angular_speed"))
    twist_base = key_twist(body.key, *speeds)
    try:
        lab.call(commands.start_jog, twist_base)
    except RuntimeError as exc:
        return JSONResponse({"successful": False, "reason": str(exc)}, status_code=409)
    return JSONResponse({"successful": True, "twist": twist_base.tolist()})
