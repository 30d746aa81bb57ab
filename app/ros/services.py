"""The service registry: one declaration per service gives its HTTP route (a typed entry in the
OpenAPI schema, so /docs calls it), its introspection (`GET /services`, `GET /services/{name}`,
like `ros2 service list -t` and `ros2 interface show`) and what the CLI and the dashboard list.

A handler gets the Lab and the validated request and returns the response. A `ServiceFailure`
becomes HTTP 400 with the reason; any other exception HTTP 500; both are service failure
responses (JSON), the server and the simulation go on.
"""
from dataclasses import dataclass
from typing import Any, Callable

from fastapi import APIRouter, HTTPException
from fastapi.responses import JSONResponse

from app.ros.messages import RosMessage, definition
from app.api.typed_routes import with_body


class ServiceFailure(Exception):
    """A service call that could not be done (the reason is the message); `status` is its HTTP code."""

    status = 400


class NotProvided(ServiceFailure):
    """A service left to a node that no node provides yet (HTTP 404)."""

    status = 404


class NodeTimeout(ServiceFailure):
    """The node that provides a service did not answer in time (HTTP 504)."""

    status = 504


class NodeFailure(ServiceFailure):
    """The node answered with something that is not the service's response (HTTP 502)."""

    status = 502


@dataclass(frozen=True)
class Service:
    name: str  # "/add_two_ints"
    type: str  # "hri_lab/AddTwoInts"
    request: type[RosMessage]
    response: type[RosMessage]
    handler: Callable[[Any, Any], RosMessage]  # (lab, request) -> response
    description: str = ""

    @property
    def srv(self) -> str:
        """The .srv text: request `---` response."""
        request, response = definition(self.request), definition(self.response)
        return "\n".join(part for part in (request, "---", response) if part)

    def info(self) -> dict:
        return {
            "name": self.name,
            "type": self.type,
            "srv": self.srv,
            "description": self.description,
            "request_schema": self.request.model_json_schema(by_alias=True),
            "response_schema": self.response.model_json_schema(by_alias=True),
        }


class ServiceRegistry:
    def __init__(self, services: list[Service] = ()) -> None:
        self._services: dict[str, Service] = {}
        for service in services:
            self.add(service)

    def add(self, service: Service) -> None:
        if service.name in self._services:
            raise ValueError(f"service {service.name} declared twice")
        self._services[service.name] = service

    def remove(self, name: str) -> Service | None:
        """Take a service away (a node's, when it unadvertises or disconnects)."""
        return self._services.pop(name if name.startswith("/") else "/" + name, None)

    def __iter__(self):
        return iter(list(self._services.values()))

    def get(self, name: str) -> Service | None:
        return self._services.get(name if name.startswith("/") else "/" + name)

    def call(self, lab: Any, name: str, request: RosMessage) -> RosMessage:
        service = self.get(name)
        if service is None:
            raise KeyError(name)
        return service.handler(lab, request)

    def router(self, lab: Any) -> APIRouter:
        router = APIRouter()

        @router.get("/services", tags=["services"], summary="List services with their types (ros2 service list -t)")
        def list_services() -> list[dict]:
            return [{"name": s.name, "type": s.type} for s in self]

        @router.get("/services/{name:path}", tags=["services"], summary="Type and .srv of a service (ros2 interface show)")
        def service_info(name: str) -> dict:
            service = self.get(name)
            if service is None:
                raise HTTPException(404, f"service '/{name.lstrip('/')}' is not advertised")
            return service.info()

        for service in self:
            router.add_api_route(
                f"/services{service.name}",
                _endpoint(lab, service),
                methods=["POST"],
                response_model=service.response,
                tags=["services"],
                summary=f"call {service.name} ({service.type})",
                description=f"{service.description}\n\n```\n{service.srv}\n```",
                operation_id="call" + service.name.replace("/", "_"),
                responses={400: {"description": "service failure"}},
            )
        return router


def _endpoint(lab: Any, service: Service) -> Callable:
    """The route of a service call: validated request in, response or failure response out."""

    def call(request: RosMessage):
        try:
            response = service.handler(lab, request)
        except ServiceFailure as failure:
            return JSONResponse({"service": service.name, "success": False, "detail": str(failure)}, status_code=failure.status)
        except Exception as exc:  # noqa: BLE001 - a handler bug is a failure response, not a crash
            detail = f"{type(exc).__name__}: {exc}"
            return JSONResponse({"service": service.name, "success": False, "detail": detail}, status_code=500)
        return response.model_dump(by_alias=True)

    return with_body(service.request, call, "call" + service.name.replace("/", "_"))
