"""The service registry: one declaration per service gives its HTTP route (app/api/services.py:
a typed entry in the OpenAPI schema, so /docs calls it), its introspection (like
`ros2 service list -t` and `ros2 interface show`) and what the CLI, the dashboard and the 3D view
list and call.

A handler gets the Lab and the validated request and returns the response; `call` is the one way
to run it. A `ServiceFailure` is a failed call with a reason (HTTP 400).
"""

import builtins
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

from app.ros.interface_models import fields
from app.ros.messages import RosMessage, definition
from app.ros.names import absolute


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
    request: builtins.type[RosMessage]  # builtins.: the field `type` above shadows the builtin here
    response: builtins.type[RosMessage]
    handler: Callable[[Any, Any], RosMessage]  # (lab, request) -> response
    description: str = ""
    text: str = ""  # the .srv as its node carried it (app/ros/interface_models.py); '' = made from the models

    @property
    def srv(self) -> str:
        """The .srv text: request `---` response (a node's own text as it wrote it)."""
        if self.text:
            return self.text
        request, response = definition(self.request), definition(self.response)
        return "\n".join(part for part in (request, "---", response) if part)

    def info(self) -> dict:
        return {
            "name": self.name,
            "type": self.type,
            "srv": self.srv,
            "description": self.description,
            "request_fields": fields(self.request),
            "response_fields": fields(self.response),
            "request_schema": self.request.model_json_schema(by_alias=True),
            "response_schema": self.response.model_json_schema(by_alias=True),
        }


class ServiceRegistry:
    def __init__(self, services: Iterable[Service] = ()) -> None:
        self._services: dict[str, Service] = {}
        for service in services:
            self.add(service)

    def add(self, service: Service) -> None:
        if service.name in self._services:
            raise ValueError(f"service {service.name} declared twice")
        self._services[service.name] = service

    def put(self, service: Service) -> None:
        """Replace a service's declaration in its place (a node's own .srv text while it serves it)."""
        self._services[service.name] = service

    def remove(self, name: str) -> Service | None:
        """Take a service away (a node's, when it unadvertises or disconnects)."""
        return self._services.pop(absolute(name), None)

    def __iter__(self):
        return iter(list(self._services.values()))

    def get(self, name: str) -> Service | None:
        return self._services.get(absolute(name))

    def call(self, lab: object, name: str, request: RosMessage) -> RosMessage:
        """Run the service's handler on `lab` (the lab that serves it, handed on as it is; raises ServiceFailure when the call fails, KeyError when
        there is no such service)."""
        service = self.get(name)
        if service is None:
            raise KeyError(absolute(name))
        return service.handler(lab, request)
