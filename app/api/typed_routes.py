"""Route functions whose signature carries a pydantic body model, built at run time (so FastAPI
validates the body and lists its schema in OpenAPI) — shared by services and actions."""
import inspect
from typing import Any, Callable

from fastapi import Body
from pydantic import BaseModel


def with_body(model: type[BaseModel], handle: Callable[[BaseModel], Any], name: str) -> Callable:
    """A route function taking the JSON body as `model` (optional when the model has no field)."""
    has_fields = bool(model.model_fields)

    def endpoint(body: BaseModel | None = None):
        return handle(body if body is not None else model())

    default = Body(...) if has_fields else Body(None)
    annotation = model if has_fields else model | None
    endpoint.__signature__ = inspect.Signature(
        [inspect.Parameter("body", inspect.Parameter.KEYWORD_ONLY, default=default, annotation=annotation)]
    )
    endpoint.__name__ = name
    return endpoint
