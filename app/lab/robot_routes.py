"""/robot: the robot's links and joints with their limits (check_urdf); /robot/description: its
URDF, the `/robot_description` parameter's text."""

from functools import lru_cache

from fastapi import APIRouter
from fastapi.responses import Response

from app.lab.robot_description import robot_description, robot_description_text

router = APIRouter(tags=["robot"])


@router.get("/robot", summary="Links and joints with limits (check_urdf)")
def robot() -> dict:
    return _description()


@lru_cache(maxsize=1)
def _description() -> dict:
    return robot_description()


@router.get(
    "/robot/description",
    summary="The Panda's URDF: the /robot_description parameter's text",
    response_class=Response,
    responses={200: {"content": {"application/xml": {"schema": {"type": "string"}}}}},
)
def description() -> Response:
    return Response(robot_description_text(), media_type="application/xml")
