"""rclpy.logging_service.LoggingService: a node's logger levels served with rcl_interfaces'
`~/get_logger_levels` and `~/set_logger_levels` (a node created with `enable_logger_service=True`),
so another node (or `hri-lab service call`) reads and sets them while the node runs."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from rclpy.impl.logging_severity import LoggingSeverity
from rclpy.logging import get_logger

if TYPE_CHECKING:
    from rclpy.node import Node


class LoggingService:
    def __init__(self, node: Node) -> None:
        from rcl_interfaces.srv import GetLoggerLevels, SetLoggerLevels

        self.services = [
            node.create_service(GetLoggerLevels, "~/get_logger_levels", self.get_logger_levels),
            node.create_service(SetLoggerLevels, "~/set_logger_levels", self.set_logger_levels),
        ]

    def get_logger_levels(self, request: Any, response: Any) -> Any:
        from rcl_interfaces.msg import LoggerLevel

        response.levels = [LoggerLevel(name=name, level=int(get_logger(name).set_to)) for name in request.names]
        return response

    def set_logger_levels(self, request: Any, response: Any) -> Any:
        from rcl_interfaces.msg import SetLoggerLevelsResult

        results = []
        for level in request.levels:
            try:
                get_logger(level.name).set_level(LoggingSeverity(level.level))
                results.append(SetLoggerLevelsResult(successful=True))
            except ValueError:
                results.append(SetLoggerLevelsResult(successful=False, reason="Failed reason: Invalid logger level."))
        response.results = results
        return response
