"""/services: list, describe and call the registry's services (ros2 service list / call)."""

from collections.abc import Callable

from fastapi import APIRouter, HTTPException

from app.api.deps import LabDep
from app.api.responses import SafeJSONResponse as JSONResponse
from app.api.typed_routes import with_body
from app.ros.messages import RosMessage
from app.ros.names import absolute
from app.ros.services import Service, ServiceFailure, ServiceRegistry
from app.runtime.process import SimulationRestarting


def router(registry: ServiceRegistry, node_of: Callable[[str], str]) -> APIRouter:
    """`node_of(name)`: the node that provides a service now (a program's, or the lab's own)."""
    r = APIRouter(tags=["services"])

    @r.get("/services", summary="List services with their types (ros2 service list -t)")
    def list_services() -> list[dict]:
        return [{"name": s.name, "type": s.type} for s in registry]

    @r.get("/services/{name:path}", summary="Type, .srv and node of a service (ros2 interface show, rosservice info)")
    def service_info(name: str) -> dict:
        service = registry.get(name)
        if service is None:
            raise HTTPException(404, f"service '{absolute(name)}' is not advertised")
        return {**service.info(), "node": node_of(service.name)}

    for service in registry:
        r.add_api_route(
            f"/services{service.name}",
            _endpoint(registry, service),
            methods=["POST"],
            response_model=service.response,
            summary=f"call {service.name} ({service.type})",
            description=f"{service.description}\n\n```\n{service.srv}\n```",
            operation_id="call" + service.name.replace("/", "_"),
            responses={400: {"description": "service failure"}},
        )
    return r


def _endpoint(registry: ServiceRegistry, service: Service):
    """The route of a service call: validated request in, response or failure response out (400
    with the reason; a handler bug is a 500 failure response, the server and simulation go on)."""

    def call(request: RosMessage, lab: LabDep):
        try:
            response = registry.call(lab, service.name, request)
        except SimulationRestarting:
            raise  # a 503 (app/api/app.py)
        except ServiceFailure as failure:
            return JSONResponse(
                {"service": service.name, "success": False, "detail": str(failure)}, status_code=failure.status
            )
        except Exception as exc:  # noqa: BLE001 - a handler bug is a failure response, not a crash
            detail = f"{type(exc).__name__}: {exc}"
            return JSONResponse({"service": service.name, "success": False, "detail": detail}, status_code=500)
        return response.model_dump(by_alias=True)

    return with_body(service.request, call, "call" + service.name.replace("/", "_"), lab=LabDep)
