"""The OpenAPI schema as the server behaves: exact int64 bounds and every refusal a route can give.

FastAPI writes the schema through float fields, so 2^63 - 1 becomes 9.223372036854776e18 (= 2^63,
outside int64); the bounds are put back as exact integers. The responses every route shares are
documented on it: 401 (a change without the server's token), 403 (a cross-site request), 413/415
(a body too large or of another type), 404 (a name or goal that does not exist), 409 (an action
busy with another goal, teleop while lifting), 503 (the simulation is restarting)."""

from __future__ import annotations

from fastapi import FastAPI
from fastapi.openapi.utils import get_openapi

from app.ros.messages import INT32_MAX, INT32_MIN, INT64_MAX, INT64_MIN

EXACT = {float(v): v for v in (INT64_MIN, INT32_MIN, INT32_MAX)} | {float(INT64_MAX): INT64_MAX}
# a refusal names its reason: {"detail": ...} (parameters: rclcpp's {"successful": false, "reason": ...})
DETAIL = {"type": "object", "anyOf": [{"required": ["detail"]}, {"required": ["reason"]}]}
MUTATING = ("post", "put", "patch", "delete")


def _refusal(description: str) -> dict:
    return {"description": description, "content": {"application/json": {"schema": DETAIL}}}


SHARED = {
    "403": _refusal("cross-site request refused (foreign Host, Origin or Referer)"),
    "503": _refusal("the simulation is restarting or did not answer in time; call again"),
}
CHANGES = {
    "401": _refusal("this server has a token and the request does not carry it"),
    "413": _refusal("the request body is larger than 1 MiB"),
    "415": _refusal("the request body is not of the endpoint's content type"),
}
NOT_FOUND = {"404": _refusal("no such service, parameter, topic, action or goal")}
BUSY = {"409": {"description": "refused: the action serves another goal / teleop while lifting runs"}}


def exact_bounds(node):
    """Integer schemas get their bounds back as exact integers (int64 included)."""
    if isinstance(node, dict):
        if node.get("type") == "integer":
            for key in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
                value = node.get(key)
                if isinstance(value, float):
                    node[key] = EXACT.get(value, int(value))
        for value in node.values():
            exact_bounds(value)
    elif isinstance(node, list):
        for value in node:
            exact_bounds(value)
    return node


def document(app: FastAPI) -> None:
    """Replace app.openapi with the schema described above (built once)."""

    def openapi() -> dict:
        if app.openapi_schema is None:
            schema = get_openapi(title=app.title, version=app.version, description=app.description, routes=app.routes)
            for path, operations in schema.get("paths", {}).items():
                for method, operation in operations.items():
                    responses = operation.setdefault("responses", {})
                    extra = dict(SHARED)
                    if method in MUTATING:
                        extra |= CHANGES
                    if "{" in path:
                        extra |= NOT_FOUND
                    if path.endswith("/goals") or path == "/teleop/key":
                        extra |= BUSY
                    for status, response in extra.items():
                        responses.setdefault(status, response)
            app.openapi_schema = exact_bounds(schema)
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]  # FastAPI's documented way to change the schema
