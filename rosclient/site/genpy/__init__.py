"""genpy (ROS 1's message generator's runtime) as programs import it: `genpy.Message`,
`genpy.Time`, `genpy.Duration`, its errors (rostime.py, message.py)."""

from genpy.message import DeserializationError, Message, SerializationError
from genpy.rostime import Duration, Time, TVal

__all__ = ["Message", "SerializationError", "DeserializationError", "Time", "Duration", "TVal"]
