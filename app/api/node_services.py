"""HTTP calls of services that nodes advertise at run time (`POST /services/NAME`): the lab's
declared services have typed routes of their own (app/api/services.py); this route, included
after them, serves the names added later. Refusals as for any service: 422 naming the field,
404 not advertised, 400 the node's failure, 502 a malformed answer, 504 no answer in time."""

from typing import Any

from fastapi import APIRouter, Body
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import JSONResponse
from pydantic import ValidationError

from app.api.deps import LabDep
from app.ros.names import absolute
from app.ros.node_services import NodeServices
from app.ros.services import ServiceFailure


def router(nodes: NodeServices) -> APIRouter:
    r = APIRouter(tags=["services"])

    @r.post("/services/{name:path}", summary="Call a service that a node provides (advertised at run time)")
    async def call_node_service(name: str, lab: LabDep, body: Any = Body(None)) -> JSONResponse:
        name = absolute(name)
        service = nodes.registry.get(name)
        if service is None:
            return JSONResponse({"detail": f"service '{name}' is not advertised"}, status_code=404)
        try:
            request = service.request.model_validate(body if body is not None else {})
        except ValidationError as exc:
            errors = [{"type": e["type"], "loc": ["body", *e["loc"]], "msg": e["msg"]} for e in exc.errors()]
            return JSONResponse({"detail": errors}, status_code=422)
        try:
            if nodes.provided_by(name) is not None:
                response = await nodes.call_async(name, request)
            else:  # it left the registry's typed routes' hands after they were built
                response = await run_in_threadpool(service.handler, lab, request)
        except ServiceFailure as failure:
            return JSONResponse({"service": name, "success": False, "detail": str(failure)}, status_code=failure.status)
        return JSONResponse(response.model_dump(by_alias=True))

    return r
