"""Pydantic message models from a service's .srv text, for a type the lab does not declare: a
program run by `hri-lab run` carries its own .srv (and the nested .msg texts) in its
advertise_service (docs/reference/rosbridge.md), and the lab checks every request against it as it
checks its own services' (a refusal names the field) and shows the text and fields.

The text is parsed as the program parsed it (interfaces/: one parser); each field
becomes a strict pydantic field of its ROS type: integers in their type's range (3.0 is 3, as
JSON Schema says), finite floats, bools, strings (a bounded string's bound), nested messages,
arrays with their fixed length or bound (uint8/char arrays also as rosbridge's base64 text). A
request must give each of its fields that has no default in the text, as the lab's own services ask;
inside a nested message a field left out takes its ROS default (as `ros2 service call` and
rosbridge_suite fill a message).
"""

from __future__ import annotations

import keyword
from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, Field, create_model

from app.ros.messages import RosMessage, RosType, integral
from interfaces.packages import SEPARATOR, carried
from interfaces.parser import BYTES, FLOATS, INTEGERS, MAX_DEFINITION_CHARS, DefinitionError

MAX_TEXT = MAX_DEFINITION_CHARS  # characters of a carried definition (the parser's cap)
MAX_STRING = 10_000  # characters of an unbounded string field (as the lab's own String)


class BadDefinition(ValueError):
    """A carried definition that cannot be read: the message names the line and what was expected."""


def service_models(type_name: str, text: str) -> tuple[type[RosMessage], type[RosMessage]]:
    """(request, response) models of the service `type_name` ('pkg/Name' or 'pkg/srv/Name') from its
    carried text (`interfaces.packages.full_text`); BadDefinition names what is wrong."""
    if len(text) > MAX_TEXT:
        raise BadDefinition(f"the definition of {type_name} is longer than {MAX_TEXT} characters")
    try:
        interfaces, (package, name) = carried(type_name, "srv", text)
        srv = interfaces.get(package, "srv", name)
    except DefinitionError as exc:
        raise BadDefinition(str(exc)) from None
    made: dict[str, type[RosMessage]] = {}
    return _model(srv._request_class, made), _model(srv._response_class, made)


def own_text(text: str) -> str:
    """The service's own .srv text of a carried definition (the nested messages' left out)."""
    return text.split(SEPARATOR)[0].strip("\n")


def _model(cls: Any, made: dict[str, type[RosMessage]], nested: bool = False) -> type[RosMessage]:
    """The pydantic model of a parsed message class: the request/response itself (a field without a
    default in the text is required), or a nested message (made once; a field left out takes its
    ROS default, as `ros2 service call` and rosbridge_suite fill a message)."""
    if nested and cls._type in made:
        return made[cls._type]
    fields: dict[str, Any] = {}
    for f in cls._fields:
        annotation = _annotation(f, made)
        attr = f.name + "_" if keyword.iskeyword(f.name) or hasattr(BaseModel, f.name) else f.name
        alias: dict[str, Any] = {"alias": f.name} if attr != f.name else {}
        if f.default is not None:
            default = Field(f.default, **alias)
        elif nested:
            default = Field(default_factory=_zero(f, made), **alias)
        else:
            default = Field(..., **alias)
        fields[attr] = (annotation, default)
    model = create_model(cls._type.replace("/", "__"), __base__=RosMessage, **fields)
    if nested:
        made[cls._type] = model
    return model


def _zero(f: Any, made: dict[str, type[RosMessage]]):
    """A factory of a field's ROS default: 0, 0.0, False, '', [], n zeros, a nested message's."""
    if f.array is not None and (f.array is True or f.bound):
        return list
    if f.msg_class is not None:
        model = _model(f.msg_class, made, nested=True)
        return (lambda: [model() for _ in range(f.array)]) if f.array is not None else model
    scalar = f._scalar_zero()
    return (lambda: [scalar] * f.array) if f.array is not None else (lambda: scalar)


def _annotation(f: Any, made: dict[str, type[RosMessage]]) -> Any:
    scalar = _scalar(f, made)
    if f.array is None:
        return Annotated[scalar, RosType(f.type_text)]
    fixed = f.array is not True and not f.bound
    limits = Field(min_length=f.array if fixed else None, max_length=None if f.array is True else f.array)
    items = Annotated[list[scalar], limits]  # type: ignore[valid-type]
    if f.base in BYTES:  # rosbridge sends uint8[]/char[] as base64 text
        return Annotated[items | str, RosType(f.type_text)]
    return Annotated[items, RosType(f.type_text)]


def _scalar(f: Any, made: dict[str, type[RosMessage]]) -> Any:
    if f.msg_class is not None:
        return _model(f.msg_class, made, nested=True)
    base, _, bound = f.base.partition("<=")
    if base in INTEGERS:
        low, high = INTEGERS[base]
        return Annotated[int, Field(ge=low, le=high), BeforeValidator(integral)]
    if base in FLOATS:
        return Annotated[float, Field(allow_inf_nan=False)]
    if base == "bool":
        return bool
    return Annotated[str, Field(max_length=int(bound) if bound else MAX_STRING)]


def fields(model: type[BaseModel]) -> list[dict]:
    """The fields of a message model as a caller sees them: name, ROS type, and the default of one
    that may be left out."""
    out = []
    for name, info in model.model_fields.items():
        ros = next((m for m in info.metadata if isinstance(m, RosType)), None)
        entry: dict[str, Any] = {"name": info.alias or name, "type": ros.name if ros else "json"}
        if not info.is_required():
            entry["default"] = info.get_default(call_default_factory=True)
        out.append(entry)
    return out
