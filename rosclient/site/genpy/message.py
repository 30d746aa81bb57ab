"""genpy's message base and its errors: the classes of `from pkg.msg import X` are
interfaces/messages.py's (made from the definitions' text, not generated code)."""

from interfaces.messages import Message


class SerializationError(Exception):
    """A message that cannot be written (a field of the wrong type or range)."""


class DeserializationError(Exception):
    """A message that cannot be read."""


__all__ = ["Message", "SerializationError", "DeserializationError"]
