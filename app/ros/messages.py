"""ROS field types for pydantic messages, and the .msg/.srv text generated from a message model.

A message is a `RosMessage` (strict: a string is not a number, a bool is not an int, unknown
fields are refused) whose fields are annotated with these types, e.g. `a: Int64`.
"""

from dataclasses import dataclass
from typing import Annotated

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, ValidationError

INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1
INT32_MIN, INT32_MAX = -(2**31), 2**31 - 1


@dataclass(frozen=True)
class RosType:
    """The ROS type name of a field (shown in the .srv text), with an optional comment."""

    name: str
    comment: str = ""


def integral(value):
    """JSON has one number type: 3.0 is the integer 3 (as JSON Schema's "integer" says); 3.5, "3"
    and true stay what they are (refused by the strict int)."""
    return int(value) if isinstance(value, float) and value.is_integer() else value


Float64 = Annotated[float, Field(allow_inf_nan=False), RosType("float64")]
# examples: /docs pre-fills them (a JSON number beyond 2^53 loses precision in the browser)
Int64 = Annotated[int, Field(ge=INT64_MIN, le=INT64_MAX, examples=[0]), BeforeValidator(integral), RosType("int64")]
Int32 = Annotated[int, Field(ge=INT32_MIN, le=INT32_MAX), BeforeValidator(integral), RosType("int32")]
Bool = Annotated[bool, RosType("bool")]
String = Annotated[str, Field(max_length=10_000), RosType("string")]
FiniteFloat = Annotated[float, Field(allow_inf_nan=False)]


# arrays; a length range is added where a field is declared: Annotated[Float64Array, Field(min_length=6, max_length=6)]
Float64Array = Annotated[list[FiniteFloat], RosType("float64[]")]
Int32Array = Annotated[
    list[Annotated[int, Field(ge=INT32_MIN, le=INT32_MAX), BeforeValidator(integral)]],
    Field(max_length=10_000),
    RosType("int32[]"),
]
StringArray = Annotated[list[Annotated[str, Field(max_length=10_000)]], Field(max_length=10_000), RosType("string[]")]


class RosMessage(BaseModel):
    model_config = ConfigDict(strict=True, extra="forbid", populate_by_name=True)


def definition(model: type[BaseModel]) -> str:
    """The ROS message definition of a model: one `type name` line per field."""
    lines = []
    for name, field in model.model_fields.items():
        ros = next((m for m in field.metadata if isinstance(m, RosType)), None)
        if ros is None:
            raise TypeError(f"{model.__name__}.{name} has no ROS type")
        lines.append(f"{ros.name} {field.alias or name}" + (f"  # {ros.comment}" if ros.comment else ""))
    return "\n".join(lines)


def example_of(model: type[BaseModel]) -> dict:
    """A request every field of which is accepted: a field's first example, else its default, else
    the zero of its ROS type (an array of zeros of its minimum length). /docs pre-fills it."""
    body = {}
    for name, field in model.model_fields.items():
        key = field.alias or name
        ros = next((m for m in field.metadata if isinstance(m, RosType)), None)
        if field.examples:
            body[key] = field.examples[0]
        elif not field.is_required():
            body[key] = field.get_default(call_default_factory=True)
        elif ros is not None and ros.name.endswith("[]"):
            length = next((m.min_length for m in field.metadata if hasattr(m, "min_length")), 0) or 0
            body[key] = [_ZEROS[ros.name[:-2]]] * length
        else:
            body[key] = _ZEROS[ros.name if ros else "string"]
    return body


_ZEROS = {"float64": 0.0, "int64": 0, "int32": 0, "bool": False, "string": ""}


class Empty(RosMessage):
    """A message with no field (an empty request or goal)."""


class BadArguments(ValueError):
    """Arguments that are not a message of the wanted type; the message names the fields."""


def validation_reason(exc: ValidationError, what: str = "request") -> str:
    """A pydantic ValidationError as one line naming each field: `a: Input should be ...`."""
    return "; ".join(f"{'.'.join(str(x) for x in e['loc']) or what}: {e['msg']}" for e in exc.errors())


def message_from_args(model: type[BaseModel], args, what: str = "request"):
    """The message of `model` from a client's args: an object of its fields, a list of the fields in
    order (rosbridge's positional args), or None (every field at its default). BadArguments names
    each field that is wrong."""
    if isinstance(args, list):
        args = dict(zip([f.alias or n for n, f in model.model_fields.items()], args))
    try:
        return model.model_validate(args if args is not None else {})
    except ValidationError as exc:
        raise BadArguments(validation_reason(exc, what)) from None
