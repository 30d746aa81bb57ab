"""/params: ROS 2 parameters over HTTP (ros2 param list / get / set / describe / dump / load): the
lab's declared ones and those of nodes that declare their own (app/ros/params.py)."""

from typing import Any

from fastapi import APIRouter, Body, HTTPException, Request
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import JSONResponse, PlainTextResponse
from pydantic import BaseModel, ConfigDict

from app.api.deps import ParamsDep
from app.ros.params import ParameterRefused


class SetParameter(BaseModel):
    model_config = ConfigDict(extra="forbid")
    value: Any


def _refused(exc: ParameterRefused) -> JSONResponse:
    return JSONResponse({"successful": False, "reason": str(exc)}, status_code=exc.status)


router = APIRouter(tags=["parameters"])

# a `param dump` file: node -> {ros__parameters: {name: value}}
PARAMETER_FILE = {
    "type": "object",
    "additionalProperties": {
        "type": "object",
        "required": ["ros__parameters"],
        "additionalProperties": False,
        "properties": {
            "ros__parameters": {"type": "object", "additionalProperties": {"type": ["number", "string", "boolean"]}}
        },
    },
}


@router.get("/params", summary="All parameters with their values (ros2 param list)")
def list_params(server: ParamsDep) -> list[dict]:
    return [{"node": p.node, "name": p.name, "type": p.type, "value": v} for p, v in server.items()]


@router.get("/params/dump", response_class=PlainTextResponse, summary="YAML of all (or one node's) parameters")
def dump(server: ParamsDep, node: str | None = None) -> str:
    return server.dump(node)


@router.post(
    "/params/load",
    summary="Set parameters from a YAML dump (ros2 param load)",
    description="Body: a `param dump` file, `Content-Type: application/yaml`, at most 64 KiB "
    "and 16 levels deep; a refused file is a 422 with the reason.",
    responses={422: {"description": "the file is refused as a whole (with the reason)"}},
    openapi_extra={"requestBody": {"required": True, "content": {"application/yaml": {"schema": PARAMETER_FILE}}}},
)
async def load(request: Request, server: ParamsDep):
    text = (await request.body()).decode("utf-8", errors="replace")
    try:  # parsing and setting take time (and wait for the simulation): off the event loop
        results = await run_in_threadpool(server.load, text)
    except ParameterRefused as exc:
        return _refused(exc)
    return {"successful": all(x["successful"] for x in results), "results": results}


@router.get("/params/{node}/{name}", summary="Value of a parameter (ros2 param get)")
def get(node: str, name: str, server: ParamsDep):
    try:
        type_, value = server.typed(node, name)
    except ParameterRefused as exc:
        return _refused(exc)
    return {"node": node, "name": name, "type": type_, "value": value}


@router.get("/params/{node}/{name}/describe", summary="Descriptor of a parameter (ros2 param describe)")
def describe(node: str, name: str, server: ParamsDep):
    try:
        return server.describe(node, name)
    except ParameterRefused as exc:
        if exc.status == 404:
            raise HTTPException(404, str(exc)) from None
        return _refused(exc)


@router.put("/params/{node}/{name}", summary="Set a parameter (ros2 param set)")
def set_param(node: str, name: str, server: ParamsDep, body: SetParameter = Body(...)):
    try:
        server.set(node, name, body.value)
    except ParameterRefused as exc:
        return _refused(exc)
    return {"successful": True, "reason": ""}
