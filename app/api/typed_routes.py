"""Route functions whose signature carries a pydantic body model, built at run time (so FastAPI
validates the body and lists its schema in OpenAPI) — shared by services and actions."""

import inspect
from collections.abc import Callable

from fastapi import Body
from fastapi.openapi.models import Example
from pydantic import BaseModel

from app.ros.messages import example_of


def with_body(
    model: type[BaseModel], handle: Callable[..., object], name: str, **dependencies: object
) -> Callable[..., object]:
    """A route function taking the JSON body as `model` (optional when the model has no field);
    handle(body, **dependencies) with each dependency a typed FastAPI dependency (e.g. lab=LabDep)."""
    has_fields = bool(model.model_fields)

    def endpoint(body: BaseModel | None = None, **resolved: object) -> object:
        return handle(body if body is not None else model(), **resolved)

    examples: dict[str, Example] = {
        "example": {"summary": "an accepted request", "value": example_of(model)}
    }  # what /docs pre-fills
    default = Body(..., openapi_examples=examples) if has_fields else Body(None, openapi_examples=examples)
    annotation = model if has_fields else model | None
    parameters = [inspect.Parameter("body", inspect.Parameter.KEYWORD_ONLY, default=default, annotation=annotation)]
    parameters += [inspect.Parameter(n, inspect.Parameter.KEYWORD_ONLY, annotation=a) for n, a in dependencies.items()]
    endpoint.__signature__ = inspect.Signature(parameters)  # type: ignore[attr-defined]  # what FastAPI reads the parameters from
    endpoint.__name__ = name
    return endpoint
