"""A JSON value's type: what json.loads returns, a rosbridge message's fields, a ROS parameter's
value as it travels (HTTP, rosbridge, a YAML parameter file), a message built from JSON. Not for
FastAPI's bodies: pydantic recurses forever on this alias (they stay `Any`)."""

from typing import TypeAlias

JSON: TypeAlias = dict[str, "JSON"] | list["JSON"] | str | int | float | bool | None
