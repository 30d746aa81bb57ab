"""Responses that always encode, and the bounded echo of an input in a refusal."""

import json
import math

from fastapi.responses import JSONResponse


class SafeJSONResponse(JSONResponse):
    """JSON that always encodes: a string that is not valid Unicode (a lone surrogate such as
    "\\ud800", which JSON can carry but UTF-8 cannot) is sent \\u-escaped instead of failing."""

    def render(self, content) -> bytes:
        try:
            return super().render(content)
        except UnicodeEncodeError:
            return json.dumps(content, ensure_ascii=True, allow_nan=False, separators=(",", ":")).encode("ascii")


ECHO_CHARS = 200  # a refusal echoes at most this much of a string
ECHO_ITEMS = 20  # ... and of a list or object


def json_safe(value, depth: int = 0):
    """A refusal's echo of the input: non-finite floats as strings, strings cut to ECHO_CHARS and
    made encodable, containers cut to ECHO_ITEMS and 8 levels, anything else as its (cut) repr."""
    if isinstance(value, float):
        return value if math.isfinite(value) else repr(value)
    if isinstance(value, (int, bool)) or value is None:
        return value
    if isinstance(value, str):
        text = value.encode("utf-8", "backslashreplace").decode("utf-8")
        return text if len(text) <= ECHO_CHARS else f"{text[:ECHO_CHARS]}... ({len(text)} characters)"
    if depth >= 8:
        return "..."
    if isinstance(value, dict):
        items = list(value.items())
        out = {json_safe(str(k)): json_safe(v, depth + 1) for k, v in items[:ECHO_ITEMS]}
        if len(items) > ECHO_ITEMS:
            out["..."] = f"{len(items) - ECHO_ITEMS} more"
        return out
    if isinstance(value, (list, tuple)):
        listed = [json_safe(v, depth + 1) for v in value[:ECHO_ITEMS]]
        return listed + [f"... {len(value) - ECHO_ITEMS} more"] if len(value) > ECHO_ITEMS else listed
    return json_safe(repr(value))


def finite_or_null(value):
    """A message with every non-finite float (a scan's out-of-range +inf, REP 117) as None: JSON has
    no Infinity or NaN, and rosbridge_suite sends them as null too (its PRs #116, #120)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite_or_null(v) for k, v in value.items()}
    if isinstance(value, list):
        return [finite_or_null(v) for v in value]
    return value
