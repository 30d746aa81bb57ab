"""/robot: the robot's links and joints with their limits (check_urdf)."""

from functools import lru_cache

from fastapi import APIRouter

from app.lab.robot_description import robot_description

router = APIRouter(tags=["robot"])


@router.get("/robot", summary="Links and joints with limits (check_urdf)")
def robot() -> dict:
    return _description()


@lru_cache(maxsize=1)
def _description() -> dict:
    return robot_description()
